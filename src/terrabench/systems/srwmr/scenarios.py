"""HIT-MRII scenarios: the paper's tasks (group ``tasks``) and the slope sweep (group ``slopes``).

Methods are the locomotion strategies the scripted operator uses: ``wrm`` (wheel rolling),
``wcm`` (crabbing), ``rclm`` (chassis lifting), ``rcm`` (creeping, entered from WRM when the
climbing efficiency drops below 10 %), ``swlm`` / ``dwlm`` (one wheel / a symmetric pair lifted with
the clutch engaged, :mod:`~terrabench.systems.srwmr.legged`). Each instance is registered with
the methods that apply to it and its time limit (:func:`~terrabench.systems.srwmr.layouts.instance`);
:meth:`SRWMRSystem.applies` reads the registry, and the planner keeps only the pairs that apply.
A method says what ends its trial (:attr:`~terrabench.systems.srwmr.methods.RoverMethod.goal_line`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from terrabench.benchmark.trial import TrialSpec
from terrabench.config import to_dict
from terrabench.systems.base import MethodInfo, System
from terrabench.systems.srwmr import ik_cases  # noqa: F401  (registers group "ik")
from terrabench.systems.srwmr.config import SRWMRConfig
from terrabench.systems.srwmr.layouts import entry, instance_ids, registered, start_burial, time_limit
from terrabench.systems.srwmr.methods import METHODS

SCENARIO = "srwmr/tasks-v1"
SLOPE_SCENARIO = "srwmr/slopes-v1"


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
        "ik": "the constraint-saturated IK at work: MC#3-#9 driven to their QP boundary, each with a -noqp twin",
        "steer": "in-place differential steering at 0.01 and 0.02 rad/s, the clearance held (sec. 8.6)",
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
        return instance_ids(None if group == "all" else group)

    def applies(self, method: str, instance: str) -> bool:
        return entry(instance, method) is not None

    def scenario(self, method: str, instance: str) -> str:
        return SLOPE_SCENARIO if registered(instance, method).group == "slopes" else SCENARIO

    def check_trial(self, method: str, instance: str, cfg: SRWMRConfig) -> None:
        """MC#1 on a ``scene.lift`` an instance's builder reads (T12, T13): one line naming the
        allowed lifts, before any simulation."""
        from terrabench.systems.srwmr.legged import check_lift

        lift = cfg.scene.lift
        if lift and registered(instance, method).uses_lift:
            try:
                check_lift(method.upper(), tuple(lift.split("+")))
            except ValueError as exc:
                raise ValueError(f"scene.lift={lift!r}: {exc}") from None

    def clip_events(self, row: Any, series: Any) -> dict[str, float]:
        """Besides start and end: ``switch`` (the first mode change, e.g. the supervisor's WRM ->
        RCM), ``creep`` (RCM's first period), ``lift`` (a wheel's soil load below 5 N in a legged
        mode: it has left the ground), ``halt`` (a health halt), each where it happens."""
        import numpy as np

        from terrabench.systems.srwmr.control import MODE_CODE
        from terrabench.systems.srwmr.robot import WHEELS

        ev = super().clip_events(row, series)
        t = np.asarray(series.get("t", ()), float)
        mode = np.asarray(series.get("mode", ()), float)
        if not t.size or mode.size != t.size:
            return ev

        def first(mask) -> None | float:
            i = np.flatnonzero(mask)
            return float(t[i[0]]) if i.size else None

        found = {
            "switch": first(mode != mode[0]),
            "creep": first(mode == MODE_CODE["RCM"]),
            "halt": first(mode == MODE_CODE["HALT"]),
        }
        legged = (mode == MODE_CODE["SWLM"]) | (mode == MODE_CODE["DWLM"])
        lifts = []
        for c in WHEELS:  # a wheel that carried load (> 50 N) and then none (< 5 N) in a legged mode
            w = np.asarray(series.get(f"W_{c}", ()), float)
            if w.size == t.size and (w > 50.0).any():
                after = np.arange(t.size) > np.flatnonzero(w > 50.0)[0]
                lifts.append(first(legged & after & (w < 5.0)))
        found["lift"] = min((x for x in lifts if x is not None), default=None)
        ev.update({k: v for k, v in found.items() if v is not None})
        return ev

    def trial_config(self, method: str, instance: str, cfg: SRWMRConfig) -> dict[str, Any]:
        """The whole resolved config, ``protocol.timeout`` and ``scene.burial`` the instance's own
        unless one was set."""
        out = to_dict(cfg)
        out["protocol"]["timeout"] = time_limit(cfg, instance, method)
        out["scene"]["burial"] = start_burial(cfg, instance, method)
        return out

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
