"""HIT-MRII: how much each wheel's soil drawbar pull changes from one control period to the next
over a window of one trial (the soil force's chatter), with its load, slip and footing state.

    python tools/probe_srwmr_chatter.py swlm t12-lift100 73 79
    python tools/probe_srwmr_chatter.py swlm t12-lift100 73 79 --set physics.timestep=0.0005

The figures behind docs/srwmr.md's "The physics step and the middle wheels' load" (seed 0). A wheel
whose pull flips sign in most periods and changes by hundreds of newtons a period is past the
explicit step's stability bound for its load (docs/assumptions-srwmr.md, "Physics step").
"""

from __future__ import annotations

import argparse

import numpy as np

from terrabench.config import parse_overrides
from terrabench.sim.episode import run_episode
from terrabench.systems.srwmr.scenarios import SYSTEM


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("method", choices=SYSTEM.default_methods())
    ap.add_argument("instance")
    ap.add_argument("t0", type=float, help="window start (s)")
    ap.add_argument("t1", type=float, help="window end (s): the trial stops there")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a config override")
    a = ap.parse_args()
    over = {**parse_overrides(a.set), "protocol.timeout": a.t1}
    spec = SYSTEM.plan(methods=[a.method], instances=[a.instance], overrides=over)[0]
    _, task, ctl = SYSTEM.trial_parts(spec)
    rows: list[np.ndarray] = []

    def on_step(task, obs, cmd) -> None:
        if task.data.time >= a.t0:
            tr = task.soil_wheels.truth
            rows.append(np.concatenate((tr["DP"], tr["W"], tr["slip"])))

    run_episode(task, ctl, on_step=on_step)
    r = np.array(rows)
    dp, w, s = r[:, 0:6], r[:, 6:12], r[:, 12:18]
    d = np.diff(dp, axis=0)
    step = task.physics.timestep * 1000
    print(f"{a.method} {a.instance} seed 0, {a.t0:g}-{a.t1:g} s, {len(r)} control periods, physics step {step:g} ms")
    print("wheel  load N  slip   DP mean  |dDP| a period: median  p99   sign flips")
    for j in range(6):
        flips = float(np.mean(np.sign(d[1:, j]) != np.sign(d[:-1, j])))
        print(f"c{j + 1}    {w[:, j].mean():6.0f}  {np.median(s[:, j]):+.2f}  {dp[:, j].mean():7.1f}"
              f"  {np.median(np.abs(d[:, j])):20.1f}  {np.percentile(np.abs(d[:, j]), 99):5.0f}   {flips:.2f}")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
