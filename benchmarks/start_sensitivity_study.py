"""How far does one OCTOPUS trial's metric depend on its start? The seeds' jitter, scaled down.

A seed > 0 shifts the start sideways by up to ``scene.jitter_offset`` and turns it by up to
``scene.jitter_yaw_deg``, drawn from the seed's own generator: the same draws at any scale. Run
the same seeds with both scaled by each ``--scales`` factor (1 = the default seeds) and read the
spread of a per-trial metric over the seeds at each scale. Where a micrometre start already gives
the whole spread of the default seeds, the metric of one trial is decided by which side of a
thresholded event (a landing, a release) the trial falls, not by the start's place; a change is
then read by the share of trials in each outcome group, not by a 5-seed median (docs/octopus.md,
"How much a seed's terrace margin says").

Every scale's trials go into one store (the resolved config is part of a trial's key), so an
interrupted study resumes where it stopped. Writes ``start_sensitivity.csv`` (one row per scale
and task: the metric's median, min, max, standard deviation and the share below ``--low``) and
``start_sensitivity.png`` (each trial's value against the scale) into ``--out``.

Usage: python benchmarks/start_sensitivity_study.py [--terrains terrace2-front,terrace2-side,step-400]
       [--seeds 20] [--scales 1e-6,1e-5,1e-4,1e-3,1e-2,1e-1,1] [--metric margin_min_m] [--low 0.03]
       [--store start_sensitivity.duckdb] [--out .] [--workers 2]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
from pathlib import Path

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.catalog import system as get_system
from terrabench.systems.octopus.config import SceneConfig

OFFSET, YAW = "scene.jitter_offset", "scene.jitter_yaw_deg"


def scaled_jitter(scale: float) -> dict[str, float]:
    """The two jitter fields at ``scale`` times their declared defaults."""
    if not (math.isfinite(scale) and scale > 0):
        raise ValueError(f"--scales: each factor must be a positive finite number, got {scale!r}")
    base = SceneConfig()
    return {OFFSET: base.jitter_offset * scale, YAW: base.jitter_yaw_deg * scale}


def summarise(values: list[float], low: float) -> dict[str, float]:
    """Median, range, population standard deviation and the share of values below ``low``."""
    return {"n": len(values), "median": statistics.median(values), "min": min(values), "max": max(values),
            "sd": statistics.pstdev(values), "share_low": sum(v < low for v in values) / len(values)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--method", default="clm")
    ap.add_argument("--terrains", default="terrace2-front,terrace2-side,step-400")
    ap.add_argument("--seeds", type=int, default=20, help="seeds 1..N (seed 0 has no jitter)")
    ap.add_argument("--scales", default="1e-6,1e-5,1e-4,1e-3,1e-2,1e-1,1")
    ap.add_argument("--metric", default="margin_min_m")
    ap.add_argument("--low", type=float, default=0.03, help="the share of trials below this is reported")
    ap.add_argument("--store", default="start_sensitivity.duckdb")
    ap.add_argument("--out", default=".")
    ap.add_argument("--workers", type=int, default=None)
    a = ap.parse_args()
    if a.seeds < 2:
        raise SystemExit(f"--seeds must be >= 2 (seed 0 has no jitter and is left out), got {a.seeds}")
    octopus = get_system("octopus")
    scales = [float(s) for s in a.scales.split(",")]
    plans = {s: [spec for spec in octopus.plan(methods=[a.method], instances=a.terrains.split(","),
                                               seeds=a.seeds + 1, overrides=scaled_jitter(s))
                 if spec.seed > 0] for s in scales}  # every argument checked before any trial runs
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    tasks = a.terrains.split(",")
    with ResultsStore(a.store) as store:
        for s, specs in plans.items():
            print(f"scale {s:g}: {run_trials(specs, store, workers=a.workers)}")
        rows = store.query("select instance, config, metrics from trials where system = 'octopus' "
                           "and method = ? and seed > 0", [a.method])
    scale_of = {round(scaled_jitter(s)[OFFSET], 15): s for s in scales}
    values: dict[tuple[float, str], list[float]] = {}
    for inst, cfg, met in rows:
        s = scale_of.get(round(json.loads(cfg)["scene"]["jitter_offset"], 15))
        v = json.loads(met).get(a.metric)
        if s is not None and v is not None and inst in tasks:
            values.setdefault((s, inst), []).append(float(v))
    if not values:
        raise SystemExit(f"no stored trial has the metric {a.metric!r}")
    table = [{"scale": s, "offset_m": scaled_jitter(s)[OFFSET], "yaw_deg": scaled_jitter(s)[YAW], "task": inst,
              **summarise(v, a.low)} for (s, inst), v in sorted(values.items())]
    with open(out / "start_sensitivity.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    for r in table:
        print(f"{r['task']:15s} x{r['scale']:<6g} {a.metric} median {r['median']:+.3f} [{r['min']:+.3f}, "
              f"{r['max']:+.3f}] sd {r['sd']:.3f}  below {a.low:g}: {r['share_low']:.2f} (n={r['n']})")
    _plot(values, a.metric, out / "start_sensitivity.png")


def _plot(values: dict[tuple[float, str], list[float]], metric: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tasks = sorted({t for _, t in values})
    fig, axes = plt.subplots(1, len(tasks), figsize=(4 * len(tasks), 3.4), sharey=True, squeeze=False)
    for ax, task in zip(axes[0], tasks):
        for (s, t), v in sorted(values.items()):
            if t == task:
                ax.plot([s] * len(v), v, "o", ms=4, alpha=0.6, color="C0")
        ax.set_xscale("log")
        ax.set_title(task)
        ax.set_xlabel("jitter scale (1 = the seeds' 3 cm, 3 deg)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(f"{metric} per trial")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
