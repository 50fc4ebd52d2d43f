"""The MRS-CWC report, built only from stored trials (and the shipped terrain data).

:func:`write_report` writes into ``out_dir``:

- ``table_A.csv``, ``table_B.csv``: the paper's Tables II and III (NSR %, NCR %, NEF, NEC J/m),
  our number beside the paper's, with the trials behind each cell, the 95 % Wilson CI of NSR
  and the ``diverged``/``error`` counts (both counted as failures).
- ``outcomes.png``, ``outcomes.csv``: every method on every terrain (colour = NCR, symbol =
  how the trial ended); the CSV names the stored trial key of each cell.
- ``fig5_group_A.png``, ``fig6_group_B.png``: analogues of the paper's Figs. 5 and 6: every
  method's leader path on one terrain, and the MRS-CWC + TDT run's K(t) and |tau_env|(t).
- ``astar_paths.csv`` (per group), ``astar_paths_terrains.csv`` (per terrain),
  ``astar_paths.png``: our A* waypoints against the released ones; ``astar_sources.csv`` when
  the store holds A* runs with both waypoint sources.
- ``statuses.csv``: how trials ended, simulated and wall time, per method and group.
- ``index.html``: all of the above on one static page, with the configs used.

Only seed-0 rows enter the tables and figures (seed 0 is the released protocol exactly). A
method whose seed-0 rows were run under more than one config appears once per config (a
*variant*), labelled by the config keys that differ, so no table row mixes two configs.

The variants and the Tables II/III lines are built in :mod:`.report_tables`, the A* waypoint
section in :mod:`.report_astar`.
"""

from __future__ import annotations

import html
import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from terrabench.benchmark.trial import STATUSES  # noqa: E402
from terrabench.report.page import Page, note, provenance_html, table_html  # noqa: E402
from terrabench.report.terrain_plot import draw_terrain  # noqa: E402
from terrabench.report.variants import Variant  # noqa: E402
from terrabench.systems.mrs_cwc.methods import METHODS  # noqa: E402
from terrabench.systems.mrs_cwc.reference import paper_row  # noqa: E402
from terrabench.systems.mrs_cwc.report_astar import _astar_section  # noqa: E402
from terrabench.systems.mrs_cwc.report_tables import (  # noqa: E402
    FAR_FROM_PAPER,
    TABLE_COLUMNS,
    _default_config,
    _finite,
    _table_html,
    find_variants,
    group_table,
)
from terrabench.systems.mrs_cwc.summary import seed_summary, summaries  # noqa: E402
from terrabench.terrain import dataset  # noqa: E402

#: The paper's table and figure for each terrain group.
PAPER_TABLE = {"A": "Table II", "B": "Table III"}
PATH_FIGURES = {"A": ("fig5_group_A.png", "Fig. 5"), "B": ("fig6_group_B.png", "Fig. 6")}
#: Every file this module may write; ones a smaller store no longer produces are removed, so a
#: report folder never shows figures from an earlier store.
OUTPUTS = (
    "index.html", "table_A.csv", "table_B.csv", "outcomes.png", "outcomes.csv",
    "fig5_group_A.png", "fig6_group_B.png", "astar_paths.csv", "astar_paths_terrains.csv",
    "astar_paths.png", "astar_sources.csv", "statuses.csv",
)
#: Trial endings drawn as symbols in the outcome matrix (a timeout is colour only).
_MARKERS = {
    "success": dict(marker="o", color="black", ms=3.5, ls=""),
    "fell": dict(marker="v", color="black", ms=4, ls=""),
    "stuck": dict(marker="s", color="black", ms=3, ls=""),
    "diverged": dict(marker="D", color="magenta", mec="black", mew=0.4, ms=4.5, ls=""),
    "error": dict(marker="X", color="red", mec="black", mew=0.4, ms=6, ls=""),
}


