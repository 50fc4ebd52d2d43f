"""The mobility map as a system: every robot's go-to-goal methods x every terrain family.

Methods are ``<robot>.<method>`` (``octopus.clm``) from the registered adapters
(:mod:`terrabench.zoo.adapter`); instances are ``FAMILY@SEVERITY`` (:mod:`terrabench.zoo.families`);
groups ``quick`` and ``full``. A pair whose family the robot cannot enter does not apply (the
planner skips it); a request made only of such pairs is refused with the adapters' reasons.

The stored config of a trial is ``{"course": ..., "protocol": ..., "robot": ...}``: the zoo's own
settings with ``protocol.timeout`` resolved at planning (``time_factor`` x the course's travel /
the robot's nominal speed + ``settle``) and the robot system's whole config (its defaults, as the
adapter gives them), so (system, method, instance, seed, config) determines the trial.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Mapping, Sequence

from terrabench.benchmark.trial import TrialSpec
from terrabench.config import from_dict, to_dict
from terrabench.systems.base import MethodInfo, System
from terrabench.zoo import families as fam
from terrabench.zoo.adapter import adapters, split_method
from terrabench.zoo.config import CourseConfig, ZooConfig

SCENARIO = "zoo/mobility-v1"


@dataclass(frozen=True)
class LoadedConfig:
    """A stored zoo config rebuilt: the zoo's own (validated) and the robot's (a dict, as stored)."""

    zoo: ZooConfig
    robot: Mapping[str, Any]


@functools.lru_cache(maxsize=512)
def _course(instance: str, robot: str, cc: CourseConfig, seed: int = 0):
    f, token = fam.parse_instance(instance)
    return f.course(token, adapters()[robot].footprint(), cc, seed)


def travel(course, fp) -> float:
    """Distance (m) the robot's rearmost point travels from the start to the goal line."""
    return float(course.goal_x - (course.start_front - fp.length))


