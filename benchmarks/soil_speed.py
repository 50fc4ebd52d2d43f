"""Cost per physics step: six soil wheels (SoilWheels hook) vs the same rover on rigid contact.

    PYTHONPATH=src nice python benchmarks/soil_speed.py [--steps 3000] [--repeats 5] [--no-footing]

Both grounds (plane, heightfield) in one run. For each ground the rigid rover and the soil rover
(every = 1, 2, 5, 10: forces held over k substeps) are timed alternately, ``repeats`` rounds of
``steps`` physics steps each, in CPU time (``time.process_time``); the fastest round of each
counts (the least disturbed by other load on a shared machine). Prints microseconds per step,
the ratio to rigid, the cost of the hook call alone, and the forward speed / mean slip / sinkage
reached. The soil tables and the
compiled kernel are built before timing (the kernel is cached on disk by numba).
"""

from __future__ import annotations

import argparse
import time

import mujoco
import numpy as np

from terrabench.soil.mujoco_soil import SoilWheels, flat_ground, hfield_ground
from terrabench.soil.presets import HIT_MRII_WHEEL, MARS_SOFT
from terrabench.soil.rover import build_rover, wheel_name
from terrabench.soil.table import SoilTable

EVERY = (1, 2, 5, 10)


def _rover(hfield: bool):
    hf = None
    if hfield:
        x = np.linspace(-5, 15, 201)
        y = np.linspace(-5, 5, 101)
        X, Y = np.meshgrid(x, y, indexing="ij")
        hf = (0.03 * np.sin(0.7 * X) * np.cos(0.5 * Y), x, y)
    m = build_rover(HIT_MRII_WHEEL, hfield=hf).compile()
    return m, mujoco.MjData(m)


class Case:
    def __init__(self, every: int | None, hfield: bool, table: SoilTable, footing: bool = True):
        self.every = every
        self.m, self.d = _rover(hfield)
        self.hook = None
        if every is not None:
            ground = hfield_ground(self.m, "ground") if hfield else flat_ground()
            self.hook = SoilWheels(self.m, self.d, [wheel_name(i) for i in range(6)], HIT_MRII_WHEEL, table, ground,
                                   every=every, footing=footing)
        self.d.ctrl[:] = 2.0
        self.step(1000)  # settle and get moving
        self.best = np.inf

    def step(self, n: int) -> None:
        m, d, hook = self.m, self.d, self.hook
        if hook is None:
            for _ in range(n):
                mujoco.mj_step(m, d)
            return
        before = hook.before_substep
        for _ in range(n):
            before(m, d)
            mujoco.mj_step(m, d)

    def time(self, n: int) -> None:
        t0 = time.process_time()
        self.step(n)
        self.best = min(self.best, (time.process_time() - t0) / n * 1e6)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--no-footing", action="store_true", help="SoilWheels(footing=False): the static footing off")
    args = ap.parse_args()
    table = SoilTable(MARS_SOFT, HIT_MRII_WHEEL)
    print(f"six wheels, {args.steps} steps x {args.repeats} alternating rounds, fastest round, CPU us per physics step")
    print("| ground | rigid | " + " | ".join(f"soil every={k}" for k in EVERY) + " |")
    print("|---|---|" + "---|" * len(EVERY))
    details = []
    for hfield in (False, True):
        cases = [Case(None, hfield, table)] + [Case(k, hfield, table, not args.no_footing) for k in EVERY]
        for _ in range(args.repeats):
            for c in cases:
                c.time(args.steps)
        rigid = cases[0].best
        cells = [f"{c.best:.1f} ({c.best / rigid:.2f}x)" for c in cases[1:]]
        name = "hfield" if hfield else "plane"
        print(f"| {name} | {rigid:.1f} | " + " | ".join(cells) + " |")
        for c in cases[1:]:
            t = c.hook.truth
            details.append(f"{name} every={c.every}: v={c.d.qvel[0]:.3f} m/s slip={np.mean(t['slip']):.3f} "
                           f"sinkage={np.mean(t['sinkage']) * 1e3:.1f} mm")
    print("\n".join(details))
    for hfield in (False, True):
        c = Case(1, hfield, table, not args.no_footing)
        hook, m, d = c.hook, c.m, c.d
        best = np.inf
        for _ in range(args.repeats):
            t0 = time.process_time()
            for _ in range(args.steps):
                hook.before_substep(m, d)
            best = min(best, (time.process_time() - t0) / args.steps * 1e6)
        print(f"{'hfield' if hfield else 'plane'}: the soil hook alone (six wheels, every=1) {best:.2f} us per call")


if __name__ == "__main__":
    main()
