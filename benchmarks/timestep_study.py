"""Does the physics step change MRS-CWC outcomes? Compare a sample of terrains at several steps.

Usage: python benchmarks/timestep_study.py [--steps 0.0025,0.005,0.01] [--terrains ...] [--method cwc-tdt]
Results go to the store (default results/timestep_study.duckdb); the table is printed.
"""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console
from rich.table import Table

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.systems.mrs_cwc.scenarios import SYSTEM

DEFAULT_TERRAINS = "A-03,A-17,A-31,A-45,B-04,B-18,B-32,B-46"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", default="0.0025,0.005")
    ap.add_argument("--terrains", default=DEFAULT_TERRAINS)
    ap.add_argument("--method", default="cwc-tdt")
    ap.add_argument("--store", default="results/terrabench.duckdb")
    ap.add_argument("--workers", type=int, default=None)
    args = ap.parse_args()
    steps = [float(s) for s in args.steps.split(",")]
    terrains = args.terrains.split(",")
    specs = {dt: SYSTEM.plan(methods=[args.method], instances=terrains, overrides={"physics.timestep": dt})
             for dt in steps}
    with ResultsStore(args.store) as st:
        run_trials([s for v in specs.values() for s in v], st, workers=args.workers)
        res = {dt: {r["instance"]: r for r in st.rows(keys=[s.key for s in v])} for dt, v in specs.items()}
    t = Table(title=f"{args.method}: outcome per terrain and physics step (status, NCR %, NEF, NEC J/m, wall s)")
    t.add_column("terrain")
    for dt in steps:
        t.add_column(f"dt={dt * 1000:g} ms")
    for tid in terrains:
        cells = []
        for dt in steps:
            r = res[dt][tid]
            m = r["metrics"]
            cells.append(f"{r['status'][:4]} {100 * m['NCR']:.0f} {m['NEF']:.2f} {m['NEC']:.0f} "
                         f"({r['wall_time']:.0f}s)")
        t.add_row(tid, *cells)
    for dt in steps:
        rows = list(res[dt].values())
        sr = np.mean([r["status"] == "success" for r in rows])
        ncr = np.mean([r["metrics"]["NCR"] for r in rows])
        nef = np.nanmean([r["metrics"]["NEF"] for r in rows])
        wall = sum(r["wall_time"] for r in rows)
        sim = sum(r["metrics"]["sim_time"] for r in rows)
        t.caption = (t.caption or "") + (f"\ndt={dt * 1000:g} ms: success {100 * sr:.0f} %, "
                                         f"mean NCR {100 * ncr:.1f} %, mean NEF {nef:.3f}, RTF {sim / wall:.0f}")
    Console(width=160).print(t)


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
