"""The MRS-CWC benchmark scenario: 8 methods x 100 terrains (paper Section IV), as a hallway system."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from terrabench.benchmark.trial import TrialSpec
from terrabench.config import ConfigError, to_dict
from terrabench.systems.base import MethodInfo, System
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import METHODS, config_for, get_method
from terrabench.systems.mrs_cwc.task import MRSTask, make_controller
from terrabench.terrain import dataset

SCENARIO = "mrs-cwc/benchmark-v1"


class MRSCWCSystem(System):
    """The MRS-CWC chain on the 100 released terrains."""

    id = "mrs-cwc"
    status_notes = {"success": "leader within protocol.success_threshold of the target",
                    "fell": "leader below protocol.fall_z",
                    "stuck": "only with the opt-in protocol.stall_time > 0"}
    summary = ("Xiao et al., MRS-CWC: six two-wheeled robots joined by elastic links whose yaw stiffness is "
               "switched in real time; 100-terrain navigation benchmark, 8 methods")
    status = "platform, all 8 methods, our A* planner beside the released waypoints, report, env"
    config_cls = MRSConfig
    instance_format = "A-01 ... A-50 (group A), B-01 ... B-50 (group B): the released terrain rows"
    groups = {"A": "the released lessthan30 file, rows 1-50 (mean axis slope 0.3-29.0 deg)",
              "B": "the released morethan30 file, rows 1-50 (the paper's 'over 30 deg' group; "
                   "mean axis slope 29.3-44.1 deg)"}
    default_group = "all"
    timeout_key = "protocol.timeout"
    threshold_key = "protocol.success_threshold"
    headline_metrics = ("d_min", "NCR", "NEF", "NEC", "sim_time")
    env_ids = ("terrabench/MRSCWC-v1",)
    perf_instances = ("B-05", "B-15", "B-25", "B-35", "B-45")
    smoke = {"methods": ["cwc-tdt"], "instances": ["A-01"], "overrides": {"protocol.timeout": 1.0}}
    golden = ({"methods": ["cwc-tdt"], "instances": ["B-01"], "overrides": {"protocol.timeout": 8.0}},
              {"methods": ["d-astar"], "instances": ["A-02"], "overrides": {"protocol.timeout": 4.0}})

    def methods(self) -> dict[str, MethodInfo]:
        return {m.id: MethodInfo(m.id, f"{m.label}: {m.summary}",
                                 (m.variant, m.guidance) + (("map",) if m.guidance == "astar" else ()))
                for m in METHODS.values()}

    def default_methods(self) -> list[str]:
        return ["cwc-tdt"]

    def instances(self, group: str | None) -> list[str]:
        # terrain-major, groups interleaved (A-01, B-01, A-02, ...): a run cut short still
        # covers every method on the same terrains of both groups
        return [t.id for t in sorted(dataset.select(None, group), key=lambda t: (t.row, t.group))]

    def select_instances(self, ids: Sequence[str]) -> list[str]:
        items = [i for i in ids if i]
        if not items:
            raise ValueError("mrs-cwc terrains: an empty list was given; valid: A-01 ... A-50, B-01 ... B-50")
        return [t.id for t in sorted((dataset.get(i) for i in items), key=lambda t: (t.row, t.group))]

    def scenario(self, method: str, instance: str) -> str:
        return SCENARIO

    def trial_config(self, method: str, instance: str, cfg: MRSConfig) -> dict[str, Any]:
        # each trial stores (and is keyed by) only the config sections its method reads
        m = get_method(method)
        if m.variant == "spring" and cfg.chain.n_units < 2:  # checked when planned, not in the worker
            raise ConfigError("chain.n_units", cfg.chain.n_units, f"an integer >= 2 for {method} (a spring-linked "
                              "chain: its law reads the first yaw joint); 1 unit runs the MJ and D methods")
        return config_for(m, to_dict(cfg))

    def make_task(self, spec: TrialSpec, cfg: MRSConfig) -> MRSTask:
        if spec.seed:
            cfg = replace(cfg, protocol=jittered(cfg, spec.seed))
        return MRSTask(get_method(spec.method), dataset.get(spec.instance), cfg)

    def make_controller(self, spec: TrialSpec, cfg: MRSConfig, task: MRSTask):
        return make_controller(task.method, task.cfg, task.terrain)

    def env_adapter(self):
        from terrabench.systems.mrs_cwc.env import MRSEnvAdapter

        return MRSEnvAdapter()

    def render_overlay(self, task: MRSTask, obs) -> str:
        from terrabench.systems.mrs_cwc.env import overlay

        return overlay(task, obs)

    def summarize(self, rows: list[dict[str, Any]]):
        from terrabench.systems.mrs_cwc.summary import summary_table

        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.systems.mrs_cwc.report import write_report

        return write_report(store, Path(out_dir), render=True, system=self)


def jittered(cfg: MRSConfig, seed: int):
    """Seeds > 0 shift the start by up to ``protocol.start_jitter`` metres (seed 0 = as released)."""
    rng = np.random.default_rng(seed)
    j = cfg.protocol.start_jitter
    sx, sy = cfg.protocol.start_xy
    dx, dy = rng.uniform(-j, j, size=2)
    return replace(cfg.protocol, start_xy=(sx + float(dx), sy + float(dy)))


SYSTEM = MRSCWCSystem()