def write_report(store, out_dir: Path, render: bool = False, system: Any = None) -> Path:
    """Write the MRS-CWC report from ``store``'s rows; returns the path of ``index.html``.

    Args:
        store: a :class:`~terrabench.benchmark.store.ResultsStore` (read only is enough).
        out_dir: folder for the HTML page, PNG figures and CSV tables (created if missing).
        render: also render a frame strip of a short MRS-CWC + TDT trial (:func:`_strip`;
            off by default: it costs a few seconds of simulation and GL rendering).
        system: the MRS-CWC system object (needed for ``render``; the system passes itself).

    Raises:
        ValueError: the store holds no mrs-cwc trials.
    """
    rows = store.rows(system="mrs-cwc")
    if not rows:
        raise ValueError(f"no mrs-cwc trials in {store.path}; run `terrabench run mrs-cwc` first")
    page = Page(out_dir, "MRS-CWC rough-terrain navigation benchmark", outputs=OUTPUTS)
    out_dir = page.out_dir
    rows0 = [r for r in rows if r["seed"] == 0]
    variants = find_variants(rows0)
    vid = {(v.method, h): v.id for v in variants for h in v.hashes}
    # summaries() groups by (method, group): give each row its variant id as the method
    tagged = [{**r, "method": vid[(r["method"], r["config_hash"])]} for r in rows0]
    summ = summaries(tagged)
    cells = {(r["method"], r["instance"]): r for r in tagged}
    terrain_ids = list(dataset.benchmark_terrains())
    page.p(f"{len(rows0)} seed-0 trials ({len(variants)} method/config variant(s)) from "
           f"<code>{html.escape(str(store.path))}</code>; every number and figure below is computed from "
           "these stored rows (the A* waypoint comparison from the shipped terrain data). Paper: Xiao et al., "
           "MRS-CWC, Tables II/III and Figs. 5/6.")

    seeded = [{**r, "method": vid[(r["method"], r["config_hash"])]} for r in rows
              if (r["method"], r["config_hash"]) in vid]
    if len({r["seed"] for r in seeded}) > 1:
        _seeds_section(page, variants, seeded)

    page.h2("Tables II and III: ours beside the paper's")
    page.p(
        "Each cell: ours / the paper's (Table II or III of the paper, 50 terrains per group). "
        "<i>n</i> = our trials in the row; a smaller count beside a mean means trials whose metric "
        "was undefined (NaN, e.g. an <code>error</code> trial) are left out of it. "
        "<code>diverged</code> and <code>error</code> trials count as failures in NSR. "
        f"Highlighted: the paper's NSR outside our 95 % Wilson CI, or NCR/NEF/NEC more than "
        f"{FAR_FROM_PAPER:.0%} from the paper's. NEC is the paper's mean of per-trial E / D_ef; it is "
        "heavy-tailed (a trial that barely moved toward the target has a huge NEC), so the CSVs also "
        "give <code>NEC_pooled</code> = sum(E) / sum(D_ef) over the row's trials."
    )
    differs = protocol_note(variants)
    if differs:
        page.raw(note(differs))
    for group in dataset.GROUPS:
        lines = group_table(variants, summ, group)
        name = f"table_{group}.csv"
        page.csv(name, lines, TABLE_COLUMNS)
        page.h3(f"Group {group} ({PAPER_TABLE[group]} of the paper) <a href='{name}'>{name}</a>")
        page.raw(_table_html(lines) if lines else note(f"No stored seed-0 trials in group {group}."))

    page.h2("Per-terrain outcomes")
    page.csv("outcomes.csv", outcome_lines(variants, cells, terrain_ids), OUTCOME_COLUMNS)
    if variants:
        page.figure(outcome_figure(variants, cells, terrain_ids), "outcomes.png",
                    "Every method (rows) on every terrain (columns): colour = NCR, symbol = how the trial ended "
                    "(no symbol: timeout; grey: not run or no NCR). <a href='outcomes.csv'>outcomes.csv</a> gives "
                    "the stored trial key of each cell.")
    else:
        page.raw(note("No stored seed-0 trials: no outcome matrix."))

    page.h2("Leader paths (analogues of the paper's Figs. 5 and 6)")
    for group in dataset.GROUPS:
        name, paper_fig = PATH_FIGURES[group]
        gids = [t for t in terrain_ids if t[0] == group]
        tid = pick_terrain(variants, cells, gids)
        if tid is None:
            page.raw(note(f"No stored seed-0 trials in group {group}: no {paper_fig} analogue."))
            continue
        fig = path_figure(store, variants, cells, dataset.get(tid))
        page.figure(fig, name, f"{paper_fig} analogue, group {group}: terrain {tid} (the group's terrain with the "
                    "most stored methods, then the most varied outcomes). Top: leader paths; below: yaw "
                    "stiffness K and |tau_env| of the MRS-CWC + TDT run, as stored (every protocol.log_period).")

    if render:
        if system is None:
            raise ValueError("render=True needs the system: write_report(store, out, render=True, system=SYSTEM)")
        _strip(page, system, tagged)
    page.h2("A* waypoints: our planner vs the released ones")
    _astar_section(page, tagged, variants)

    page.h2("How trials ended")
    lines = status_lines(variants, tagged)
    page.csv("statuses.csv", lines, STATUS_COLUMNS)
    page.raw(table_html(lines, STATUS_COLUMNS) + " <a href='statuses.csv'>statuses.csv</a>")

    page.h2("Provenance")
    page.raw(provenance_html(store, rows, system_id="mrs-cwc", default_config=_default_config, extra=[
        f"seed 0 (in the tables and figures): {len(rows0)}; seeds &gt; 0 (only in the seeds section): "
        f"{len(rows) - len(rows0)}", f"methods shown: {len(variants)} (method, config) variant(s)"]))

    return page.finish()


