"""The MRS-CWC report's A* section: our planner's waypoints against the released ones
(``astar_paths.csv``, ``astar_paths_terrains.csv``, ``astar_paths.png``) and, when the store holds
A* runs with both waypoint sources, their outcomes side by side (``astar_sources.csv``)."""

from __future__ import annotations

import html
import json
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from terrabench.config import to_dict  # noqa: E402
from terrabench.planning.astar import polyline_deviation  # noqa: E402
from terrabench.report.page import Page, table_html  # noqa: E402
from terrabench.report.terrain_plot import draw_terrain  # noqa: E402
from terrabench.report.variants import Variant  # noqa: E402
from terrabench.systems.mrs_cwc.config import MRSConfig  # noqa: E402
from terrabench.systems.mrs_cwc.methods import METHODS  # noqa: E402
from terrabench.systems.mrs_cwc.planner import plan_waypoints  # noqa: E402
from terrabench.systems.mrs_cwc.summary import summaries  # noqa: E402
from terrabench.terrain import dataset  # noqa: E402

# ------------------------------------------------------------------ A* waypoints
ASTAR_TERRAIN_COLUMNS = ("terrain", "group", "deviation", "ours_to_released", "released_to_ours",
                         "n_ours", "n_released", "length_ours", "length_released")
ASTAR_GROUP_COLUMNS = ("group", "terrains", "mean", "median", "max", "max_terrain")
SOURCE_COLUMNS = ("group", "method", "waypoint_source", "label", "config_hash", "terrains", "NSR", "NCR",
                  "diverged", "error")


def astar_comparison(cfg: MRSConfig) -> tuple[list[dict[str, Any]], dict[str, tuple[np.ndarray, np.ndarray]]]:
    """Our planner's waypoints vs the released ones on all 100 terrains.

    Args:
        cfg: the config whose ``planner``, ``protocol.start_xy`` and ``protocol.target_xy`` are used.

    Returns:
        Per-terrain lines (deviations in m: the mean distance from points along one polyline
        to the other, each way, and their average) and ``{terrain id: (ours (n, 2), released
        (m, 2))}`` waypoint arrays (m).
    """
    lines, waypoints = [], {}
    for t in dataset.select(group="all"):
        ours, released = plan_waypoints(t, cfg), dataset.released_waypoints(t.id)
        a, b = polyline_deviation(ours, released), polyline_deviation(released, ours)
        lines.append({"terrain": t.id, "group": t.group, "deviation": 0.5 * (a + b), "ours_to_released": a,
                      "released_to_ours": b, "n_ours": len(ours), "n_released": len(released),
                      "length_ours": _length(ours), "length_released": _length(released)})
        waypoints[t.id] = (ours, released)
    return lines, waypoints


def _length(poly: np.ndarray) -> float:
    return float(np.hypot(*np.diff(poly, axis=0).T).sum())


def astar_group_lines(lines: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Mean, median and max deviation (m) per group."""
    out = []
    for group in dataset.GROUPS:
        g = [ln for ln in lines if ln["group"] == group]
        d = np.array([ln["deviation"] for ln in g])
        worst = g[int(np.argmax(d))]
        out.append({"group": group, "terrains": len(g), "mean": float(d.mean()), "median": float(np.median(d)),
                    "max": float(d.max()), "max_terrain": worst["terrain"]})
    return out


def astar_figure(lines: list[dict[str, Any]], waypoints: dict[str, tuple[np.ndarray, np.ndarray]]):
    """Per group the terrains of median and largest deviation: both waypoint polylines."""
    shown = []
    for group in dataset.GROUPS:
        g = sorted((ln for ln in lines if ln["group"] == group), key=lambda ln: ln["deviation"])
        shown += [(g[len(g) // 2], "median"), (g[-1], "largest")]
    fig, axes = plt.subplots(2, 2, figsize=(13, 11))
    for ax, (ln, which) in zip(axes.flat, shown):
        ours, released = waypoints[ln["terrain"]]
        draw_terrain(ax, dataset.get(ln["terrain"]), {"released waypoints": released.T, "our A* waypoints": ours.T})
        for line in ax.lines[-2:]:  # the two polylines just drawn: mark their waypoints
            line.set_marker("o")
            line.set_markersize(3)
        ax.set_title(f"{ax.get_title()}\n{which} deviation in group {ln['group']}: {ln['deviation']:.2f} m", fontsize=9)
    fig.tight_layout()
    return fig


def source_lines(tagged: list[dict[str, Any]], variants: list[Variant]) -> list[dict[str, Any]]:
    """A* methods stored with both waypoint sources: each variant's outcome on the terrains
    that both sources ran (per group), so the two are compared trial for trial."""
    source = {v.id: v.config.get("waypoint_source") for v in variants}
    out = []
    for mid in [m for m in METHODS if METHODS[m].guidance == "astar"]:
        vs = [v for v in variants if v.method == mid]
        sources = {source[v.id] for v in vs}
        if len(sources) < 2:
            continue
        ids = {v.id for v in vs}
        mine = [r for r in tagged if r["method"] in ids]
        for group in dataset.GROUPS:
            ran = [{r["instance"] for r in mine if r["instance"][0] == group and source[r["method"]] == s}
                   for s in sources]
            common = set.intersection(*ran)
            if not common:
                continue
            summ = summaries([r for r in mine if r["instance"] in common])
            for v in vs:
                s = summ.get((v.id, group))
                if s is not None:
                    out.append({"group": group, "method": mid, "waypoint_source": source[v.id], "label": v.label,
                                "config_hash": v.config_hash, "terrains": s["n"], "NSR": s["NSR"],
                                "NCR": s["NCR"], "diverged": s["diverged"], "error": s["errors"]})
    return out


def _astar_section(page: "Page", tagged: list[dict[str, Any]], variants: list[Variant]) -> None:
    """Deviation tables and figure; the outcomes by waypoint source when both were run."""
    cfg = MRSConfig()
    lines, waypoints = astar_comparison(cfg)
    groups = astar_group_lines(lines)
    page.csv("astar_paths_terrains.csv", lines, ASTAR_TERRAIN_COLUMNS)
    page.csv("astar_paths.csv", groups, ASTAR_GROUP_COLUMNS)
    page.p("Our A* (<code>planner.plan_waypoints</code> with the default planner config of this terrabench "
           "version) against the waypoints the released A* variants follow. Deviation: mean distance (m) from "
           "points sampled along one polyline to the other, averaged over both directions. Computed from the "
           "shipped terrain data, not from stored trials.")
    page.raw(table_html(groups, ASTAR_GROUP_COLUMNS)
             + " <a href='astar_paths.csv'>astar_paths.csv</a>, per terrain: "
             "<a href='astar_paths_terrains.csv'>astar_paths_terrains.csv</a>")
    planner_json = html.escape(json.dumps(to_dict(cfg.planner), indent=2))
    page.raw(f"<details><summary>planner config used</summary><pre>{planner_json}"
             "</pre></details>")
    page.figure(astar_figure(lines, waypoints), "astar_paths.png",
                "Waypoints on the height map: per group the terrain of median and of largest deviation.")
    src = source_lines(tagged, variants)
    if src:
        page.csv("astar_sources.csv", src, SOURCE_COLUMNS)
        page.p("Stored A* runs with both waypoint sources, on the terrains both ran:")
        page.raw(table_html(src, SOURCE_COLUMNS) + " <a href='astar_sources.csv'>astar_sources.csv</a>")
