"""The mobility map's table and page: per robot method and family, the severities crossed."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

#: per-trial columns of the page's table
TRIAL_COLUMNS = ("method", "family", "severity", "seed", "status", "success", "progress", "speed", "energy_per_m",
                 "energy_per_m_kg", "max_pitch", "max_roll", "sim_time", "wall_time")
#: a severity counts as crossed when at least this share of its starts (seeds) succeeded: a reading of
#: stored trials, so the report's, not a trial's config (the config's unread `protocol.success_share`
#: copy of it was removed 2026-12-08)
CROSSED_SHARE = 0.8
#: contrasts shown as clips: the hardest severities one robot crosses and another fails
CONTRASTS = 3
#: the contrast clips: at most this many simulated seconds each, played this many times real time
CLIP_SECONDS, CLIP_SPEEDUP = 60.0, 8.0


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


def point_lines(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per (method, family, severity): starts (seeds), successes, their share, and the means over
    the successful starts of speed (m/s), energy per metre (J/m) and per metre and kg (J/(m kg))."""
    by: dict[tuple[str, str, str], list[dict[str, Any]]] = {}
    for ln in trial_lines(rows):
        by.setdefault((ln["method"], ln["family"], ln["token"]), []).append(ln)
    out = []
    for (m, f, tok), lines in by.items():
        ok = [ln for ln in lines if ln["status"] == "success"]
        out.append({"method": m, "family": f, "token": tok, "severity": lines[0]["severity"], "starts": len(lines),
                    "success": len(ok), "share": len(ok) / len(lines),
                    **{k: _mean(ln.get(k) for ln in ok) for k in ("speed", "energy_per_m", "energy_per_m_kg")},
                    "statuses": ", ".join(sorted({ln["status"] for ln in lines}))})
    return out


def _mean(values) -> float:
    v = [float(x) for x in values if x is not None and math.isfinite(float(x))]
    return sum(v) / len(v) if v else float("nan")


