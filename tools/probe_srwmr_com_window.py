"""HIT-MRII: the CoM window, where the middle axle stands against the body's CoM at each clearance,
for the fitted linkage and for variants of it (kinematics only, level flat ground; no simulation).

    python tools/probe_srwmr_com_window.py --out docs/results/srwmr-com-window

A front lift needs the CoM behind the middle axle at the front CoM shift's clearance, a rear lift
needs it ahead at the rear shift's; com_x slides the curve, the linkage sets its span. The variants
are the ones measured in docs/srwmr.md, "The CoM window": the CoM moved back (com_x -0.080, the
window centred), the sixth session's refit (the middle axle >= 175 mm ahead at 500 mm) and a fit
weighted to the paper's shrink per lift (its tolerance 0.1 -> 0.02). The curve of each stops at the
highest clearance that keeps the front and middle tyres 2 r + 50 mm apart
(``RobotConfig.wheelbase_fm_least``). Writes ``window.csv`` and ``window.png``.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
from pathlib import Path

import numpy as np

from terrabench.systems.srwmr import kinematics as kin
from terrabench.systems.srwmr import legged
from terrabench.systems.srwmr import linkage_fit as fit
from terrabench.systems.srwmr.robot import RobotConfig


def refit_with(**changes: tuple[str, float]) -> RobotConfig:
    """The linkage fit again with some targets' (field, value) replaced; the fitted config."""
    targets = tuple(dataclasses.replace(t, **dict([changes[t.name]])) if t.name in changes else t
                    for t in fit.TARGETS)
    return fit.refit(fit.fitted_robot(), targets)[0]


def tyre_gap_kept(cfg: RobotConfig, clearance: float) -> bool:
    d = kin.delta_for_clearance(cfg, clearance)
    return float(kin.wheelbase_front_middle(cfg, [d, d])[0]) >= cfg.wheelbase_fm_least


def variants() -> dict[str, RobotConfig]:
    base = fit.fitted_robot()
    return {
        "fitted (default)": base,
        "com_x -0.080": dataclasses.replace(base, com_x=-0.0797),
        "refit: middle >= 175 mm ahead at 500 mm": refit_with(middle_ahead_at_500_m=("value", 0.175)),
        "refit: the paper's shrink weighted": refit_with(shrink_per_lift=("tol", 0.02)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, required=True, help="folder for window.csv and window.png")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    rows = []
    curves = {}
    for name, cfg in variants().items():
        top = fit.evaluate(cfg)["clearance_max_m"]
        cls = [c for c in np.arange(0.15, top, 0.001) if tyre_gap_kept(cfg, c)]
        ahead = [kin.middle_ahead_of_com(cfg, c) for c in cls]
        curves[name] = (cls, ahead)
        rows.append({"variant": name, "com_x_m": round(cfg.com_x, 4),
                     "shrink_per_lift": round(fit.evaluate(cfg)["shrink_per_lift"], 3),
                     "highest_clearance_m": round(cls[-1], 3),
                     "ahead_at_150_mm": round(1000 * ahead[0]), "ahead_at_highest_mm": round(1000 * ahead[-1]),
                     "window_mm": round(1000 * (ahead[-1] - ahead[0]))})
        print(f"{name:42s} window {rows[-1]['window_mm']:4d} mm: {rows[-1]['ahead_at_150_mm']:+5d} mm at 150 mm, "
              f"{rows[-1]['ahead_at_highest_mm']:+5d} mm at {1000 * cls[-1]:.0f} mm "
              f"(shrink per lift {rows[-1]['shrink_per_lift']})")
    with open(a.out / "window.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for name, (cls, ahead) in curves.items():
        ax.plot(1000 * np.array(cls), 1000 * np.array(ahead), label=name)
    ax.axhline(0.0, color="k", lw=0.8)
    for pos in ("front", "rear"):
        ax.axvline(1000 * legged.SHIFT[pos], color="grey", ls="--", lw=0.8)
        ax.text(1000 * legged.SHIFT[pos], ax.get_ylim()[1], f" {pos} shift", va="top", fontsize=8, color="grey")
    ax.set_xlabel("clearance (mm)")
    ax.set_ylabel("middle axle ahead of the CoM (mm)")
    ax.set_title("The CoM window: > 0 lets a front wheel lift, < 0 a rear wheel")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out / "window.png", dpi=110)
    print(f"written: {a.out / 'window.csv'}, {a.out / 'window.png'}")


if __name__ == "__main__":
    main()
