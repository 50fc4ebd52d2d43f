"""How often does the chain roll over in the first minutes, and was it stiffening just before?

For each terrain, run a method for ``--horizon`` seconds in the benchmark's loop and record
the first time the chain is on its side (mean over the units of the body z-axis's vertical
component below ``--side``), the yaw stiffness then and 2 s before, and the largest yaw-joint
bend in those 2 s. It answers: do our CWC failures in group B start with a roll-over, and does
the stiffness rise while interior joints are bent (the spring energy 0.5 K q^2 is released)?

Usage: python benchmarks/rollover_study.py [--method cwc-tdt] [--group B] [--horizon 120]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np
from rich.console import Console

from terrabench.config import override, parse_overrides
from terrabench.systems.mrs_cwc import task as trial
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import get_method
from terrabench.terrain import dataset


def first_rollover(terrain_id: str, method_id: str, cfg: MRSConfig, horizon: float, side: float) -> dict:
    """The benchmark loop for ``horizon`` seconds; the first time the chain is on its side."""
    cfg = replace(cfg, protocol=replace(cfg.protocol, timeout=horizon))
    period = cfg.protocol.control_period
    window = int(round(2.0 / period))
    k_hist: list[float] = []
    q_hist: list[np.ndarray] = []
    found: dict = {"t": float("nan")}

    def sample(scene, obs, cmd) -> None:
        k_hist.append(cmd.yaw_stiffness if cmd.yaw_stiffness is not None else float("nan"))
        q_hist.append(obs.joint_yaw.copy())
        up = float(np.mean(scene.data.xmat[scene.unit_bodies, 8]))
        if found["t"] != found["t"] and obs.t > 5.0 and up < side:  # after the drop has settled
            back = max(0, len(k_hist) - 1 - window)
            found.update(t=obs.t, K_then=k_hist[-1], K_2s_before=k_hist[back],
                         max_bend=float(np.max(np.abs(q_hist[back:]))) if q_hist[0].size else float("nan"))

    trial.run(get_method(method_id), dataset.get(terrain_id), cfg, on_step=sample)
    return found


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--method", default="cwc-tdt")
    ap.add_argument("--group", default="B")
    ap.add_argument("--horizon", type=float, default=120.0)
    ap.add_argument("--side", type=float, default=0.3, help="mean unit 'up' below this = on its side")
    ap.add_argument("--set", dest="sets", action="append", default=[])
    args = ap.parse_args()
    cfg = override(MRSConfig(), parse_overrides(args.sets))
    con = Console()
    rolled, stiffening = 0, 0
    terrains = dataset.select(None, args.group)
    for t in terrains:
        r = first_rollover(t.id, args.method, cfg, args.horizon, args.side)
        if r["t"] == r["t"]:
            rolled += 1
            rising = r["K_then"] > r["K_2s_before"] + 5
            stiffening += rising
            con.print(f"{t.id}: on its side at {r['t']:.1f} s; K {r['K_2s_before']:.0f} -> {r['K_then']:.0f} "
                      f"over the 2 s before; largest yaw bend {np.degrees(r['max_bend']):.0f} deg")
        else:
            con.print(f"{t.id}: upright for {args.horizon:.0f} s")
    con.print(f"[bold]{args.method}, group {args.group}: {rolled}/{len(terrains)} roll over within "
              f"{args.horizon:.0f} s (after the first 5 s); {stiffening} of them while K was rising by > 5")


if __name__ == "__main__":
    main()
