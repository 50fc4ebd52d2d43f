"""Stored single-wheel rows -> the CLI table and the HTML report (plots in :mod:`terrabench.soil.report`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from terrabench.systems.soil.scenarios import parse_instance

SOURCE = {"rig": "mujoco", "analytic": "analytic"}


def sweep_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Trial rows as sweep points (soil, load_N, slip, DP_N, ..., source)."""
    out = []
    for r in rows:
        if r["status"] != "done" or r["method"] not in SOURCE:
            continue
        soil, load, slip = parse_instance(r["instance"])
        m = r["metrics"]
        out.append({"soil": r["config"]["soil"]["name"], "load_N": load, "slip": slip, "DP_N": m["DP_N"],
                    "torque_Nm": m["torque_Nm"], "sinkage_m": m["sinkage_m"], "DP_coeff": m["DP_coeff"],
                    "efficiency": m["efficiency"], "source": SOURCE[r["method"]]})
    return out


def summary_table(rows: list[dict[str, Any]]):
    """DP/W at slip 0.2 / 0.4 / 0.6 and sinkage at slip 0.2, per soil, load and method."""
    from rich.table import Table

    pts = {}
    for p in sweep_rows(rows):
        pts[(p["soil"], p["load_N"], p["source"], round(p["slip"], 2))] = p
    t = Table(title="single wheel: DP/W at slip 0.2 / 0.4 / 0.6, sinkage at 0.2 (mm); rig vs analytic")
    for c in ("soil", "load N", "source", "DP/W s=0.2", "s=0.4", "s=0.6", "sinkage mm"):
        t.add_column(c)
    for soil, load, src in sorted({k[:3] for k in pts}):
        cells = [f"{pts[(soil, load, src, s)]['DP_coeff']:.3f}" if (soil, load, src, s) in pts else "-" for s in (0.2, 0.4, 0.6)]
        z = pts.get((soil, load, src, 0.2))
        t.add_row(soil, f"{load:g}", src, *cells, f"{1e3 * z['sinkage_m']:.1f}" if z else "-")
    return t


def write_report(store, out_dir: Path) -> Path:
    from terrabench.soil.report import write_report as plot_report

    rows = sweep_rows(store.rows(system="soil"))
    if not rows:
        raise ValueError("the store has no finished soil trials; run `terrabench run soil --group single-wheel` first")
    return plot_report(rows, Path(out_dir))
