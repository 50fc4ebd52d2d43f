"""MuJoCo's ccd_tolerance: 1e-4 (ours) against its default 1e-6, side by side in one run.

For each terrain of the perf sample, the MRS-CWC + TDT trial loop is run cut at ``--seconds``
with each tolerance, interleaved (a, b, a, b ...) so that machine load hits both alike; the
figure is the time inside ``mj_step`` per physics step (the two runs follow slightly different
trajectories, so whole-trial times are compared per step), and the ratio 1e-6 / 1e-4.

Usage: python benchmarks/ccd_study.py [--terrains B-05,B-15] [--seconds 30] [--repeats 2]
"""

from __future__ import annotations

import argparse

import numpy as np

from terrabench.config import override
from terrabench.sim.episode import run_episode
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import get_method
from terrabench.systems.mrs_cwc.task import MRSTask, make_controller
from terrabench.terrain import dataset


def engine_us_per_step(terrain_id: str, ccd: float, seconds: float, method: str) -> tuple[float, str]:
    cfg = override(MRSConfig(), {"physics.ccd_tolerance": ccd, "protocol.timeout": seconds})
    m, t = get_method(method), dataset.get(terrain_id)
    log = run_episode(MRSTask(m, t, cfg), make_controller(m, cfg, t))
    return 1e6 * log.timing["engine"] / log.timing["physics_steps"], log.status


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--terrains", default="B-05,B-15,B-25,B-35,B-45")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--method", default="cwc-tdt")
    args = ap.parse_args()
    print(f"{'terrain':8} {'us/step 1e-4':>13} {'us/step 1e-6':>13} {'1e-6 / 1e-4':>12}")
    ratios = []
    for tid in args.terrains.split(","):
        a, b = [], []
        for _ in range(args.repeats):
            a.append(engine_us_per_step(tid, 1e-4, args.seconds, args.method)[0])
            b.append(engine_us_per_step(tid, 1e-6, args.seconds, args.method)[0])
        ra, rb = min(a), min(b)  # the least-disturbed repeat
        ratios.append(rb / ra)
        print(f"{tid:8} {ra:13.1f} {rb:13.1f} {rb / ra:12.2f}")
    print(f"{'mean':8} {'':13} {'':13} {np.mean(ratios):12.2f}")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
