"""How far does HIT-MRII's creeping mode (RCM) climb against the rolling wheels' rim speed?

RCM is an inchworm: in the lift the front pair stands still while the middle and rear pairs roll
in, in the lowering the front pair rolls out while the others stand. The rolling wheels' rim
speed is ``supervisor.rcm_rim_ratio`` times the chassis's lift speed (default: the paper's own
command, 7.0 mm/s per 3.6 mm/s [S Task 4]; 0: the linkage's kinematic speed only). This study
runs the same RCM trials at several ratios and reads how far each gets, its body slip in the RCM
step and the front pair's drawbar pull in the lowering phases (the phase in which the ratio
acts), to tell a traction deficit from a plan or geometry limit (docs/srwmr.md, "T11's stall
against the rolling set's rim speed"). It is a diagnostic: the default ratio is not chosen here.

Every ratio's trials go into one store (the resolved config is part of a trial's key), so an
interrupted study resumes where it stopped. Writes ``rcm_rim.csv`` (one row per task and ratio)
and ``rcm_rim.png`` (the body's x against time per ratio) into ``--out``.

Usage: python benchmarks/rcm_rim_study.py [--terrains t11-slope15,t4-sinkage]
       [--ratios 0,default,2.5,3,3.5] [--timeout 1600] [--window 300:400]
       [--store rcm_rim.duckdb] [--out .] [--workers 2]
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.catalog import system as get_system
from terrabench.systems.srwmr.config import SupervisorConfig
from terrabench.systems.srwmr.control import MODE_CODE

RATIO = "supervisor.rcm_rim_ratio"
DEFAULT = SupervisorConfig().rcm_rim_ratio  # the paper's 7.0 / 3.6, where it is declared
FRONT = ("DP_c1", "DP_c2")  # the front pair's drawbar pull series (N)


def lowering_front_pull(ts: dict[str, np.ndarray], window: tuple[float, float]) -> float:
    """Mean drawbar pull (N) of the front pair over the stored rows of ``window`` (s) in which the
    hinges open (the lowering: the front pair rolls, the others stand); nan when there are none."""
    t = ts["t"]
    opening = np.gradient(ts["delta_L"], t) < -1e-4
    rows = opening & (t >= window[0]) & (t < window[1])
    if not rows.any():
        return float("nan")
    return float(np.mean([ts[k][rows].mean() for k in FRONT]))


def rcm_step_slip(metrics: dict, ts: dict[str, np.ndarray]) -> float:
    """Body slip of the plan step in which RCM first runs (T4's first, T11's second: the step the
    supervisor inserts when WRM stalls), read from the stored ``mode`` and ``step`` series; nan
    when RCM never ran."""
    rcm = np.flatnonzero(ts["mode"] == MODE_CODE["RCM"])
    if not rcm.size:
        return float("nan")
    v = metrics.get(f"step{int(ts['step'][rcm[0]])}_slip")
    return float("nan") if v is None else float(v)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--terrains", default="t11-slope15,t4-sinkage")
    ap.add_argument("--ratios", default="0,default,2.5,3,3.5", help="'default': the config's own (the paper's)")
    ap.add_argument("--timeout", type=float, default=1600.0, help="simulated seconds per trial")
    ap.add_argument("--window", default="300:400", help="START:END (s) for the lowering phases' front pull")
    ap.add_argument("--store", default="rcm_rim.duckdb")
    ap.add_argument("--out", default=".")
    ap.add_argument("--workers", type=int, default=None)
    a = ap.parse_args()
    try:
        ratios = [DEFAULT if r.strip() == "default" else float(r) for r in a.ratios.split(",")]
        window = tuple(float(v) for v in a.window.split(":"))
    except ValueError as e:
        raise SystemExit(f"--ratios takes numbers separated by commas, --window START:END: {e}") from None
    if len(window) != 2 or not window[0] < window[1]:
        raise SystemExit(f"--window must be START:END with START < END, got {a.window!r}")
    if not a.timeout > 0:
        raise SystemExit(f"--timeout must be > 0 simulated seconds, got {a.timeout}")
    srwmr = get_system("srwmr")
    tasks = a.terrains.split(",")
    # every argument (the ratio's range, the instances) checked before any trial runs
    plans = {r: srwmr.plan(methods=["rcm"], instances=tasks, seeds=1,
                           overrides={RATIO: r, srwmr.timeout_key: a.timeout}) for r in ratios}
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    table, curves = [], {}
    with ResultsStore(a.store) as store:
        for r, specs in plans.items():
            print(f"ratio {r:g}: {run_trials(specs, store, workers=a.workers)}")
        for r, specs in plans.items():
            for row in store.rows(keys=[s.key for s in specs]):
                m, ts = row["metrics"], store.timeseries(row["key"])
                curves[(row["instance"], r)] = (ts["t"], ts["x"])
                at = {f"x at {T:g} s m": round(float(np.interp(T, ts["t"], ts["x"])), 3)
                      for T in (200, 400, 800, a.timeout) if T <= ts["t"][-1]}
                table.append({"task": row["instance"], "rim ratio": r, "status": row["status"],
                              "sim time s": round(m["sim_time"], 1), "progress m": round(m["progress"], 3),
                              "RCM step body slip": round(rcm_step_slip(m, ts), 3),
                              f"front pull, lowering {a.window} s, N": round(lowering_front_pull(ts, window), 1),
                              "elec kJ": round(m["energy_elec_kJ"], 1), **at})
    cols = list(dict.fromkeys(k for row in table for k in row))
    with open(out / "rcm_rim.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(table)
    for row in table:
        print("  ".join(f"{k}={v}" for k, v in row.items()))
    _plot(curves, out / "rcm_rim.png")


def _plot(curves: dict[tuple[str, float], tuple[np.ndarray, np.ndarray]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tasks = sorted({t for t, _ in curves})
    fig, axes = plt.subplots(1, len(tasks), figsize=(5 * len(tasks), 3.6), squeeze=False)
    for ax, task in zip(axes[0], tasks):
        for (t, r), (time, x) in sorted(curves.items()):
            if t == task:
                tag = " (the paper's, default)" if r == DEFAULT else ""
                ax.plot(time, x, lw=1.2, label=f"rim ratio {r:.3g}{tag}")
        ax.set_title(f"{task}, RCM")
        ax.set_xlabel("simulated time s")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0][0].set_ylabel("body x m")
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
