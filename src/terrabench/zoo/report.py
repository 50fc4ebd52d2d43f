"""The mobility map's table and page: per robot method and family, the severities crossed."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

#: per-trial columns of the page's table
TRIAL_COLUMNS = ("method", "family", "severity", "seed", "status", "success", "progress", "speed", "energy_per_m_kg",
                 "max_pitch", "max_roll", "sim_time", "wall_time")


def trial_lines(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One dict per stored trial (sorted by method, family, severity, seed)."""
    from terrabench.zoo.families import FAMILIES, parse_instance

    out = []
    for r in rows:
        fam_id, _, tok = r["instance"].partition("@")
        try:
            f, tok = parse_instance(r["instance"])
            sev = f.value(tok)
        except ValueError:
            sev = float("nan")
        m = r.get("metrics") or {}
        out.append({"method": r["method"], "family": fam_id, "token": tok, "severity": sev, "seed": r["seed"],
                    "status": r["status"], "wall_time": r.get("wall_time"),
                    **{k: m.get(k) for k in TRIAL_COLUMNS if k in m}})
    order = {f: i for i, f in enumerate(FAMILIES)}
    out.sort(key=lambda d: (d["method"], order.get(d["family"], 99), d["severity"] if math.isfinite(d["severity"])
                            else 0.0, d["seed"]))
    return out


def map_lines(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per (method, family): trials, successes, the largest severity crossed and the first failure."""
    by: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for ln in trial_lines(rows):
        by.setdefault((ln["method"], ln["family"]), []).append(ln)
    out = []
    for (m, f), lines in by.items():
        ok = [ln for ln in lines if ln["status"] == "success"]
        bad = [ln for ln in lines if ln["status"] != "success"]
        out.append({"method": m, "family": f, "trials": len(lines), "success": len(ok),
                    "max_crossed": max((ln["token"] for ln in ok), key=lambda t: _val(f, t), default=""),
                    "first_failure": (f"{bad[0]['status']} at {bad[0]['token']}" if bad else "")})
    return out


def _val(family: str, token: str) -> float:
    from terrabench.zoo.families import family as get

    try:
        return get(family).value(token)
    except ValueError:
        return float("nan")


def summary_table(rows: list[dict[str, Any]]):
    from rich.table import Table

    t = Table(title="zoo: the mobility map (successes / trials, largest severity crossed, first failure)")
    cols = ("method", "family", "success", "trials", "max_crossed", "first_failure")
    for c in cols:
        t.add_column(c)
    for ln in map_lines(rows):
        t.add_row(*(str(ln[c]) for c in cols))
    return t


def map_figure(lines: list[dict[str, Any]]):
    """A method x family grid coloured by the share of stored trials that succeeded."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from terrabench.zoo.families import FAMILIES

    methods = sorted({ln["method"] for ln in lines})
    fams = [f for f in FAMILIES if any(ln["family"] == f for ln in lines)]
    grid = np.full((len(methods), len(fams)), np.nan)
    for ln in lines:
        grid[methods.index(ln["method"]), fams.index(ln["family"])] = ln["success"] / max(ln["trials"], 1)
    fig, ax = plt.subplots(figsize=(1.0 + 0.7 * len(fams), 1.0 + 0.45 * len(methods)))
    im = ax.imshow(np.ma.masked_invalid(grid), cmap="RdYlGn", vmin=0, vmax=1, aspect="auto")
    ax.set_xticks(range(len(fams)), fams, rotation=60, ha="right")
    ax.set_yticks(range(len(methods)), methods)
    fig.colorbar(im, ax=ax, label="share crossed")
    return fig


def write_report(store, out_dir: Path, system: Any = None) -> Path:
    """``index.html``: the map (per method and family) and every trial, one section per settings
    group (:func:`terrabench.report.variants.settings_groups`: trials made with different ``--set``
    values are never mixed in one map); CSVs beside it, suffixed with the group's slug."""
    from terrabench.catalog import system as get_system
    from terrabench.report.page import Page
    from terrabench.report.variants import Defaults, settings_groups

    system = system if system is not None else get_system("zoo")
    rows = store.rows(system="zoo")
    page = Page(out_dir, "terrabench zoo: the mobility map")
    page.p(f"{len(rows)} stored trials. A row per robot method and terrain family: successes, the largest "
           "severity crossed, the first failure (status at severity).")
    groups = settings_groups(rows, Defaults(system))
    for g in groups:
        grows, slug = list(g.rows), g.slug
        if len(groups) > 1:
            page.h2(f"Settings: {g.label} ({len(grows)} trials)")
        lines = map_lines(grows)
        page.table(lines, ("method", "family", "success", "trials", "max_crossed", "first_failure"),
                   csv_name=f"map{slug}.csv")
        if lines:
            page.figure(map_figure(lines), f"map{slug}.png", "Share of the stored severities crossed per method "
                        "and family (blank: not run or unsupported).")
        page.h3("Trials")
        page.table(trial_lines(grows), TRIAL_COLUMNS, csv_name=f"trials{slug}.csv")
    return page.finish()
