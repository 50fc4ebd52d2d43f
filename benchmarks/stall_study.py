"""What the opt-in stall stop (``protocol.stall_time``) would have saved and changed, per store.

Replays every stored MRS-CWC trial's leader series through the same rule the episode applies
(:class:`terrabench.sim.stall.StallWatch`, via :func:`~terrabench.sim.stall.first_stall`, whose
agreement with the episode is tested) at the same instants (the slow checks, every
``protocol.divergence_check_period``; the stored series holds every one of them), for each
stall time asked for. Exact for the stop instant and the status; for NCR the series is
thinned (every ``log_period``), so a d_min that improved between stored samples is bounded,
and the table says "exact" only where the thinned minimum before the stop equals the trial's.

``--verify N`` re-runs up to N of the predicted stops with the stop switched on and checks
that each ends ``stuck`` at the predicted instant (the first N in key order, longest stall
time first).

Usage: python benchmarks/stall_study.py STORE [--times 60,120,240] [--verify 6] [--seeds 0]
"""

from __future__ import annotations

import argparse
import json
import math
from dataclasses import dataclass

import duckdb

from terrabench.sim.stall import first_stall


@dataclass
class Outcome:
    key: str
    scenario: str
    method: str
    instance: str
    seed: int
    status: str
    sim_time: float
    stop_t: float | None  # when the stall stop would fire (s), None if never
    ncr: float
    ncr_at_stop: float | None  # bound from the thinned series (>= the exact value's d_min)
    config: dict


def _protocol(cfg: dict):
    """The stored protocol section, missing fields (older stores) at their defaults."""
    from terrabench import catalog

    return catalog.system("mrs-cwc").load_config(cfg).protocol


def replay(series: dict[str, list[float]], cfg: dict, status: str, stall_time: float) -> float | None:
    """The instant (s) the stall stop fires on this stored trial, or None."""
    pr = _protocol(cfg)
    # the last row is the stop: success / fell are checked before the stall rule, the time
    # limit after it
    return first_stall(series["t"], series["x"], series["y"], pr.target_xy, period=pr.control_period,
                       check_period=pr.divergence_check_period, stall_time=stall_time,
                       distance=pr.stall_distance, check_last=status == "timeout")


def study(path: str, times: list[float], seeds: set[int] | None = None) -> dict[float, list[Outcome]]:
    con = duckdb.connect(path, read_only=True)
    rows = con.execute("select key, scenario, method, instance, seed, status, metrics, config from trials "
                       "where system = 'mrs-cwc' order by key").fetchall()
    rows = [r for r in rows if seeds is None or r[4] in seeds]
    out: dict[float, list[Outcome]] = {s: [] for s in times}
    for key, scen, method, inst, seed, status, met, conf in rows:
        m, cfg = json.loads(met), json.loads(conf)
        ser = {name: vals for name, vals in con.execute(
            "select name, values from series where key = ? order by position", [key]).fetchall()}
        if not ser:
            continue
        pr = _protocol(cfg)
        tx, ty = pr.target_xy
        L0, thr = m["L0"], pr.success_threshold
        for s in times:
            stop = replay(ser, cfg, status, s)
            ncr_stop = None
            if stop is not None:
                n = sum(1 for t in ser["t"] if t <= stop + 1e-9)
                d = min(math.hypot(tx - x, ty - y) for x, y in zip(ser["x"][:n], ser["y"][:n]))
                d = 0.0 if d < thr else d
                ncr_stop = (L0 - d) / L0
            out[s].append(Outcome(key, scen, method, inst, seed, status, m["sim_time"], stop, m["NCR"], ncr_stop, cfg))
    return out


def summarise(out: dict[float, list[Outcome]]) -> None:
    print(f"{'stall_time':>10} {'trials':>6} {'stopped':>7} {'of them success':>15} {'sim saved h':>11} "
          f"{'saved %':>7} {'NCR exact':>9} {'NCR loss > 1 pt':>15} {'max NCR loss':>12}")
    for s, rows in out.items():
        stopped = [r for r in rows if r.stop_t is not None and r.stop_t < r.sim_time - 1e-9]
        at_end = [r for r in rows if r.stop_t is not None and r.stop_t >= r.sim_time - 1e-9]
        total = sum(r.sim_time for r in rows)
        saved = sum(r.sim_time - r.stop_t for r in stopped)
        lost = [r.ncr - r.ncr_at_stop for r in stopped]
        exact = sum(1 for x in lost if abs(x) < 1e-12)
        succ = sum(1 for r in stopped if r.status == "success")
        print(f"{s:10g} {len(rows):6d} {len(stopped):7d} {succ:15d} {saved / 3600:11.2f} "
              f"{100 * saved / total:7.1f} {exact:4d}/{len(stopped):<4d} {sum(1 for x in lost if x > 0.01):15d} "
              f"{max(lost, default=0.0):12.4f}"
              + (f"   (+{len(at_end)} stalled at the time limit: stuck instead of timeout)" if at_end else ""))
        by: dict[str, list] = {}
        for r in stopped:
            by.setdefault(r.method, []).append(r)
        for meth in sorted(by):
            rs = by[meth]
            print(f"{'':10} {meth:>14}: {len(rs)} stopped, statuses "
                  f"{ {st: sum(1 for r in rs if r.status == st) for st in sorted({r.status for r in rs})} }, "
                  f"saved {sum(r.sim_time - r.stop_t for r in rs) / 3600:.2f} h")


def verify(out: dict[float, list[Outcome]], n: int) -> int:
    """Re-run up to n predicted stops with the stop on; returns the number that disagree."""
    from terrabench import catalog
    from terrabench.benchmark.trial import TrialSpec

    system = catalog.system("mrs-cwc")
    bad = 0
    picked = []
    for s in sorted(out, reverse=True):
        for r in out[s]:
            if r.stop_t is not None and r.stop_t < r.sim_time and len(picked) < n \
                    and r.key not in {p[1].key for p in picked}:
                picked.append((s, r))
    for s, r in picked:
        conf = json.loads(json.dumps(r.config))
        conf["protocol"]["stall_time"] = s
        spec = TrialSpec(system="mrs-cwc", scenario=r.scenario, method=r.method,
                         instance=r.instance, seed=r.seed, config=conf)
        res = system.run_trial(spec)
        ok = res.status == "stuck" and abs(res.metrics["sim_time"] - r.stop_t) < 1e-6
        bad += not ok
        print(f"verify {r.method} {r.instance} seed {r.seed} stall {s:g}: predicted stuck at {r.stop_t:.3f} s, "
              f"ran {res.status} at {res.metrics['sim_time']:.3f} s, NCR {res.metrics['NCR']:.4f} "
              f"(stored {r.ncr:.4f}, bound {r.ncr_at_stop:.4f}) {'ok' if ok else 'MISMATCH'}")
    return bad


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("store")
    ap.add_argument("--times", default="60,120,240", help="stall times to replay (s), comma-separated")
    ap.add_argument("--verify", type=int, default=0, help="re-run this many predicted stops")
    ap.add_argument("--seeds", default=None, help="only these seeds, comma-separated (default: all)")
    a = ap.parse_args()
    times = [float(x) for x in a.times.split(",")]
    out = study(a.store, times, None if a.seeds is None else {int(x) for x in a.seeds.split(",")})
    summarise(out)
    if a.verify:
        raise SystemExit(1 if verify(out, a.verify) else 0)


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
