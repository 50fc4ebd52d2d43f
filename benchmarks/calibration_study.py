"""Does the simulated chain feel the torques the released benchmark felt?

Runs the eight calibration trials of the released MRS-CWC benchmark (the per-trial logs in
``shared/data/mrs_cwc/released_logs``: CoppeliaSim 4.7 + Bullet 2.78) with one or more
candidate configurations (``--set`` overrides, one candidate per ``--cand``) and prints, per
log, the candidate's figures side by side with the release:

- mean power (W) = E / T and E/D_ef (J/m); E is 0.025 * sum |tau w| over all wheels (the
  release's ``power_sekibun``), ours from the wheel actuator-force sensors;
- the |tau_env| distribution of the CWC law (median, 99th percentile, share of control steps
  above the 20 N m soft latch) and the share of steps with K > 50 N m/rad;
- on every log, the mean XY distance of our leader path from the released one (m, both ways).

Then the same figures against the release's per-group statistics table (medians over all
released logs of a method and group; see the README there).

Usage:
    python benchmarks/calibration_study.py                       # default config only
    python benchmarks/calibration_study.py --cand "drive=stiff" --cand "chain.wheel_drive=constraint"
    python benchmarks/calibration_study.py --cand "" --cand "chain.wheel_kv=1000" --logs B-02_cwc-tdt

A candidate is a ';'-separated list of KEY=VALUE overrides (the CLI's ``--set`` syntax); the
empty string is the default configuration. Success threshold 0.25 m as in the released logs.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

LOG_DIR = Path(os.environ.get("MRS_RELEASED_LOGS", "/work/shared/data/mrs_cwc/released_logs"))
LOGS = ("A-02_cwc-tdt", "A-03_cwc-tdt", "A-03_cs-tdt", "A-03_mj-tdt", "A-03_d-tdt",
        "B-02_cwc-tdt", "B-02_mj-tdt", "B-03_cwc-tdt")
#: The release's per-group statistics (README of the released logs): mean power W, E/D_ef J/m,
#: median |tau_env|, p99 |tau_env|, share |tau_env| > 20, share K > 50 (NaN: not logged).
GROUP_STATS = {
    ("cs-tdt", "A"): (17.6, 263, 0.96, 5.9, 0.000, 0.00),
    ("cs-tdt", "B"): (22.2, 514, 2.01, 13.1, 0.007, 0.00),
    ("cwc-tdt", "A"): (18.1, 270, 1.84, 18.6, 0.001, 0.37),
    ("cwc-tdt", "B"): (20.7, 482, 3.20, 19.9, 0.009, 0.35),
    ("d-tdt", "A"): (9.7, 127, np.nan, np.nan, np.nan, np.nan),
    ("d-tdt", "B"): (19.6, 488, np.nan, np.nan, np.nan, np.nan),
    ("mj-tdt", "A"): (17.3, 255, np.nan, np.nan, np.nan, np.nan),
    ("mj-tdt", "B"): (30.6, 815, np.nan, np.nan, np.nan, np.nan),
}
THRESHOLD = 0.25  # the released non-A* logs stop at 0.25 m


def signature(t, tau_env, k, energy, d_ef, xy):
    """The compared figures of one trial (any source)."""
    tau = np.abs(np.asarray(tau_env, float))
    tau = tau[np.isfinite(tau)]
    k = np.asarray(k, float)
    k = k[np.isfinite(k)]
    T = float(t[-1] - t[0])
    has_tau = tau.size > 0 and np.abs(tau).max() > 0
    return {
        "T": T, "E": float(energy), "P": float(energy) / T if T > 0 else np.nan,
        "EpD": float(energy) / d_ef if d_ef > 0 else np.nan,
        "tau50": float(np.median(tau)) if has_tau else np.nan,
        "tau99": float(np.percentile(tau, 99)) if has_tau else np.nan,
        "tau20": float((tau > 20).mean()) if has_tau else np.nan,
        "K50": float((k > 50).mean()) if (k.size and k.max() > 0) else np.nan,
        "xy": np.asarray(xy, float),
    }


def released(name: str) -> dict:
    import csv

    with open(LOG_DIR / f"{name}.csv") as f:
        rows = list(csv.DictReader(f))
    col = lambda c: np.array([float(r[c]) for r in rows])  # noqa: E731
    t = col("Time")
    d_ef = float(np.hypot(9.0, 9.0) - col("distance_2").min())
    sig = signature(t, col("tau_environment"), col("K_s"), col("power_sekibun")[-1], d_ef,
                    np.c_[col("X"), col("Y")])
    sig["status"] = "succ" if col("distance_2").min() < 0.3 else "fail"
    return sig


def simulate(name: str, sets: list[str], timeout: float) -> dict:
    from terrabench.config import override, parse_overrides
    from terrabench.systems.base import run_task
    from terrabench.systems.mrs_cwc.config import MRSConfig
    from terrabench.systems.mrs_cwc.methods import get_method
    from terrabench.systems.mrs_cwc.task import MRSTask, make_controller
    from terrabench.terrain import dataset

    terrain_id, method_id = name.split("_")
    cfg = override(MRSConfig(), parse_overrides(sets))
    cfg = replace(cfg, protocol=replace(cfg.protocol, timeout=timeout, success_threshold=THRESHOLD))
    method, terrain = get_method(method_id), dataset.get(terrain_id)
    controller = make_controller(method, cfg, terrain)
    rec: list[tuple[float, float]] = []

    def on_step(task, obs, cmd):
        rec.append((cmd.tau_env, np.nan if cmd.yaw_stiffness is None else cmd.yaw_stiffness))

    w0 = time.perf_counter()
    res = run_task(MRSTask(method, terrain, cfg), controller, on_step=on_step)
    a = np.array(rec) if rec else np.zeros((0, 2))
    ts = res.timeseries
    sig = signature(ts["t"], a[:, 0], a[:, 1], res.metrics["energy"], res.metrics["D_ef"], np.c_[ts["x"], ts["y"]])
    sig["status"] = {"success": "succ", "timeout": "time"}.get(res.status, res.status)
    sig["wall"] = time.perf_counter() - w0
    return sig


def path_gap(ours: np.ndarray, ref: np.ndarray) -> float:
    """Mean nearest-point XY distance, averaged both ways (m)."""
    def one(a, b):
        b = b[:: max(1, len(b) // 4000)]
        d = np.empty(len(a))
        for i in range(0, len(a), 512):
            blk = a[i: i + 512]
            d[i: i + 512] = np.sqrt(((blk[:, None, :] - b[None, :, :]) ** 2).sum(-1)).min(1)
        return float(d.mean())
    return 0.5 * (one(ours[::4], ref) + one(ref[::4], ours))


def _fmt(x, spec):
    return "-" if x is None or (isinstance(x, float) and not np.isfinite(x)) else format(x, spec)


def row(label: str, s: dict, gap: float | None = None) -> str:
    return (f"{label:<34} {s['status']:>5} {s['T']:6.0f} {_fmt(s['P'], '6.1f')} {_fmt(s['EpD'], '6.0f')} "
            f"{_fmt(s['tau50'], '6.2f')} {_fmt(s['tau99'], '6.1f')} "
            f"{_fmt(100 * s['tau20'] if np.isfinite(s['tau20']) else np.nan, '6.1f')} "
            f"{_fmt(100 * s['K50'] if np.isfinite(s['K50']) else np.nan, '6.0f')} {_fmt(gap, '6.2f')}")


HEADER = (f"{'log / candidate':<34} {'stat':>5} {'T s':>6} {'P W':>6} {'E/Def':>6} {'|te|50':>6} {'|te|99':>6} "
          f"{'>20 %':>6} {'K>50%':>6} {'path m':>6}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cand", action="append", default=None,
                    help="';'-separated KEY=VALUE overrides of one candidate ('' = default); repeatable")
    ap.add_argument("--logs", default=",".join(LOGS), help="comma-separated released logs to replay")
    ap.add_argument("--timeout", type=float, default=600.0, help="simulated-time limit per trial (s)")
    ap.add_argument("--jobs", type=int, default=1, help="parallel trials (the shared cores: <= 2)")
    args = ap.parse_args()
    if not LOG_DIR.is_dir():
        print(f"released logs not found at {LOG_DIR} (set MRS_RELEASED_LOGS): nothing to compare; skipped")
        return
    cands = args.cand if args.cand is not None else [""]
    logs = [n for n in args.logs.split(",") if n]
    missing = [n for n in logs if not (LOG_DIR / f"{n}.csv").exists()]
    if missing:
        print(f"skipping logs not found in {LOG_DIR}: {', '.join(missing)}")
        logs = [n for n in logs if n not in missing]
    ref = {n: released(n) for n in logs}
    jobs = [(n, [s for s in c.split(";") if s.strip()], args.timeout) for c in cands for n in logs]
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        sims = list(pool.map(simulate, *zip(*jobs)))
    out = {(c, n): s for (c, n), s in zip([(c, n) for c in cands for n in logs], sims)}
    print(HEADER)
    for n in logs:
        print(row(f"{n}  RELEASE", ref[n]))
        for c in cands:
            s = out[(c, n)]
            print(row(f"  {c or 'default'}"[:34], s, path_gap(s["xy"], ref[n]["xy"])))
    print("\nagainst the release's group statistics (median over the calibration runs of a cell):")
    print(HEADER)
    cells = sorted({(n.split("_")[1], n[0]) for n in logs})
    keys = ("P", "EpD", "tau50", "tau99", "tau20", "K50")
    for m, g in cells:
        st = GROUP_STATS.get((m, g))
        if st:
            print(row(f"{m} {g}  RELEASE (group)", {"status": "", "T": np.nan, **dict(zip(keys, st))}))
        for c in cands:
            ss = [out[(c, n)] for n in logs if n.split("_")[1] == m and n[0] == g]
            med = {k: float(np.nanmedian([s[k] for s in ss])) if any(np.isfinite(s[k]) for s in ss) else np.nan
                   for k in keys}
            print(row(f"  {c or 'default'} (n={len(ss)})"[:34], {"status": "", "T": np.nan, **med}))
    print(f"\nwall: {sum(s['wall'] for s in sims):.0f} s of trials", file=sys.stderr)


if __name__ == "__main__":
    main()
