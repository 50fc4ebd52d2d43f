"""NSR (with a 95 % Wilson interval), NCR and NEF per method from one or more result stores.

Usage: python benchmarks/sample_table.py /tmp/fid_base.duckdb /tmp/fid_cand.duckdb [--instances B-01..B-16]
"""

from __future__ import annotations

import json
import math

import duckdb


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    if n == 0:
        return math.nan, math.nan
    p = k / n
    den = 1 + z * z / n
    c = (p + z * z / (2 * n)) / den
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return c - h, c + h


def _instances(spec: str | None) -> set[str] | None:
    if not spec:
        return None
    if ".." in spec:
        a, b = spec.split("..")
        g = a.split("-")[0]
        return {f"{g}-{i:02d}" for i in range(int(a.split("-")[1]), int(b.split("-")[1]) + 1)}
    return set(spec.split(","))


def main() -> None:
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("stores", nargs="+")
    ap.add_argument("--instances", default=None, help="comma list or range, e.g. B-01..B-16")
    ap.add_argument("--seeds", default=None, help="comma list of seeds to keep (default: all)")
    args = ap.parse_args()
    keep = _instances(args.instances)
    print(f"{'store':28} {'method':8} {'n':>3} {'NSR %':>6} {'95 % CI':>10} {'NCR %':>6} {'NEF':>6}  statuses")
    for path in args.stores:
        con = duckdb.connect(path, read_only=True)
        rows = con.execute("select method, instance, seed, status, metrics from trials "
                           "order by method, instance, seed, finished_at").fetchall()
        seeds = None if args.seeds is None else {int(x) for x in args.seeds.split(",")}
        latest: dict[tuple, tuple] = {}  # a trial stored under two config versions: the newest
        for m, inst, seed, st, met in rows:
            if (keep is None or inst in keep) and (seeds is None or seed in seeds):
                latest[(m, inst, seed)] = (st, json.loads(met))
        by: dict[str, list] = {}
        for (m, _, _), v in sorted(latest.items()):
            by.setdefault(m, []).append(v)
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
