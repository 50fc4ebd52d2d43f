"""Cost per physics step: six soil wheels (SoilWheels hook) vs the same rover on rigid contact.

    PYTHONPATH=src nice python benchmarks/soil_speed.py [--steps 3000] [--hfield]

Prints microseconds per step (median of 3 repeats) for rigid contact and for SoilWheels
with every = 1, 2, 5, 10, 20 (forces held over k substeps), the ratio to rigid, and the
forward speed / mean slip / sinkage reached (to show held forces stay stable).
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


def _rover(hfield: bool):
    hf = None
    if hfield:
        x = np.linspace(-5, 15, 201)
        y = np.linspace(-5, 5, 101)
        X, Y = np.meshgrid(x, y, indexing="ij")
        hf = (0.03 * np.sin(0.7 * X) * np.cos(0.5 * Y), x, y)
    m = build_rover(HIT_MRII_WHEEL, hfield=hf).compile()
    return m, mujoco.MjData(m)


def run(steps: int, every: int | None, hfield: bool, table: SoilTable) -> tuple[float, float, float, float]:
    m, d = _rover(hfield)
    hook = None
    if every is not None:
        ground = hfield_ground(m, "ground") if hfield else flat_ground()
        hook = SoilWheels(m, d, [wheel_name(i) for i in range(6)], HIT_MRII_WHEEL, table, ground, every=every)
    d.ctrl[:] = 2.0
    for _ in range(1000):  # settle and get moving
        if hook:
            hook.before_substep(m, d)
        mujoco.mj_step(m, d)
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        if hook:
            for _ in range(steps):
                hook.before_substep(m, d)
                mujoco.mj_step(m, d)
        else:
            for _ in range(steps):
                mujoco.mj_step(m, d)
        times.append((time.perf_counter() - t0) / steps * 1e6)
    slip = float(np.mean(hook.truth["slip"])) if hook else float("nan")
    sink = float(np.mean(hook.truth["sinkage"])) if hook else float("nan")
    return float(np.median(times)), float(d.qvel[0]), slip, sink


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--hfield", action="store_true")
    args = ap.parse_args()
    table = SoilTable(MARS_SOFT, HIT_MRII_WHEEL)
    rigid, v, _, _ = run(args.steps, None, args.hfield, table)
    print(f"ground={'hfield' if args.hfield else 'plane'} steps={args.steps}")
    print(f"rigid           {rigid:7.1f} us/step  1.00x  v={v:.3f} m/s")
    for k in (1, 2, 5, 10, 20):
        t, v, s, z = run(args.steps, k, args.hfield, table)
        print(f"soil every={k:<3d} {t:7.1f} us/step  {t / rigid:4.2f}x  v={v:.3f} m/s  slip={s:.3f}  sinkage={z * 1e3:.1f} mm")


if __name__ == "__main__":
    main()
