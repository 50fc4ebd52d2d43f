"""Are the trials two stores have in common bitwise identical? (e.g. a Ray run against a local one)

For every key present in both files, compares status, every metric and every time-series
column exactly (NaN equals NaN). Prints one line per differing trial and a summary; exit
status 1 if anything differs or nothing is shared.

Usage: python tools/compare_stores.py results/terrabench.duckdb /tmp/ray.duckdb
       python tools/compare_stores.py before.duckdb after.duckdb --by trial

``--by trial`` pairs rows by (system, method, instance, seed) instead of by key: for comparing
results across a change that re-keys trials (a config field moved or renamed) but must not
change a number.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from terrabench.benchmark.store import ResultsStore


def same_number(a: float, b: float) -> bool:
    return (a != a and b != b) or a == b


def _by(rows: list[dict], ident, path: str) -> dict:
    """Rows by ``ident``; two rows under one identity (a store holding several ``--set`` variants
    of one trial, paired ``--by trial``) would pair arbitrarily, so they stop the comparison."""
    out: dict = {}
    for r in rows:
        k = ident(r)
        if k in out:
            sys.exit(f"{path}: two trials pair as {k} (config hashes {out[k]['config_hash']} and "
                     f"{r['config_hash']}): this store holds several variants of one trial; compare "
                     "--by key, or stores holding one variant each")
        out[k] = r
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--by", choices=("key", "trial"), default="key",
                    help="pair rows by store key (default) or by (system, method, instance, seed)")
    ap.add_argument("--ignore", default="", help="comma-separated metric names not compared "
                    "(e.g. wall-clock timings a store kept as metrics)")
    args = ap.parse_args()
    ignored = {m for m in args.ignore.split(",") if m}
    ident = ((lambda r: r["key"]) if args.by == "key"
             else (lambda r: (r["system"], r["method"], r["instance"], r["seed"])))
    with ResultsStore(args.a, read_only=True) as sa, ResultsStore(args.b, read_only=True) as sb:
        ra, rb = _by(sa.rows(), ident, args.a), _by(sb.rows(), ident, args.b)
        shared = sorted(set(ra) & set(rb), key=str)
        differing = 0
        for key in shared:
            x, y = ra[key], rb[key]
            why = []
            if x["status"] != y["status"]:
                why.append(f"status {x['status']} vs {y['status']}")
            for name in sorted((set(x["metrics"]) | set(y["metrics"])) - ignored):
                if not same_number(x["metrics"].get(name, np.nan), y["metrics"].get(name, np.nan)):
                    why.append(f"metric {name}")
            ta, tb = sa.timeseries(x["key"]), sb.timeseries(y["key"])
            if list(ta) != list(tb):
                why.append("series columns")
            else:
                why += [f"series {n}" for n in ta if not np.array_equal(ta[n], tb[n], equal_nan=True)]
            if why:
                differing += 1
                print(f"{x['method']} {x['instance']} seed {x['seed']}: " + ", ".join(why))
        skipped = f"; not compared: {', '.join(sorted(ignored))}" if ignored else ""
        print(f"{len(shared)} shared trials, {differing} differ "
              f"(metrics, status and every series value compared exactly{skipped})")
    sys.exit(1 if differing or not shared else 0)


if __name__ == "__main__":
    main()
