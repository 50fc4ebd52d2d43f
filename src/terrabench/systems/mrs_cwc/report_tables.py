"""The MRS-CWC report's method/config variants and its Tables II and III (ours beside the paper's):
the lines of ``table_A.csv`` / ``table_B.csv`` and their HTML, built only from stored trials."""

from __future__ import annotations

import html
import json
import math
from typing import Any

from terrabench.benchmark.trial import canonical_json
from terrabench.config import to_dict
from terrabench.report.variants import Variant
from terrabench.report.variants import find_variants as _find_variants
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import METHODS, config_for
from terrabench.systems.mrs_cwc.reference import METRIC_NAMES, TRIALS_PER_GROUP, paper_row

#: Beyond this relative difference an NCR/NEF/NEC cell is highlighted against the paper's.
FAR_FROM_PAPER = 0.2
_SOURCE_NAMES = {"planner": "our planner", "released": "released waypoints"}


# ------------------------------------------------------------------ variants and tables
def find_variants(rows: list[dict[str, Any]]) -> list[Variant]:
    """The (method, settings) variants of ``rows`` (:func:`terrabench.report.variants.find_variants`):
    methods in :data:`METHODS` order (unknown ones last), within a method the default config first,
    then the one with the most trials; labels name the waypoint source first."""
    return _find_variants(rows, default_config=_default_config, order=list(METHODS),
                          label=lambda m: METHODS[m].label if m in METHODS else m, describe=_describe_setting,
                          key_order=lambda k: (k != "waypoint_source", k))


def _default_config(mid: str, instance: str = "") -> dict[str, Any] | None:
    """The config this version plans for ``mid`` with no overrides (None for unknown methods);
    the same on every terrain."""
    if mid not in METHODS:
        return None
    return json.loads(canonical_json(config_for(METHODS[mid], to_dict(MRSConfig()))))


def _describe_setting(key: str, value: Any) -> str:
    return _SOURCE_NAMES.get(value, str(value)) if key == "waypoint_source" else f"{key}={value}"


TABLE_COLUMNS = (
    "group", "method", "label", "config_hash", "n", "n_paper",
    "NSR", "NSR_lo", "NSR_hi", "NSR_paper",
    "NCR", "n_NCR", "NCR_paper", "NEF", "n_NEF", "NEF_paper", "NEC", "n_NEC", "NEC_paper",
    "NEC_pooled", "diverged", "error",
)


def group_table(variants: list[Variant], summ: dict, group: str) -> list[dict[str, Any]]:
    """One line per variant with trials in ``group``: ours beside the paper's (NSR, NCR in %)."""
    lines = []
    for v in variants:
        s = summ.get((v.id, group))
        if s is None:
            continue
        paper = paper_row(group, v.method) or {}
        line: dict[str, Any] = {
            "group": group, "method": v.method, "label": v.label, "config_hash": v.config_hash,
            "n": s["n"], "n_paper": TRIALS_PER_GROUP if paper else None,
            "NSR": s["NSR"], "NSR_lo": s["NSR_lo"], "NSR_hi": s["NSR_hi"], "NSR_paper": paper.get("NSR"),
            "NEC_pooled": s["NEC_pooled"], "diverged": s["diverged"], "error": s["errors"],
        }
        for name in METRIC_NAMES[1:]:
            line[name], line[f"n_{name}"], line[f"{name}_paper"] = s[name], s[f"n_{name}"], paper.get(name)
        lines.append(line)
    return lines


def _far(line: dict[str, Any], name: str) -> bool:
    """Whether our cell is far from the paper's (see :data:`FAR_FROM_PAPER`)."""
    ours, paper = line[name], line[f"{name}_paper"]
    if paper is None or not _finite(ours):
        return False
    if name == "NSR":
        return not line["NSR_lo"] <= paper <= line["NSR_hi"]
    return abs(ours - paper) > FAR_FROM_PAPER * abs(paper)


_UNITS = ("%", "%", "", "J/m")  # of METRIC_NAMES


def _table_html(lines: list[dict[str, Any]]) -> str:
    head = ("<tr><th rowspan=2>method</th><th rowspan=2>config</th><th rowspan=2><i>n</i></th>"
            + "".join(f"<th colspan={3 if m == 'NSR' else 2}>{m} {u}</th>" for m, u in zip(METRIC_NAMES, _UNITS))
            + "<th rowspan=2>diverged</th><th rowspan=2>error</th></tr><tr>"
            + "<th>ours</th><th>paper</th><th>95 % CI</th>" + "<th>ours</th><th>paper</th>" * 3 + "</tr>")
    body = []
    for ln in lines:
        tds = [html.escape(ln["label"]), f"<a href='#cfg-{ln['config_hash']}'><code>{ln['config_hash'][:8]}</code></a>",
               str(ln["n"])]
        for name in METRIC_NAMES:
            count = ln.get(f"n_{name}", ln["n"])
            small = f" <small>({count})</small>" if count != ln["n"] else ""
            cls = " class=far" if _far(ln, name) else ""
            tds.append(f"<span{cls}>{_fmt(name, ln[name])}</span>{small}")
            tds.append(_fmt(name, ln[f"{name}_paper"]))
            if name == "NSR":
                tds.append(f"{ln['NSR_lo']:.0f}-{ln['NSR_hi']:.0f}")
        tds += [str(ln["diverged"]), str(ln["error"])]
        body.append("<tr>" + "".join(f"<td>{t}</td>" for t in tds) + "</tr>")
    return f"<table>{head}{''.join(body)}</table>"


def _fmt(name: str, v: Any) -> str:
    if not _finite(v):
        return "-"
    return f"{v:.3f}" if name == "NEF" else f"{v:.1f}"


def _finite(v: Any) -> bool:
    return isinstance(v, (int, float)) and math.isfinite(v)