SEED_COLUMNS = ("group", "method", "label", "n_terrains", "n_seeds", "NSR", "NSR_lo", "NSR_hi", "flip_share",
                "NSR_paper")


#: the protocol settings the paper's numbers were measured under (spec section 2); a variant that
#: changes one is not comparable with them (the report says so in words)
PAPER_PROTOCOL = {"protocol.timeout": (1000.0, "s"), "protocol.success_threshold": (0.5, "m")}


def protocol_note(variants: list[Variant]) -> str:
    """One sentence naming the variants run under another protocol than the paper's, or ''."""
    parts = []
    for v in variants:
        changed = [f"{k} = {v.diff[k]} {unit} (paper {ref:g} {unit})" for k, (ref, unit) in PAPER_PROTOCOL.items()
                   if k in v.diff and v.diff[k] != ref]
        if changed:
            parts.append(f"{v.id}: {', '.join(changed)}")
    if not parts:
        return ""
    return ("Not the paper's protocol, so not comparable with its numbers (a shorter time limit turns late "
            "arrivals into timeouts; another success distance changes what counts as arrival): " + "; ".join(parts)
            + ".")


def seed_lines(variants: list[Variant], seeded: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One line per (group, variant): NSR over seeds with a terrain bootstrap CI, flip share."""
    summ = seed_summary(seeded)
    lines = []
    for group in dataset.GROUPS:
        for v in variants:
            s = summ.get((v.id, group))
            if s is None:
                continue
            paper = paper_row(group, v.method) or {}
            lines.append({"group": group, "method": v.id, "label": v.label, **s,
                          "NSR_paper": paper.get("NSR", float("nan"))})
    return lines


def _short(label: str, width: int = 70) -> str:
    return label if len(label) <= width else label[: width - 3] + "..."


def _seeds_section(page: "Page", variants: list[Variant], seeded: list[dict[str, Any]]) -> None:
    lines = seed_lines(variants, seeded)
    if not lines:
        return
    page.h2("NSR over seeds (the primary figure when several seeds are stored)")
    page.p("One trial per terrain, as in the paper, is a single draw of a chaotic system: seeds > 0 move "
           "the start by up to 5 cm. Here each method's NSR is the success share over every (terrain, seed) "
           "trial on the terrains run with all its seeds, with a 95 % bootstrap CI over terrains (a "
           "terrain keeps its seeds together), and <i>flips</i> is the share of those terrains whose outcome "
           "differs between seeds. The paper's NSR (one trial per terrain) is the black tick.")
    page.csv("nsr_seeds.csv", lines, SEED_COLUMNS)
    groups = [g for g in dataset.GROUPS if any(ln["group"] == g for ln in lines)]
    fig, axes = plt.subplots(1, len(groups), figsize=(6.5 * len(groups), 0.6 + 0.35 * len(lines)), squeeze=False)
    for ax, group in zip(axes[0], groups):
        sel = [ln for ln in lines if ln["group"] == group]
        y = np.arange(len(sel))
        nsr = np.array([ln["NSR"] for ln in sel])
        err = np.array([[ln["NSR"] - ln["NSR_lo"] for ln in sel], [ln["NSR_hi"] - ln["NSR"] for ln in sel]])
        ax.barh(y, nsr, xerr=err if len(sel) else None, color="#4c72b0", alpha=0.8, capsize=3)
        ax.scatter([ln["NSR_paper"] for ln in sel], y, marker="|", s=200, color="k", zorder=3)
        ax.set_yticks(y, [f"{_short(ln['label'])} (flips {ln['flip_share']:.0f} %)" for ln in sel], fontsize=7)
        ax.set(xlim=(0, 100), xlabel="NSR % over seeds", title=f"group {group}")
        ax.invert_yaxis()
    fig.tight_layout()
    page.figure(fig, "nsr_seeds.png", "NSR over seeds with 95 % CI (bars), the paper's NSR (ticks), and the share of "
                "terrains whose outcome flips between seeds. <a href='nsr_seeds.csv'>nsr_seeds.csv</a>")
    page.raw(table_html([{k: (f"{v:.1f}" if isinstance(v, float) else v) for k, v in ln.items()}
                                for ln in lines], SEED_COLUMNS))


def _strip(page: Page, system: Any, rows: list[dict[str, Any]], seconds: float = 3.0,
           name: str = "trial_strip.png") -> None:
    """Four snapshots of a short MRS-CWC + TDT trial (the first stored cwc-tdt terrain, else A-01;
    ``seconds`` simulated), or a note when this machine has no headless GL."""
    from terrabench.systems.mrs_cwc.env import overlay

    tid = next((r["instance"] for r in rows if r["method"].startswith("cwc-tdt")), "A-01")
    spec = system.plan(methods=["cwc-tdt"], instances=[tid], overrides={"protocol.timeout": seconds + 0.1})[0]
    times = [seconds * k / 3 for k in range(4)]
    page.snapshots(name, f"MRS-CWC + TDT on {tid}, the first {seconds:g} simulated seconds (t = "
                   f"{', '.join(f'{t:g}' for t in times)} s), rendered from the benchmark's own episode "
                   "(<code>terrabench render</code> makes a clip).", system, spec, times, overlay=overlay)


# ------------------------------------------------------------------ outcome matrix
OUTCOME_COLUMNS = ("terrain", "group", "method", "label", "config_hash", "status", "NCR_pct", "d_min", "sim_time",
                   "key")


def outcome_lines(variants: list[Variant], cells: dict, terrain_ids: list[str]) -> list[dict[str, Any]]:
    """One line per stored seed-0 trial, variants in table order, terrains in id order."""
    lines = []
    for v in variants:
        for tid in terrain_ids:
            r = cells.get((v.id, tid))
            if r is not None:
                m = r["metrics"]
                lines.append({"terrain": tid, "group": tid[0], "method": v.method, "label": v.label,
                              "config_hash": v.config_hash, "status": r["status"],
                              "NCR_pct": 100.0 * m.get("NCR", np.nan), "d_min": m.get("d_min"),
                              "sim_time": m.get("sim_time"), "key": r["key"]})
    return lines


def outcome_figure(variants: list[Variant], cells: dict, terrain_ids: list[str]):
    """Heat map variants x terrains of NCR (%) with a symbol per trial ending."""
    ncr = np.full((len(variants), len(terrain_ids)), np.nan)
    marks: dict[str, list[tuple[int, int]]] = {s: [] for s in _MARKERS}
    for i, v in enumerate(variants):
        for j, tid in enumerate(terrain_ids):
            r = cells.get((v.id, tid))
            if r is None:
                continue
            ncr[i, j] = 100.0 * r["metrics"].get("NCR", np.nan)
            if r["status"] in marks:
                marks[r["status"]].append((i, j))
    fig, ax = plt.subplots(figsize=(0.16 * len(terrain_ids) + 4, 0.42 * len(variants) + 2.4))
    cmap = plt.get_cmap("RdYlGn").with_extremes(bad="0.85")
    im = ax.imshow(np.ma.masked_invalid(ncr), cmap=cmap, vmin=0, vmax=100, aspect="auto", interpolation="nearest")
    for status, ij in marks.items():
        if ij:
            i, j = np.array(ij).T
            ax.plot(j, i, **_MARKERS[status])
    # group boundary: the first column of each later group
    for j in range(1, len(terrain_ids)):
        if terrain_ids[j][0] != terrain_ids[j - 1][0]:
            ax.axvline(j - 0.5, color="black", lw=1.5)
    ax.set_xticks(range(len(terrain_ids)), terrain_ids, rotation=90, fontsize=6)
    ax.set_yticks(range(len(variants)), [v.label for v in variants], fontsize=8)
    fig.colorbar(im, ax=ax, label="NCR (%)", pad=0.01, fraction=0.02)
    handles = [Line2D([], [], label=s, **kw) for s, kw in _MARKERS.items()]
    handles += [Patch(facecolor="white", edgecolor="black", label="timeout: colour only"),
                Patch(facecolor="0.85", edgecolor="black", label="not run / NCR undefined")]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.28 if len(variants) < 6 else -0.12),
              ncol=len(handles), fontsize=8, frameon=False)
    ax.set_title("Outcome per terrain (seed 0)")
    return fig


# ------------------------------------------------------------------ Fig. 5/6 analogues
def pick_terrain(variants: list[Variant], cells: dict, terrain_ids: list[str]) -> str | None:
    """The terrain with the most stored variants, then the most distinct endings, then the
    widest NCR spread; the lowest id on ties. ``None`` if no variant ran on any of them."""

    def score(tid: str) -> tuple[int, int, float]:
        rs = [cells[(v.id, tid)] for v in variants if (v.id, tid) in cells]
        ncr = [r["metrics"].get("NCR", np.nan) for r in rs]
        ncr = [x for x in ncr if _finite(x)]
        return len(rs), len({r["status"] for r in rs}), (max(ncr) - min(ncr)) if ncr else 0.0

    stored = [t for t in terrain_ids if any((v.id, t) in cells for v in variants)]
    return max(stored, key=score) if stored else None


def path_figure(store, variants: list[Variant], cells: dict, terrain):
    """Leader paths of every stored variant on ``terrain``; K(t) and |tau_env|(t) of CWC + TDT."""
    paths, cwc = {}, None
    for v in variants:
        r = cells.get((v.id, terrain.id))
        if r is None:
            continue
        ts = store.timeseries(r["key"])  # only the drawn trials' series are read
        if "x" in ts:
            ncr = r["metrics"].get("NCR", np.nan)
            paths[f"{v.label}: {r['status']}, NCR {100 * ncr:.0f} %"] = (ts["x"], ts["y"])
        if v.method == "cwc-tdt" and cwc is None and "K" in ts:
            cwc = (v, r, ts)
    # the legend (start, target, one line per path) gets its own row so it hides no path
    legend_h = 0.16 * math.ceil((len(paths) + 2) / 2)
    fig = plt.figure(figsize=(8, 10.5 + legend_h))
    gs = fig.add_gridspec(4, 1, height_ratios=(6.2, legend_h, 1.4, 1.4), hspace=0.3)
    ax = fig.add_subplot(gs[0])
    im = draw_terrain(ax, terrain, paths)
    ax.get_legend().remove()
    ax_leg = fig.add_subplot(gs[1])
    ax_leg.axis("off")
    ax_leg.legend(*ax.get_legend_handles_labels(), loc="center", ncol=2, fontsize=7, frameon=False)
    # a diverged path may leave the map; keep the view on the terrain
    x0, x1, y0, y1 = im.get_extent()
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax_k = fig.add_subplot(gs[2])
    ax_t = fig.add_subplot(gs[3], sharex=ax_k)
    if cwc is None:
        ax_k.text(0.5, 0.5, f"no {METHODS['cwc-tdt'].label} trial stored on {terrain.id}", ha="center",
                  va="center", transform=ax_k.transAxes)
    else:
        v, r, ts = cwc
        law = r["config"].get("stiffness", {})
        ax_k.plot(ts["t"], ts["K"], color="tab:blue")
        ax_t.plot(ts["t"], np.abs(ts["tau_env"]), color="tab:red", lw=0.8)
        for name, ls in (("latch_on", "--"), ("latch_off", ":")):
            if name in law:
                ax_t.axhline(law[name], color="black", ls=ls, lw=0.8, label=f"{name} = {law[name]:g} N m")
        ax_t.legend(fontsize=7, loc="upper right")
        ax_k.set_title(f"{v.label} on {terrain.id}: {r['status']} (trial {r['key']})", fontsize=9)
    ax_k.set_ylabel("K (N m/rad)")
    ax_t.set_ylabel("|tau_env| (N m)")
    ax_t.set_xlabel("t (s)")
    return fig


# ------------------------------------------------------------------ statuses
#: Trial endings of this system (``done`` belongs to systems without a goal).
ENDINGS = tuple(s for s in STATUSES if s != "done")
STATUS_COLUMNS = ("group", "label", "config_hash", "n", *ENDINGS, "sim_time_h", "wall_time_h")


def status_lines(variants: list[Variant], tagged: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per group and variant: trial endings, total simulated and wall time (h); a total line last."""

    def line(group: str, label: str, h: str, rs: list[dict[str, Any]]) -> dict[str, Any]:
        ln: dict[str, Any] = {"group": group, "label": label, "config_hash": h, "n": len(rs)}
        for s in ENDINGS:
            ln[s] = sum(r["status"] == s for r in rs)
        ln["sim_time_h"] = sum(r["metrics"].get("sim_time", 0.0) for r in rs) / 3600
        ln["wall_time_h"] = sum(r["wall_time"] for r in rs) / 3600
        return ln

    out = []
    for group in dataset.GROUPS:
        for v in variants:
            rs = [r for r in tagged if r["method"] == v.id and r["instance"][0] == group]
            if rs:
                out.append(line(group, v.label, v.config_hash, rs))
    out.append(line("all", "all seed-0 trials", "", tagged))
    return out