class ZooSystem(System):
    """Every robot x every terrain family (issue 29)."""

    id = "zoo"
    summary = ("the mobility map: every robot (MRS-CWC chain, OCTOPUS, HIT-MRII) x 14 terrain families at "
               "graded severities, one protocol")
    status = ("families, courses, adapters for mrs-cwc, octopus, srwmr (beams: analytic model, none); "
              "quick/full groups (`docs/zoo.md`)")
    config_cls = ZooConfig
    groups = {"quick": "every family at 2-4 severities (`docs/zoo.md` for its cost)",
              "full": "every family at 5-8 severities"}
    default_group = "quick"
    timeout_key = "protocol.timeout"
    headline_metrics = ("success", "progress", "speed", "energy_per_m_kg", "max_pitch", "sim_time")
    instance_format = "FAMILY@SEVERITY, e.g. step-up@0.15, soft-flat@loose, rough-mrs@A"
    perf_instances = ("step-up@0.15", "rough-sine@0.05")
    realtime_factor = 3.0  # measured: OCTOPUS CLM on heightfields 4.0x, HIT-MRII on soil 4.5x (docs/zoo.md)
    status_notes = {"success": "the robot's rearmost point passed the goal line",
                    "stuck": "the rearmost point moved less than protocol.stuck_progress in protocol.stuck_time, "
                             "or the robot's own halt (the rover's health monitor)",
                    "fell": "a tracked body below the course's fall height, or out of the lane",
                    "turned_over": "|roll| or |pitch| beyond protocol.turn_over",
                    "timeout": "the scaled time limit (protocol.time_factor x nominal travel time + settle)"}
    smoke = {"methods": ["octopus.ccm"], "instances": ["step-up@0.05"], "overrides": {"protocol.timeout": 1.0}}
    golden = ({"methods": ["octopus.ccm", "mrs-cwc.cwc-tdt"], "instances": ["step-up@0.05"],
               "overrides": {"protocol.timeout": 2.0}},
              {"methods": ["srwmr.wrm"], "instances": ["soft-flat@loose"], "overrides": {"protocol.timeout": 2.0}})

    # ------------------------------------------------------------------ scenarios
    def methods(self) -> dict[str, MethodInfo]:
        out = {}
        for robot, ad in adapters().items():
            for m, text in ad.methods.items():
                mid = f"{robot}.{m}"
                out[mid] = MethodInfo(mid, f"{ad.label}: {text}", (robot,))
        return out

    def default_methods(self) -> list[str]:
        return [f"{r}.{m}" for r, ad in adapters().items() for m in (ad.default_methods or tuple(ad.methods))]

    def instances(self, group: str | None) -> list[str]:
        return fam.instances("quick" if group == "quick" else "full")

    def select_instances(self, ids: Sequence[str]) -> list[str]:
        from terrabench.benchmark.plan import check_id_list

        items = check_id_list(list(ids), "zoo instance(s)", lambda: self.instances(None), self.id) or []
        for i in items:
            fam.parse_instance(i)  # ValueError naming the form and the families
        return items

    def scenario(self, method: str, instance: str) -> str:
        return SCENARIO

    def reason(self, method: str, instance: str) -> str | None:
        """Why ``method`` cannot run ``instance`` (None: it can)."""
        ad, m = split_method(method)
        f, _ = fam.parse_instance(instance)
        return ad.method_reason(m, f.id)

    def applies(self, method: str, instance: str) -> bool:
        return self.reason(method, instance) is None

    def plan(self, *, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
             group: str | None = None, seeds: int = 1, overrides: Mapping[str, Any] | None = None) -> list[TrialSpec]:
        try:
            return super().plan(methods=methods, instances=instances, group=group, seeds=seeds, overrides=overrides)
        except ValueError as exc:
            if not str(exc).startswith("no zoo method") or instances is None:
                raise
            mids = list(self.methods()) if methods in (None, ["all"]) else list(methods or [])
            why = sorted({f"{m} on {i.partition('@')[0]}: {self.reason(m, i)}" for m in mids for i in instances
                          if self.reason(m, i)})
            raise ValueError(f"{exc}; why not: {'; '.join(why)}") from None

    def check_trial(self, method: str, instance: str, cfg: Any) -> None:
        ad, m = split_method(method)
        f, _ = fam.parse_instance(instance)
        ad.refuse(m, f.id)
        zoo = cfg.zoo if isinstance(cfg, LoadedConfig) else cfg
        _course(instance, ad.robot, zoo.course)  # a bad severity is refused here, before any simulation

    def time_limit(self, method: str, instance: str, zoo: ZooConfig) -> float:
        """The simulated time limit (s): ``protocol.timeout`` if set, else the scaled one."""
        if zoo.protocol.timeout is not None:
            return float(zoo.protocol.timeout)
        ad, _ = split_method(method)
        fp = ad.footprint()
        pr = zoo.protocol
        t = pr.time_factor * travel(_course(instance, ad.robot, zoo.course), fp) / fp.speed + pr.settle
        return float(math.ceil(t))

    def trial_config(self, method: str, instance: str, cfg: Any) -> dict[str, Any]:
        ad, m = split_method(method)
        if isinstance(cfg, LoadedConfig):
            zoo, robot = cfg.zoo, dict(cfg.robot)
        else:
            zoo, robot = cfg, ad.robot_config(m)
        out = to_dict(zoo)
        out["protocol"]["timeout"] = self.time_limit(method, instance, zoo)
        out["robot"] = robot
        return out

    def load_config(self, config: Mapping[str, Any]) -> LoadedConfig:
        own = {k: v for k, v in config.items() if k != "robot"}
        return LoadedConfig(from_dict(ZooConfig, own), dict(config.get("robot", {})))

    # ------------------------------------------------------------------ running
    def course_of(self, spec: TrialSpec, cfg: LoadedConfig):
        ad, _ = split_method(spec.method)
        return _course(spec.instance, ad.robot, cfg.zoo.course, int(spec.seed))

    def make_task(self, spec: TrialSpec, cfg: LoadedConfig):
        ad, m = split_method(spec.method)
        ad.refuse(m, fam.parse_instance(spec.instance)[0].id)
        zoo = cfg.zoo
        timeout = self.time_limit(spec.method, spec.instance, zoo)
        zoo = replace(zoo, protocol=replace(zoo.protocol, timeout=timeout))
        return ad.make_task(m, self.course_of(spec, cfg), cfg.robot, zoo, timeout, int(spec.seed))

    def make_controller(self, spec: TrialSpec, cfg: LoadedConfig, task):
        ad, m = split_method(spec.method)
        return ad.make_controller(m, task)

    # ------------------------------------------------------------------ results
    def summarize(self, rows: list[dict[str, Any]]):
        from terrabench.zoo.report import summary_table

        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.zoo.report import write_report

        return write_report(store, Path(out_dir), system=self)


SYSTEM = ZooSystem()
