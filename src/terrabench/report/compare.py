"""Stored trials side by side, one line per (instance, config variant): what an ablation reads.

``terrabench run SYSTEM --vary KEY=V1,V2`` stores one variant per value; ``terrabench compare
SYSTEM`` reads any store and puts the variants of each instance side by side: the statuses, and
for each metric the median with the smallest and largest value over the seeds. Variants are the
report's (:mod:`terrabench.report.variants`): a method under one set of settings, labelled by
the settings that tell it apart from the method's other variants, so no line mixes two configs.
"""

from __future__ import annotations

import csv
import math
import statistics
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from terrabench.benchmark.trial import canonical_json
from terrabench.report.variants import Defaults, find_variants, flatten

if TYPE_CHECKING:
    from terrabench.systems.base import System


@dataclass(frozen=True)
class Line:
    """One (instance, variant): its trials' statuses and each metric's (median, min, max)."""

    instance: str
    method: str
    label: str
    settings: Mapping[str, Any]
    n: int
    statuses: Mapping[str, int]
    metrics: Mapping[str, tuple[float, float, float] | None]

    @property
    def successes(self) -> int:
        return self.statuses.get("success", 0)


def _number(v: Any) -> float | None:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        return None
    return float(v)


def _settings_order(config: Mapping[str, Any], keys: Sequence[str]) -> tuple:
    """Sort key of a variant: its values of ``keys`` (the settings its method's variants differ
    in, the default's own values included), numbers by value, anything else by its JSON."""
    flat = flatten(dict(config))
    out = []
    for k in keys:
        v = flat.get(k)
        x = _number(v)
        out.append((0, x, "") if x is not None else (1, 0.0, canonical_json(v)))
    return tuple(out)


def metric_names(rows: Sequence[dict[str, Any]]) -> list[str]:
    """Every metric that is a finite number in at least one row, sorted."""
    return sorted({k for r in rows for k, v in r["metrics"].items() if _number(v) is not None})


#: metric columns shown by default for a system that names no headline metrics
SHOWN_DEFAULT = 6


def shown_metrics(lines: Sequence[Line], system: System) -> list[str]:
    """The metrics a terminal table of ``lines`` shows by default: the system's headline metrics
    the lines have, else the first :data:`SHOWN_DEFAULT` of them."""
    have = list(lines[0].metrics) if lines else []
    return [m for m in system.headline_metrics if m in have] or have[:SHOWN_DEFAULT]


def check_selection(system: System, *, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
                    group: str | None = None) -> None:
    """ValueError, one line naming the bad value and the valid ones, for a method, instance or
    group ``system`` does not have, or for instances and a group both given (None: not given)."""
    from terrabench.benchmark.plan import check_group, split_ids

    check_group(system, group, instances)
    split_ids(methods, f"{system.id} method(s)", list(system.methods()))
    if instances is not None:
        system.select_instances(instances)


def select(rows: Sequence[dict[str, Any]], system: System, *, methods: Sequence[str] | None = None,
           instances: Sequence[str] | None = None, group: str | None = None) -> list[dict[str, Any]]:
    """The stored ``rows`` of those methods and instances (or the group's; None: every one)."""
    keep = set(instances) if instances is not None else set(system.instances(group)) if group is not None else None
    return [r for r in rows if (methods is None or r["method"] in methods) and (keep is None or r["instance"] in keep)]


def compare(rows: Sequence[dict[str, Any]], system: System, metrics: Sequence[str] | None = None) -> list[Line]:
    """One :class:`Line` per (instance, variant) of ``rows`` (one system's stored rows), in the
    instances' stored order, the variants of a method by their settings' values. ``metrics``
    (default: every numeric metric of the rows); a name no row has is bad input naming the ones
    they have."""
    names = metric_names(rows)
    if metrics is None:
        metrics = names
    else:
        bad = [m for m in metrics if m not in names]
        if bad:
            raise ValueError(f"no stored trial has the metric(s) {', '.join(map(repr, bad))}; "
                             f"valid: {', '.join(names) or 'none (no numeric metric stored)'}")
    variants = find_variants(rows, default_config=Defaults(system), order=list(system.methods()))
    rank = {m: i for i, m in enumerate(system.methods())}
    varied = {m: sorted({k for v in variants if v.method == m for k in v.diff}) for m in {v.method for v in variants}}
    # a sweep reads in the order of its values: within a method, the variants by their settings
    variants.sort(key=lambda v: (rank.get(v.method, len(rank)), v.method, _settings_order(v.config, varied[v.method])))
    out: list[Line] = []
    instances = list(dict.fromkeys(r["instance"] for r in rows))
    for inst in instances:
        here = [r for r in rows if r["instance"] == inst]
        for v in variants:
            rs = v.rows_of(here)
            if not rs:
                continue
            cells: dict[str, tuple[float, float, float] | None] = {}
            for m in metrics:
                xs = [x for x in (_number(r["metrics"].get(m)) for r in rs) if x is not None]
                cells[m] = (statistics.median(xs), min(xs), max(xs)) if xs else None
            out.append(Line(inst, v.method, v.label, dict(v.diff), len(rs),
                            dict(Counter(r["status"] for r in rs).most_common()), cells))
    return out


