"""A store's seed-0 MRS-CWC trials against a written report's ``outcomes.csv``, trial by trial.

For checking that a re-run reproduces a published report (e.g. ``docs/results/mrs-cwc``) when
the report's store is not at hand: status must match exactly, simulated time to 1 us and NCR
to the 4 decimals the CSV keeps (the CSV is written rounded). Study variants in the CSV (labels naming
``eq12`` or the planner) are left out unless ``--all-variants``.

Usage: python tools/compare_outcomes.py STORE [--csv docs/results/mrs-cwc/outcomes.csv]
Exit code 1 if any compared trial differs.
"""

from __future__ import annotations

import argparse
import csv
import json

import duckdb


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("store")
    ap.add_argument("--csv", default="docs/results/mrs-cwc/outcomes.csv")
    ap.add_argument("--all-variants", action="store_true", help="also the study variants")
    a = ap.parse_args()
    old = {}
    with open(a.csv, newline="") as f:
        for r in csv.DictReader(f):
            if not a.all_variants and ("eq12" in r["label"] or "planner" in r["label"]):
                continue
            old[(r["method"], r["terrain"])] = r
    con = duckdb.connect(a.store, read_only=True)
    rows = con.execute("select method, instance, status, metrics from trials "
                       "where system = 'mrs-cwc' and seed = 0").fetchall()
    same, bad = 0, []
    for method, inst, status, met in rows:
        o = old.get((method, inst))
        if o is None:
            continue
        m = json.loads(met)
        if (o["status"] == status and abs(float(o["NCR_pct"]) - 100 * m["NCR"]) < 6e-5
                and abs(float(o["sim_time"]) - m["sim_time"]) < 1e-6):
            same += 1
        else:
            bad.append((method, inst, o["status"], status, o["NCR_pct"], 100 * m["NCR"], o["sim_time"], m["sim_time"]))
    print(f"{len(old)} report rows, {len(rows)} stored seed-0 rows; compared {same + len(bad)}: "
          f"{same} equal, {len(bad)} differ (status exactly, sim_time to 1 us, NCR to 4 decimals)")
    for b in bad[:20]:
        print("  differs:", *b)
    raise SystemExit(1 if bad else 0)


if __name__ == "__main__":
    main()
