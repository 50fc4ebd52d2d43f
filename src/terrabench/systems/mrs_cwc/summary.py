"""Group figures of stored MRS-CWC rows (NSR, NCR, NEF, NEC per method and group) and the CLI table."""

from __future__ import annotations

from typing import Any

from terrabench.metrics.navigation import group_summary
from terrabench.systems.mrs_cwc.methods import METHODS
from terrabench.systems.mrs_cwc.reference import METRIC_NAMES, paper_row


def group_rows(rows: list[dict[str, Any]]) -> dict[tuple[str, str], list[dict[str, Any]]]:
    """(method, group) -> rows; the group is the terrain id's letter."""
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        out.setdefault((r["method"], r["instance"][0]), []).append(r)
    return out


def summaries(rows: list[dict[str, Any]]) -> dict[tuple[str, str], dict[str, float]]:
    """(method, group) -> :func:`group_summary` of its trials (status decides success)."""
    out = {}
    for key, rs in group_rows(rows).items():
        trials = []
        for r in rs:
            m = dict(r["metrics"])
            m["success"] = 1.0 if r["status"] == "success" else 0.0
            trials.append(m)
        s = group_summary(trials)
        s["diverged"] = sum(1 for r in rs if r["status"] == "diverged")
        s["errors"] = sum(1 for r in rs if r["status"] == "error")
        s["wall_time"] = sum(r["wall_time"] for r in rs)
        out[key] = s
    return out


def summary_table(rows: list[dict[str, Any]]):
    """A rich table: per (group, method) our NSR/NCR/NEF/NEC, the paper's in brackets."""
    from rich.table import Table

    table = Table(title="MRS-CWC benchmark: ours (paper, Tables II/III)")
    for col in ("grp", "method", "n", "NSR %", "95% CI", "NCR %", "NEF", "NEC J/m", "div"):
        table.add_column(col, justify="left" if col in ("grp", "method") else "right")
    order = {m: i for i, m in enumerate(METHODS)}
    for (mid, group), s in sorted(summaries(rows).items(), key=lambda kv: (kv[0][1], order.get(kv[0][0], 99))):
        paper = paper_row(group, mid) or {}
        cells = [f"{_fmt(n, s[n])} ({_fmt(n, paper.get(n, float('nan')))})" for n in METRIC_NAMES]
        ci = f"{s['NSR_lo']:.0f}-{s['NSR_hi']:.0f}"
        label = METHODS[mid].label if mid in METHODS else mid
        table.add_row(group, label, str(s["n"]), cells[0], ci, *cells[1:], str(s["diverged"]))
    return table


def _fmt(name: str, v: float) -> str:
    if v != v:
        return "-"
    return f"{v:.3f}" if name == "NEF" else f"{v:.1f}"


def seed_summary(rows: list[dict[str, Any]], *, draws: int = 2000) -> dict[tuple[str, str], dict[str, float]]:
    """(method, group) -> NSR over seeds, its CI, and how often outcomes flip between seeds.

    The benchmark is chaotic (a few cm of start offset flips hard terrains), so one trial per
    terrain is a noisy draw. Per (method, group), on the terrains run with every seed seen for
    that pair: ``NSR`` = success share over all (terrain, seed) trials (%); ``NSR_lo`` /
    ``NSR_hi`` = 95 % percentile bootstrap over terrains (a terrain keeps all its seeds: seeds
    of one terrain are not independent); ``flip_share`` = share of terrains whose outcome
    (success or not) differs between seeds (%); ``n_terrains``, ``n_seeds``. Deterministic
    (fixed bootstrap seed).
    """
    import numpy as np

    out = {}
    for key, rs in group_rows(rows).items():
        seeds = sorted({int(r["seed"]) for r in rs})
        by_terrain: dict[str, dict[int, float]] = {}
        for r in rs:
            by_terrain.setdefault(r["instance"], {})[int(r["seed"])] = 1.0 if r["status"] == "success" else 0.0
        full = sorted(t for t, d in by_terrain.items() if len(d) == len(seeds))
        if not full:
            continue
        s = np.array([[by_terrain[t][k] for k in seeds] for t in full])  # (terrains, seeds)
        per_terrain = s.mean(axis=1)
        rng = np.random.default_rng(0)
        boot = per_terrain[rng.integers(0, len(full), size=(draws, len(full)))].mean(axis=1)
        out[key] = {"NSR": 100 * float(per_terrain.mean()), "NSR_lo": 100 * float(np.percentile(boot, 2.5)),
                    "NSR_hi": 100 * float(np.percentile(boot, 97.5)),
                    "flip_share": 100 * float(np.mean(s.min(axis=1) != s.max(axis=1))),
                    "n_terrains": float(len(full)), "n_seeds": float(len(seeds))}
    return out