def cell_text(cell: tuple[float, float, float] | None) -> str:
    """``"0.282 [0.255, 0.296]"`` (median [min, max]); one value when they agree; ``-`` for none."""
    if cell is None:
        return "-"
    med, lo, hi = cell
    return f"{med:.4g}" if lo == hi else f"{med:.4g} [{lo:.4g}, {hi:.4g}]"


def statuses_text(line: Line) -> str:
    """``"success 4/5, timeout 1"``: the successes over the trials first, then the other statuses."""
    rest = [f"{s} {n}" for s, n in line.statuses.items() if s != "success"]
    return ", ".join([f"success {line.successes}/{line.n}"] + rest)


def write_csv(lines: Sequence[Line], path: Path) -> None:
    """One row per line: instance, method, variant label, its settings (JSON), n, successes,
    statuses (JSON), and per metric its median, min and max (empty where no trial has it)."""
    metrics = list(lines[0].metrics) if lines else []
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["instance", "method", "variant", "settings", "n", "successes", "statuses"]
                   + [f"{m}_{part}" for m in metrics for part in ("median", "min", "max")])
        for ln in lines:
            vals: list[Any] = []
            for m in metrics:
                c = ln.metrics.get(m)
                vals += list(c) if c is not None else ["", "", ""]
            w.writerow([ln.instance, ln.method, ln.label, canonical_json(dict(ln.settings)), ln.n, ln.successes,
                        canonical_json(dict(ln.statuses))] + vals)


def plot(lines: Sequence[Line], metrics: Sequence[str], path: Path) -> None:
    """One panel per metric: for each (instance, method), the median (marker) and the seeds' range
    (bar) of each of its variants, the settings along x (one tick per set of settings, shared by
    the methods); written as PNG at ``path``."""
    from matplotlib.figure import Figure

    ticks = list(dict.fromkeys(_short(ln.label) for ln in lines))
    series = list(dict.fromkeys((ln.instance, ln.method) for ln in lines))
    several = len({m for _, m in series}) > 1
    cols = min(3, len(metrics))
    rows = -(-len(metrics) // cols)
    fig = Figure(figsize=(4.2 * cols, 3.2 * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    width = 0.6 / max(len(series), 1)
    keys = {t.partition("=")[0] for t in ticks}
    one_key = len(keys) == 1 and all("=" in t and ", " not in t for t in ticks)
    names = [t.partition("=")[2] for t in ticks] if one_key else ticks  # one setting: its values on x
    for ax, m in zip(axes, metrics):
        for j, (inst, meth) in enumerate(series):
            xs, med, lo, hi = [], [], [], []
            for ln in lines:
                c = ln.metrics.get(m)
                if (ln.instance, ln.method) == (inst, meth) and c is not None:
                    xs.append(ticks.index(_short(ln.label)) + (j - (len(series) - 1) / 2) * width)
                    med.append(c[0])
                    lo.append(c[0] - c[1])
                    hi.append(c[2] - c[0])
            if xs:  # a series keeps its colour in every panel, also where another has no value
                ax.errorbar(xs, med, yerr=[lo, hi], fmt="o-", ms=4, capsize=2, lw=1, color=f"C{j % 10}",
                            label=f"{inst} {meth}" if several else inst)
        ax.set_title(m, fontsize="medium")
        ax.set_xticks(range(len(ticks)))
        ax.set_xticklabels(names, rotation=0 if one_key else 30, ha="center" if one_key else "right",
                           fontsize="small")
        if one_key:
            ax.set_xlabel(next(iter(keys)), fontsize="small")
        ax.grid(alpha=0.3)
    for ax in axes[len(metrics):]:
        ax.set_visible(False)
    seen: dict[str, Any] = {}
    for ax in axes[: len(metrics)]:
        for h, name in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(name, h)
    fig.legend(list(seen.values()), list(seen), loc="outside lower center", ncols=min(len(seen), 5) or 1,
               fontsize="small", frameon=False)
    fig.suptitle("median (marker) and range over seeds (bar)", fontsize="medium")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def _short(label: str) -> str:
    """A variant's settings without the method (``"clm (a=1, b=2)"`` -> ``"a=1, b=2"``)."""
    head, sep, rest = label.partition(" (")
    return rest[:-1] if sep and rest.endswith(")") else label
