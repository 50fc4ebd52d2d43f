"""Per-part CPU time of one episode: the task's observe / check / row / apply / power, the
controller call and mj_step, in us per control tick (each part's fastest of ``--repeats``
passes; the wrappers add ~1 us a part, "rest" is the shared loop and the wrappers).

    python tools/time_parts.py octopus --method clm --instance step-400 --seconds 20

The figures behind docs/performance.md's per-part tables; perf (`terrabench perf`) gives the
loop/raw ratio the issue asks for, this says where the loop's Python goes.
"""

from __future__ import annotations

import argparse
import time

import mujoco

from terrabench.catalog import system as get_system
from terrabench.sim.episode import run_episode

PARTS = ("observe", "check", "row", "apply", "power")


def one_pass(system, spec) -> tuple[dict[str, float], int]:
    acc = {p: 0.0 for p in (*PARTS, "controller", "mj_step")}
    clock = time.process_time
    _, task, ctrl = system.trial_parts(spec)
    for name in PARTS:
        fn = getattr(task, name)

        def wrapped(*a, _fn=fn, _name=name):
            t0 = clock()
            r = _fn(*a)
            acc[_name] += clock() - t0
            return r
        setattr(task, name, wrapped)

    def timed_ctrl(obs):
        t0 = clock()
        r = ctrl(obs)
        acc["controller"] += clock() - t0
        return r
    step = mujoco.mj_step

    def timed_step(*a):
        t0 = clock()
        step(*a)
        acc["mj_step"] += clock() - t0
    mujoco.mj_step = timed_step
    try:
        t0 = clock()
        log = run_episode(task, timed_ctrl)
        acc["loop"] = clock() - t0
    finally:
        mujoco.mj_step = step
    return acc, log.steps


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("system")
    ap.add_argument("--method")
    ap.add_argument("--instance", required=True)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    system = get_system(a.system)
    overrides = {system.timeout_key: a.seconds} if system.timeout_key else {}
    spec = system.plan(methods=[a.method or system.default_methods()[0]], instances=[a.instance], seeds=1,
                       overrides=overrides)[0]
    best: dict[str, float] = {}
    for _ in range(a.repeats):
        acc, ticks = one_pass(system, spec)
        for k, v in acc.items():
            best[k] = min(best.get(k, float("inf")), v)
    us = {k: 1e6 * v / ticks for k, v in best.items()}
    rest = us["loop"] - sum(v for k, v in us.items() if k != "loop")
    outside = us["loop"] - us["mj_step"] - us["apply"]
    print(f"{a.system} {spec.method} {a.instance}: {ticks} ticks, us per tick (fastest of {a.repeats})")
    for k in ("loop", "mj_step", "controller", *PARTS):
        print(f"  {k:10s} {us[k]:7.1f}  ({100 * us[k] / us['loop']:4.1f} %)")
    print(f"  {'rest':10s} {rest:7.1f}")
    print(f"  Python outside mj_step and apply (what raw does not run): {outside:.1f}; "
          f"loop/raw if the wrappers cost nothing ~ {(us['mj_step'] + us['apply']) / us['loop']:.2f}")


if __name__ == "__main__":
    main()