def map_lines(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per (method, family): trials, successes, the largest severity crossed in at least
    :data:`CROSSED_SHARE` of its starts (and in the robot's own size), and the first failure."""
    points: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for pt in point_lines(rows):
        points.setdefault((pt["method"], pt["family"]), []).append(pt)
    firsts: dict[tuple[str, str], str] = {}
    for ln in trial_lines(rows):
        if ln["status"] != "success":
            firsts.setdefault((ln["method"], ln["family"]), f"{ln['status']} at {ln['token']}")
    out = []
    for (m, f), pts in points.items():
        crossed = [p for p in pts if p["share"] >= CROSSED_SHARE - 1e-9]
        best = max(crossed, key=lambda p: _val(f, p["token"]), default=None)
        out.append({"method": m, "family": f, "trials": sum(p["starts"] for p in pts),
                    "success": sum(p["success"] for p in pts), "max_crossed": best["token"] if best else "",
                    "max_crossed_robot_units": relative_text(m, f, best["severity"]) if best else "",
                    "first_failure": firsts.get((m, f), "")})
    return out


def relative_text(method: str, family_id: str, value: float) -> str:
    """``value`` of ``family_id`` in the robot's own size (the family's relative scales), e.g.
    ``"3.3 wheel radii, 0.9 body heights"``; '' for families without one."""
    fp = _footprint(method)
    if fp is None or not math.isfinite(value):
        return ""
    from terrabench.zoo.families import family as get

    return ", ".join(f"{fn(value, fp):.2g} {label}" for label, fn in get(family_id).relative)


def _footprint(method: str):
    from terrabench.zoo.adapter import split_method

    try:
        return split_method(method)[0].footprint()
    except ValueError:
        return None


def _val(family: str, token: str) -> float:
    from terrabench.zoo.families import family as get

    try:
        return get(family).value(token)
    except ValueError:
        return float("nan")


MAP_COLUMNS = ("method", "family", "success", "trials", "max_crossed", "max_crossed_robot_units", "first_failure")


def summary_table(rows: list[dict[str, Any]]):
    from rich.table import Table

    t = Table(title=f"zoo: the mobility map (successes / trials, largest severity crossed in >= "
                    f"{CROSSED_SHARE:.0%} of starts, first failure)")
    cols = MAP_COLUMNS
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
    fig, ax = plt.subplots(figsize=(1.0 + 0.8 * len(fams), 1.0 + 0.45 * len(methods)))
    for ln in lines:
        i, j = methods.index(ln["method"]), fams.index(ln["family"])
        grid[i, j] = ln["success"] / max(ln["trials"], 1)
        ax.text(j, i, ln["max_crossed"] or "-", ha="center", va="center", fontsize=7)
    im = ax.imshow(np.ma.masked_invalid(grid), cmap="RdYlGn", vmin=0, vmax=1, aspect="auto")
    ax.set_xticks(range(len(fams)), fams, rotation=60, ha="right")
    ax.set_yticks(range(len(methods)), methods)
    fig.colorbar(im, ax=ax, label="share crossed")
    return fig


#: the per-family panels: (point column, y label); success share first
PANELS = (("share", "share of starts crossed"), ("speed", "speed m/s (crossed)"),
          ("energy_per_m_kg", "energy J/(m kg) (crossed)"))


POINT_COLUMNS = ("method", "family", "token", "severity", "starts", "success", "share", "speed", "energy_per_m",
                 "energy_per_m_kg", "statuses")


def curve_figure(family_id: str, points: list[dict[str, Any]]):
    """One family: success share, speed and energy per metre and kg against the severity (one
    curve per method), and the success share against the severity in the robot's own size (the
    family's first relative scale), where the family has one."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.zoo.families import family as get

    fam = get(family_id)
    rel = fam.relative[0] if fam.relative else None
    n = len(PANELS) + (1 if rel else 0)
    fig, axes = plt.subplots(1, n, figsize=(3.3 * n, 3.0), squeeze=False)
    axes = axes[0]
    methods = sorted({p["method"] for p in points})
    numeric = family_id not in ("rough-mrs", "soft-flat")
    for k, m in enumerate(methods):
        pts = sorted((p for p in points if p["method"] == m), key=lambda p: p["severity"])
        x = [p["severity"] for p in pts]
        style = dict(marker="o", ms=4, lw=1.2, color=plt.cm.tab10(k % 10), label=m)
        for ax, (col, _) in zip(axes, PANELS):
            ax.plot(x, [p[col] for p in pts], **style)
        if rel:
            fp = _footprint(m)
            if fp is not None:
                axes[-1].plot([rel[1](v, fp) for v in x], [p["share"] for p in pts], **style)
    for ax, (_, label) in zip(axes, PANELS):
        ax.set_xlabel(f"{fam.severity} ({fam.unit})")
        ax.set_ylabel(label)
    axes[0].set_ylim(-0.05, 1.05)
    if not numeric:  # named points: label the ticks with the tokens
        ticks = sorted({(p["severity"], p["token"]) for p in points})
        for ax in axes:
            ax.set_xticks([t[0] for t in ticks], [t[1] for t in ticks], rotation=45, ha="right", fontsize=7)
    if rel:
        axes[-1].set_xlabel(f"{fam.severity} in {rel[0]}")
        axes[-1].set_ylabel("share of starts crossed")
        axes[-1].set_ylim(-0.05, 1.05)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"{family_id}: {fam.title}", fontsize=10)
    fig.tight_layout()
    return fig


def contrasts(points: list[dict[str, Any]], n: int = CONTRASTS) -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """The ``n`` most instructive contrasts: per family, the hardest severity that one robot crosses
    in every start and another robot fails in every start; (crossed point, failed point) pairs,
    one per family, the hardest (largest severity rank in its family) first. The failing method
    must cross some easier severity of the family in every start (a method that crosses nothing
    there says nothing about this severity)."""
    from terrabench.zoo.families import family as get

    by: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for p in points:
        by.setdefault((p["family"], p["token"]), []).append(p)
    crosses = {(p["method"], p["family"]) for p in points if p["share"] == 1.0}
    best: dict[str, tuple[float, dict[str, Any], dict[str, Any]]] = {}
    for (f, tok), pts in by.items():
        ok = [p for p in pts if p["share"] == 1.0]
        bad = [p for p in pts if p["success"] == 0 and (p["method"], f) in crosses]
        pairs = [(a, b) for a in ok for b in bad if a["method"].partition(".")[0] != b["method"].partition(".")[0]]
        if not pairs:
            continue
        toks = list(get(f).full) or [tok]
        rank = toks.index(tok) / max(len(toks) - 1, 1) if tok in toks else 0.0
        a, b = min(pairs, key=lambda ab: (ab[0]["method"], ab[1]["method"]))
        if f not in best or rank > best[f][0]:
            best[f] = (rank, a, b)
    ranked = sorted(best.values(), key=lambda t: (-t[0], t[1]["family"]))
    return [(a, b) for _, a, b in ranked[:n]]


def _contrast_clips(page, system, rows: list[dict[str, Any]], pairs, slug: str) -> None:
    """A clip of each side of each contrast, re-run from the stored row (its first seed)."""
    from terrabench.benchmark.trial import TrialSpec

    by = {(r["method"], r["instance"]): r for r in sorted(rows, key=lambda r: r["seed"], reverse=True)}
    for a, b in pairs:
        inst = f"{a['family']}@{a['token']}"
        for p in (a, b):
            r = by.get((p["method"], inst))
            if r is None:
                continue
            spec = TrialSpec(system.id, r["scenario"], r["method"], r["instance"], r["seed"], r["config"])
            name = f"clip_{inst.replace('@', '_')}_{p['method'].replace('.', '_')}{slug}.mp4"
            t_end = (r.get("metrics") or {}).get("sim_time", float("nan"))
            page.clip(name, f"{p['method']} on {inst} (seed {r['seed']}): {r['status']} at {t_end:.1f} s; "
                      f"the first {CLIP_SECONDS:g} s at {CLIP_SPEEDUP:g}x real time (<code>terrabench render zoo "
                      f"--method {p['method']} --terrain {inst}</code>)", system, spec, CLIP_SECONDS, every=None,
                      fps=25.0, speedup=CLIP_SPEEDUP, width=640, height=360)


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
        page.table(lines, MAP_COLUMNS, csv_name=f"map{slug}.csv")
        if lines:
            page.figure(map_figure(lines), f"map{slug}.png", "Share of the stored trials crossed per method and "
                        f"family; the text: the largest severity crossed in >= {CROSSED_SHARE:.0%} of its starts "
                        "(blank: not run or unsupported).")
        points = point_lines(grows)
        page.h3("Success, speed and energy against severity, per family")
        page.p("One curve per method; speed and energy are means over the crossed starts; the last panel puts the "
               "severity in each robot's own size (wheel radii, body heights or lengths: the adapters' footprints).")
        from terrabench.zoo.families import FAMILIES

        for f in FAMILIES:
            fpts = [p for p in points if p["family"] == f]
            if fpts:
                page.figure(curve_figure(f, fpts), f"curve_{f}{slug}.png", f"{f}: every point is a stored row "
                            f"of points{slug}.csv.")
        page.csv(f"points{slug}.csv", points, POINT_COLUMNS)
        page.p(f"Every point of the curves: <a href='points{slug}.csv'>points{slug}.csv</a>.")
        pairs = contrasts(points)
        if pairs:
            page.h3("Contrasts: the same course crossed by one robot and failed by another")
            page.table([{"course": f"{a['family']}@{a['token']}", "crossed by": a["method"], "failed by": b["method"],
                         "how it failed": b["statuses"]} for a, b in pairs],
                       ("course", "crossed by", "failed by", "how it failed"), csv_name=f"contrasts{slug}.csv")
            _contrast_clips(page, system, grows, pairs, slug)
        page.h3("Trials")
        page.table(trial_lines(grows), TRIAL_COLUMNS, csv_name=f"trials{slug}.csv")
    return page.finish()
