"""The MRS-CWC benchmark scenario: 8 methods x 100 terrains (paper Section IV)."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path
from typing import Any, Sequence

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.config import from_dict, override, to_dict
from terrabench.metrics.navigation import group_summary
from terrabench.systems.mrs_cwc import trial
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import METHODS, config_for, get_method
from terrabench.systems.mrs_cwc.reference import METRIC_NAMES, paper_row
from terrabench.terrain import dataset

SCENARIO = "mrs-cwc/benchmark-v1"
DEFAULT_METHODS = ("cwc-tdt",)


class MRSCWCSystem:
    """The MRS-CWC chain on the 100 released terrains."""

    name = "mrs-cwc"
    scenario = SCENARIO
    timeout_key = "protocol.timeout"
    threshold_key = "protocol.success_threshold"
    headline_metrics = ("d_min", "NCR", "NEF", "NEC", "sim_time")

    def plan(
        self,
        *,
        methods: Sequence[str] | None = None,
        instances: Sequence[str] | None = None,
        group: str | None = None,
        seeds: int = 1,
        overrides: dict[str, Any] | None = None,
        config: MRSConfig | None = None,
    ) -> list[TrialSpec]:
        """Specs for methods x terrains x seeds. ``methods=["all"]`` means all eight."""
        if seeds < 1:
            raise ValueError(f"seeds must be at least 1, got {seeds}")
        mids = list(methods or DEFAULT_METHODS)
        if mids == ["all"]:
            mids = list(METHODS)
        for mid in mids:
            get_method(mid)
        terrains = dataset.select(instances, group)
        cfg = override(config or MRSConfig(), overrides or {})
        cfg_dict = to_dict(cfg)
        # terrain-major, groups interleaved (A-01, B-01, A-02, ...): a run cut short still
        # covers every method on the same terrains of both groups
        ordered = sorted(terrains, key=lambda t: (t.row, t.group))
        # each trial stores (and is keyed by) only the config sections its method reads
        per_method = {mid: config_for(get_method(mid), cfg_dict) for mid in mids}
        return [
            TrialSpec(self.name, SCENARIO, mid, t.id, seed, per_method[mid])
            for seed in range(seeds)
            for t in ordered
            for mid in mids
        ]

    def run_trial(self, spec: TrialSpec) -> TrialResult:
        t0 = time.perf_counter()
        cfg = from_dict(MRSConfig, spec.config)
        if spec.seed:
            cfg = replace(cfg, protocol=_jittered(cfg, spec.seed))
        status, metrics, series, info = trial.run(get_method(spec.method), dataset.get(spec.instance), cfg)
        return TrialResult(status, metrics, series, time.perf_counter() - t0, info)

    def summarize(self, rows: list[dict[str, Any]]):
        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.systems.mrs_cwc.report import write_report

        return write_report(store, Path(out_dir))


def _jittered(cfg: MRSConfig, seed: int):
    """Seeds > 0 shift the start by up to ``protocol.start_jitter`` metres (seed 0 = as released)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    j = cfg.protocol.start_jitter
    sx, sy = cfg.protocol.start_xy
    dx, dy = rng.uniform(-j, j, size=2)
    return replace(cfg.protocol, start_xy=(sx + float(dx), sy + float(dy)))


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


SYSTEM = MRSCWCSystem()
