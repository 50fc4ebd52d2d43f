"""Why does the CWC soft latch rarely fire in MuJoCo? Decompose tau_env on a few terrains.

The released law (spec section 4) computes ``tau_env = I*alpha + tau_m - tau_spring`` from
the leader's wheel torques and the first link's yaw, and latches "soft" when |tau_env| > 20
N m. This script runs MRS-CWC + TDT with a recorder on the law and prints, per terrain, the
percentiles of each term, how often the latch and the stiff state are on, and how the
steering torque tau_m compares with the friction limit of the leader's wheels.

Usage: python benchmarks/cwc_torque_study.py [--terrains B-04,B-18] [--timeout 300]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np
from rich.console import Console
from rich.table import Table

from terrabench.systems.base import run_task
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import get_method
from terrabench.systems.mrs_cwc.task import MRSTask, make_controller
from terrabench.terrain import dataset


def record(terrain_id: str, cfg: MRSConfig, method_id: str = "cwc-tdt") -> dict[str, np.ndarray]:
    """Run one trial and return the law's inputs and terms at every control period."""
    rows: list[tuple[float, ...]] = []
    state = {"k": None, "rate": None}
    method, terrain = get_method(method_id), dataset.get(terrain_id)
    controller = make_controller(method, cfg, terrain)
    period = cfg.protocol.control_period

    def sample(task, obs, cmd) -> None:
        law = controller.body.law
        c = law.cfg
        rate, (tau_l, tau_r) = float(obs.yaw_rate[0]), obs.wheel_torque[0]
        alpha = 0.0 if state["rate"] is None else (rate - state["rate"]) / period
        k_prev = c.k_init if state["k"] is None else state["k"]  # the K the law just used
        rows.append((c.inertia * alpha, c.motor_gain * (tau_r - tau_l), k_prev * float(obs.joint_yaw[0]),
                     law.tau_env, law.k, float(law.soft), law.memory))
        state["k"], state["rate"] = law.k, rate

    result = run_task(MRSTask(method, terrain, cfg), controller, on_step=sample)
    status, metrics = result.status, result.metrics
    a = np.array(rows)
    names = ("I_alpha", "tau_m", "K_q", "tau_env", "K", "soft", "memory")
    out = {n: a[:, i] for i, n in enumerate(names)}
    out["status"], out["NCR"] = status, metrics["NCR"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--terrains", default="B-04,B-11,B-18,B-25,B-32")
    ap.add_argument("--timeout", type=float, default=300.0)
    ap.add_argument("--set", dest="sets", action="append", default=[], help="config override KEY=VALUE")
    args = ap.parse_args()
    from terrabench.config import override, parse_overrides

    cfg = override(MRSConfig(), parse_overrides(args.sets))
    cfg = replace(cfg, protocol=replace(cfg.protocol, timeout=args.timeout))
    t = Table(title="MRS-CWC + TDT: terms of tau_env (N m), 50th / 99th percentile of |term|")
    for col in ("terrain", "status", "NCR %", "|I alpha|", "|tau_m|", "|K q|", "|tau_env|",
                "latch on %", "K>50 %", "corr(tau_m, Kq)"):
        t.add_column(col)
    for tid in args.terrains.split(","):
        r = record(tid, cfg)

        def pct(x):
            return f"{np.percentile(np.abs(x), 50):.2f} / {np.percentile(np.abs(x), 99):.1f}"

        corr = np.corrcoef(r["tau_m"], r["K_q"])[0, 1]
        t.add_row(tid, r["status"], f"{100 * r['NCR']:.0f}", pct(r["I_alpha"]), pct(r["tau_m"]), pct(r["K_q"]),
                  pct(r["tau_env"]), f"{100 * r['soft'].mean():.1f}", f"{100 * (r['K'] > 50).mean():.0f}",
                  f"{corr:+.2f}")
    Console().print(t)


if __name__ == "__main__":
    main()
