"""Tables and figures of the beams system, read only from stored trial rows: the entry points
:func:`summarize` and :func:`write_report`; the figures are drawn in :mod:`.report_figures`, the
table lines built in :mod:`.report_tables`.

Paper reference values are shipped in :data:`PAPER` (Xuan, Wang & Li, Tables 1-4, Sec. III-A,
III-D, IV) and shown beside ours.
"""

from __future__ import annotations

import html
import os
from pathlib import Path
from typing import Any

from .model import critical_stiffness
from .report_figures import _sensitivity_fig, reading_figures
from .report_tables import PAPER, READING_BASIS, _only, _tables, paper_vs_readings, readings_present


def summarize(rows: list[dict[str, Any]]):
    """Rich tables: the paper's results under each gap reading, then per reading: estimation beside
    the paper, traversal energies, open loop, delay, experiment, MuJoCo check."""
    from rich.console import Group
    from rich.table import Table

    rds = readings_present(rows)
    parts = []
    if rows:
        t = Table(title="The paper's results under each reading of the gap d (layout.gap_reading)")
        for c in ["result", "paper"] + rds:
            t.add_column(c)
        for ln in paper_vs_readings(rows):
            t.add_row(ln["result"], ln["paper"], *[ln[rd] for rd in rds])
        parts.append(t)
    for rd in rds:
        parts.extend(_tables(_only(rows, rd), f"[{rd}] "))
    if not parts:
        return Table(title="beams: no stored rows")
    return Group(*parts)



# --------------------------------------------------------------------------- HTML report

def write_report(store, out_dir: Path, system: Any) -> Path:
    """Write ``out_dir/index.html`` plus PNG figures and CSV tables from the store's beams rows.

    Rows are split by their settings (:func:`terrabench.report.variants.settings_groups`, the gap
    reading aside, which is compared side by side): each group with settings other than the
    defaults gets its own section, files suffixed with the group's slug.

    Raises:
        ValueError: the store holds no beams trials, or ``out_dir`` cannot be written.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.report.page import Page, provenance_html
    from terrabench.report.variants import Defaults, settings_groups

    rows = store.rows(system="beams")
    if not rows:
        raise ValueError(f"no beams trials in {store.path}; run `terrabench run beams` first")
    page = Page(out_dir, "Beam traversal with environmental force sensing")
    out_dir = page.out_dir
    page.p(html.escape(PAPER["source"]))
    defaults = Defaults(system)
    groups = settings_groups(rows, defaults, ignore=("layout.gap_reading",))
    k0 = critical_stiffness()
    page.p(f"Critical stiffness k<sub>0</sub> = M g h<sub>c</sub> / arccos(H/L)<sup>2</sup> = "
           f"{k0:.4f} N m/rad (paper: 0.028). Rows in store: {len(rows)} in {len(groups)} settings group(s).")
    for rd in readings_present(rows):
        page.p(f"<b>{rd} reading</b> rests on {html.escape(READING_BASIS[rd])}.")
    for g in groups:
        _group_section(page, store, list(g.rows), g.label, g.slug, plt)
    page.h2("Provenance")
    page.raw(provenance_html(store, rows, system_id="beams", default_config=defaults))
    return page.finish()


def _group_section(page: Any, store: Any, rows: list[dict[str, Any]], label: str, slug: str, plt: Any) -> None:
    """One settings group: the paper-vs-ours table, the summary tables, every figure and CSV."""
    out_dir = page.out_dir
    page.h2(f"Settings: {html.escape(label)}")

    def _write_csv(path: Path, lines: list[dict[str, Any]]) -> None:
        if lines:
            page.csv(path.name, lines, list(dict.fromkeys(k for ln in lines for k in ln)))

    def save(fig, name, caption, rd=None):
        if rd is not None and rd != "edge":
            name = name.replace(".", f"_{rd}.", 1)
        name = name.replace(".", f"{slug}.", 1)
        if rd is not None:
            caption = f"[{rd} reading] {caption}"
        fig.tight_layout()
        page.figure(fig, name, html.escape(caption))

    all_rows = rows
    for rd in readings_present(all_rows) or ["edge"]:
        rows = _only(all_rows, rd)
        reading_figures(page, store, rows, rd, slug, plt, save, _write_csv)
    rows = all_rows
    _sensitivity_fig(rows, save, plt, out_dir, _write_csv, slug)
    from rich.console import Console
    con = Console(record=True, width=150, file=open(os.devnull, "w"))
    con.print(summarize(rows))
    pv = paper_vs_readings(rows)
    _write_csv(out_dir / f"paper_vs_readings{slug}.csv", pv)
    page.h3("Tables")
    page.raw("<pre>" + html.escape(con.export_text()) + "</pre>")
