"""OCTOPUS scenarios: the paper's three step tasks, the rough-road block, a step-height sweep."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from terrabench.benchmark.trial import TrialSpec
from terrabench.systems.base import MethodInfo, System
from terrabench.systems.octopus.ccm import CCMController
from terrabench.systems.octopus.clm import DRIVE_ON, CLMController
from terrabench.systems.octopus.config import OctopusConfig
from terrabench.systems.octopus.task import ROUGH_LEVELS, OctopusTask

SCENARIO = "octopus/steps-v1"
SWEEP_SCENARIO = "octopus/sweep-v1"
STEP_TASKS = ("step-400", "terrace2-front", "terrace2-side", "block-500")
SWEEP_HEIGHTS_MM = tuple(range(100, 551, 50))
SWEEP_TASKS = tuple(f"sweep-h{h}" for h in SWEEP_HEIGHTS_MM)
ROUGH_SCENARIO = "octopus/rough-v1"
ROUGH_TASKS = tuple(ROUGH_LEVELS)
METHODS = {
    "clm": MethodInfo("clm", "compound locomotion mode: arms walk and lift, flippers crawl (Chen et al.)", ("arms",)),
    "ccm": MethodInfo("ccm", "crawler-only mode: automated flipper step climbing (Nagatani/Okada stand-in)",
                      ("crawler",)),
}


class OctopusSystem(System):
    """The OCTOPUS arm-and-flipper crawler on steps, terraces and a block."""

    id = "octopus"
    status_notes = {"success": "on top, past the edge and stable for protocol.success_hold",
                    "stuck": "no progress for protocol.stuck_time",
                    "turned_over": "|roll| beyond protocol.turn_over or |pitch| beyond 1.6 rad (task.TURN_OVER_PITCH): "
                                   "the last-resort guard",
                    "tipped_back": "the COG passed behind the rearmost contact loaded > 20 N, a rear end of the "
                                   "robot (rear flipper, rear track pulley, rear arm tip), nose up and rising, for "
                                   "0.2 s (task.TIP_BACK_HOLD)"}
    summary = ("Chen, Kamezaki et al., OCTOPUS: four arms walk while four flippers crawl (compound locomotion), "
               "400 mm steps without vision")
    status = ("robot, scenes, CLM and CCM controllers, stability margin, report, env "
              "(`docs/octopus.md` for what climbs)")
    config_cls = OctopusConfig
    groups = {"steps": "the paper's tasks: step-400, terrace2-front, terrace2-side, block-500",
              "sweep": "step heights 100-550 mm in 50 mm (sweep-h100 ... sweep-h550)",
              "rough": "beyond the paper: 1.5 m over sine-sum rough ground, normalised height 0.01/0.02/0.04 "
                       "(rough-1..3), a new terrain per seed"}
    default_group = "steps"
    timeout_key = "protocol.timeout"
    headline_metrics = ("max_pitch", "max_roll", "min_margin", "progress", "sim_time")
    perf_instances = ("step-400", "block-500")
    env_ids = ("terrabench/Octopus-v1",)
    smoke = {"methods": ["clm"], "instances": ["step-400"], "overrides": {"protocol.timeout": 2.0}}
    golden = ({"methods": ["clm", "ccm"], "instances": ["step-400"], "overrides": {"protocol.timeout": 4.0}},)

    def methods(self) -> dict[str, MethodInfo]:
        return dict(METHODS)

    def clip_events(self, row: Any, series: Any) -> dict[str, float]:
        """Besides start and end, read off the stored controller events: ``climb`` (CLM's first
        walk -> climb, the climb of Fig. 9 starting), ``over`` (its front pulley over the top,
        the front arms unloading), ``release`` (its first climb -> release), ``walk_on`` (back to
        walking on the top); ``press`` and ``abort`` (CCM's first press at a riser and its
        tip-back abort); ``tipped_back`` (the tip-back rule's crossing, from the trial's info);
        ``rear_up`` (the first stored row of a climb's drive on, the stored ``climb_stage``: the
        rear lift of eq. 28 ended, so ``over`` to ``rear_up`` is the rear lift)."""
        ev = super().clip_events(row, series)
        info = (row.get("info") or {}) if hasattr(row, "get") else {}
        wanted = {"climb": lambda e: e[1] == "walk" and e[2] == "climb",
                  "over": lambda e: e[1] == e[2] == "climb" and "over the top" in e[3],
                  "release": lambda e: e[1] == "climb" and e[2] == "release",
                  "walk_on": lambda e: e[1] == "release" and e[2] == "walk",
                  "press": lambda e: e[2] == "press",
                  "abort": lambda e: e[2] == "abort"}
        for e in info.get("events") or ():
            for name, match in wanted.items():
                if name not in ev and len(e) >= 4 and match(e):
                    ev[name] = float(e[0])
        tb = info.get("tip_back")
        if tb and "t" in tb:
            ev["tipped_back"] = float(tb["t"])
        stage = np.asarray(series.get("climb_stage", ()), float)
        up = np.flatnonzero(stage == DRIVE_ON)
        if up.size:
            ev["rear_up"] = float(np.asarray(series["t"], float)[up[0]])
        return ev

    def default_methods(self) -> list[str]:
        return ["clm", "ccm"]

    def instances(self, group: str | None) -> list[str]:
        if group == "steps":
            return list(STEP_TASKS)
        if group == "sweep":
            return list(SWEEP_TASKS)
        if group == "rough":
            return list(ROUGH_TASKS)
        return list(STEP_TASKS) + list(SWEEP_TASKS) + list(ROUGH_TASKS)

    def scenario(self, method: str, instance: str) -> str:
        if instance.startswith("rough-"):
            return ROUGH_SCENARIO
        return SWEEP_SCENARIO if instance.startswith("sweep-") else SCENARIO

    def make_task(self, spec: TrialSpec, cfg: OctopusConfig) -> OctopusTask:
        return OctopusTask(spec.method, spec.instance, cfg, spec.seed)

    def make_controller(self, spec: TrialSpec, cfg: OctopusConfig, task: OctopusTask):
        if spec.method == "clm":
            return CLMController(cfg.clm, cfg.robot, cfg.protocol.control_period)
        if spec.method == "ccm":
            return CCMController(cfg.ccm, cfg.protocol.control_period, cfg.robot)
        raise ValueError(f"unknown octopus method {spec.method!r}; valid: {', '.join(METHODS)}")

    def env_adapter(self):
        from terrabench.systems.octopus.env import OctopusEnvAdapter

        return OctopusEnvAdapter()

    def summarize(self, rows: list[dict[str, Any]]):
        from terrabench.systems.octopus.report import summary_table

        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.systems.octopus.report import write_report

        return write_report(store, Path(out_dir), system=self)


SYSTEM = OctopusSystem()
