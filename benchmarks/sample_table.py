"""NSR (with a 95 % Wilson interval), NCR and NEF per method from one or more result stores.

Usage: python benchmarks/sample_table.py /tmp/fid_base.duckdb /tmp/fid_cand.duckdb
"""

from __future__ import annotations

import json
import math
import sys

import duckdb


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    if n == 0:
        return math.nan, math.nan
    p = k / n
    den = 1 + z * z / n
    c = (p + z * z / (2 * n)) / den
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return c - h, c + h


def main() -> None:
    print(f"{'store':28} {'method':8} {'n':>3} {'NSR %':>6} {'95 % CI':>10} {'NCR %':>6} {'NEF':>6}  statuses")
    for path in sys.argv[1:]:
        con = duckdb.connect(path, read_only=True)
        rows = con.execute("select method, status, metrics from trials order by method, instance").fetchall()
        by: dict[str, list] = {}
        for m, st, met in rows:
            by.setdefault(m, []).append((st, json.loads(met)))
        for m, trials in by.items():
            n = len(trials)
            k = sum(1 for st, _ in trials if st == "success")
            lo, hi = wilson(k, n)
            ncr = sum(x["NCR"] for _, x in trials) / n
            nef = sum(x["NEF"] for _, x in trials if x["NEF"] == x["NEF"]) / n
            sts: dict[str, int] = {}
            for st, _ in trials:
                sts[st] = sts.get(st, 0) + 1
            print(f"{path[-28:]:28} {m:8} {n:3d} {100 * k / n:6.0f} {100 * lo:4.0f}-{100 * hi:<4.0f} "
                  f"{100 * ncr:6.1f} {nef:6.3f}  {sts}")


if __name__ == "__main__":
    main()
