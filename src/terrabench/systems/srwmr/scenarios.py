"""HIT-MRII scenarios: the paper's tasks (group ``tasks``) and the slope sweep (group ``slopes``).

Methods are the locomotion strategies the scripted operator uses: ``wrm`` (wheel rolling),
``wcm`` (crabbing), ``rclm`` (chassis lifting), ``rcm`` (creeping, entered from WRM when the
climbing efficiency drops below 10 %), ``swlm`` / ``dwlm`` (one wheel / a symmetric pair lifted with
the clutch engaged, :mod:`~terrabench.systems.srwmr.legged`). Each instance lists the methods that apply to it
(:data:`~terrabench.systems.srwmr.layouts.APPLIES`); planning drops the other pairs.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from terrabench.benchmark.trial import TrialSpec
from terrabench.systems.base import MethodInfo, System
from terrabench.systems.srwmr.config import SRWMRConfig

SCENARIO = "srwmr/tasks-v1"
SLOPE_SCENARIO = "srwmr/slopes-v1"
METHODS = {
    "wrm": MethodInfo(
        "wrm", "wheel rolling mode (straight, Ackermann path), health halt at body slip 0.96", ("wheels",)
    ),
    "wcm": MethodInfo("wcm", "wheel crabbing mode: steer +-90 deg, roll sideways, steer back", ("wheels",)),
    "rclm": MethodInfo(
        "rclm", "robot chassis lifting mode: raise/lower the chassis, wheels coordinated (MC#2)", ("suspension",)
    ),
    "rcm": MethodInfo(
        "rcm", "robot creeping mode (inchworm), entered from WRM below 10 % climbing efficiency", ("suspension",)
    ),
    "swlm": MethodInfo(
        "swlm", "single wheel legged mode: CoM shift, clutch, lift one wheel (MC#1), roll, lower, release",
        ("suspension", "clutch"),
    ),
    "dwlm": MethodInfo(
        "dwlm", "double wheel legged mode: as SWLM with a symmetric pair (c1+c2, c3+c4, c5+c6)",
        ("suspension", "clutch"),
    ),
}


class SRWMRSystem(System):
    """The HIT-MRII reconfigurable rover on loose soil."""

    id = "srwmr"
    status_notes = {"success": "the chassis passed the task's goal line, or the plan ended at it",
                    "stuck": "a health halt (body slip >= supervisor.health_slip) or a plan ended short of the goal",
                    "turned_over": "|roll| or |pitch| beyond protocol.turn_over"}
    summary = ("Qi et al., HIT-MRII: a six-wheeled rover with active rockers and passive clutched bogies, "
               "constraint-saturated inverse kinematics, locomotion modes on loose soil")
    status = ("rover, kinematics, MC#1-#11, DAQP-saturated IK, WRM/WCM/RCLM/RCM and the wheel-legged SWLM/DWLM "
              "with the supervisor, the paper's tasks T1-T15 and a slope sweep, report, env "
              "(`docs/srwmr.md` for what is and is not reproduced)")
    config_cls = SRWMRConfig
    groups = {
        "tasks": "the paper's tasks a simulation repeats (T1-T15)",
        "slopes": "success and slip vs slope 0-25 deg on very loose and loose soil (WRM vs RCM)",
    }
    default_group = "tasks"
    timeout_key = "protocol.timeout"
    headline_metrics = ("body_slip", "progress", "distance", "energy_kJ", "W_diff_max", "sim_time")
    perf_instances = ("t1-loose",)
    realtime_factor = 10.0  # `terrabench perf srwmr`: 10-12x real time per core (docs/srwmr.md)
    env_ids = ("terrabench/SRWMR-v1",)
    smoke = {"methods": ["wrm"], "instances": ["t1-loose"], "overrides": {"protocol.timeout": 3.0}}
    golden = ({"methods": ["wrm"], "instances": ["t1-loose"], "overrides": {"protocol.timeout": 4.0}},
              {"methods": ["rcm"], "instances": ["t4-sinkage"], "overrides": {"protocol.timeout": 4.0}})

    def methods(self) -> dict[str, MethodInfo]:
        return dict(METHODS)

    def instances(self, group: str | None) -> list[str]:
        from terrabench.systems.srwmr.layouts import LEGGED_TASKS, SLOPES, TASKS

        if group == "tasks":
            return list(TASKS) + list(LEGGED_TASKS)
        if group == "slopes":
            return list(SLOPES)
        return list(TASKS) + list(LEGGED_TASKS) + list(SLOPES)

    def scenario(self, method: str, instance: str) -> str:
        return SLOPE_SCENARIO if instance.startswith("slope-") else SCENARIO

    def plan(
        self,
        *,
        methods: Sequence[str] | None = None,
        instances: Sequence[str] | None = None,
        group: str | None = None,
        seeds: int = 1,
        overrides=None,
    ) -> list[TrialSpec]:
        from terrabench.systems.srwmr.layouts import APPLIES

        specs = super().plan(methods=methods, instances=instances, group=group, seeds=seeds, overrides=overrides)
        kept = [s for s in specs if s.method in APPLIES.get(s.instance, ())]
        if specs and not kept:
            asked = sorted({s.instance for s in specs})
            valid = "; ".join(f"{i}: {', '.join(APPLIES.get(i, ()))}" for i in asked)
            raise ValueError(f"no requested method applies to the requested instance(s); valid: {valid}")
        self._check_lifts(kept)
        return kept

    def _check_lifts(self, specs) -> None:
        """MC#1 and the legged modes' lift rules, before any simulation (one line naming the allowed
        lifts): each legged trial's plan is built and checked."""
        from terrabench.systems.srwmr.layouts import layout
        from terrabench.systems.srwmr.legged import LEGGED, check_lift

        for s in specs:
            if s.method.upper() not in LEGGED:
                continue
            cfg = self.load_config(s.config)
            lay = layout(s.instance, s.method, cfg.robot, cfg.scene.approach, cfg.scene.lift)
            for st in lay.plan:
                if st.mode in LEGGED:
                    try:
                        check_lift(st.mode, st.lift)
                    except ValueError as exc:
                        raise ValueError(f"scene.lift={cfg.scene.lift!r}: {exc}") from None

    def make_task(self, spec: TrialSpec, cfg: SRWMRConfig):
        from terrabench.systems.srwmr.task import SRWMRTask

        return SRWMRTask(spec.method, spec.instance, cfg, spec.seed)

    def make_controller(self, spec: TrialSpec, cfg: SRWMRConfig, task):
        from terrabench.systems.srwmr.control import RoverController

        if spec.method not in METHODS:
            raise ValueError(f"unknown srwmr method {spec.method!r}; valid: {', '.join(METHODS)}")
        return RoverController(
            list(task.layout.plan), cfg.robot, cfg.supervisor, cfg.limits, cfg.scales, cfg.protocol.control_period
        )

    def env_adapter(self):
        from terrabench.systems.srwmr.env import SRWMREnvAdapter

        return SRWMREnvAdapter()

    def summarize(self, rows: list[dict[str, Any]]):
        from terrabench.systems.srwmr.report import summary_table

        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.systems.srwmr.report import write_report

        return write_report(store, Path(out_dir), system=self)


SYSTEM = SRWMRSystem()
