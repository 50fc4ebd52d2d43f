"""HIT-MRII electrical input power per actuator group (drive, steer, rocker hinges) and per plan
step of one trial (mean W over the step's control periods), with the body's mean forward speed.

    python tools/probe_srwmr_power.py rclm t10-heights
    python tools/probe_srwmr_power.py wrm t8-speeds

The figures behind docs/srwmr.md's reading of T10's held power against the paper's (the motor
model of `motors.HIT_MRII`, the same as the stored `energy_elec_kJ`; seed 0).
"""

from __future__ import annotations

import argparse
import collections

import numpy as np

from terrabench.sim.episode import run_episode
from terrabench.systems.srwmr.motors import HIT_MRII
from terrabench.systems.srwmr.scenarios import SYSTEM


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("method", choices=SYSTEM.default_methods())
    ap.add_argument("instance")
    a = ap.parse_args()
    spec = SYSTEM.plan(methods=[a.method], instances=[a.instance], seeds=1)[0]
    _, task, ctl = SYSTEM.trial_parts(spec)
    power: dict[int, dict[str, float]] = collections.defaultdict(lambda: collections.defaultdict(float))
    ticks: collections.Counter[int] = collections.Counter()
    vx: dict[int, float] = collections.defaultdict(float)

    def on_step(task, obs, cmd) -> None:
        k = getattr(cmd, "step", np.nan)
        k = -1 if k != k else int(k)  # -1: no plan step
        f, v = task._act_force, task._act_vel
        for g, ids in task._groups.items():
            i = np.asarray(ids)
            power[k][g] += float(HIT_MRII.power({g: f[i]}, {g: v[i]})[g].sum())
        ticks[k] += 1
        vx[k] += float(task.data.qvel[0])

    log = run_episode(task, ctl, on_step=on_step)
    print(f"{a.method} {a.instance} seed 0: {log.status} at {log.sim_time:.0f} s")
    for k in sorted(ticks):
        parts = {g: w / ticks[k] for g, w in power[k].items()}
        print(f"  step {k:2d}: {ticks[k] * task.timing.control_period:6.1f} s  "
              + "  ".join(f"{g} {w:5.1f} W" for g, w in parts.items())
              + f"  total {sum(parts.values()):5.1f} W  body vx {1000 * vx[k] / ticks[k]:5.1f} mm/s")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
