"""The single-wheel soil testbed as a system: slip sweeps at several loads for each soil preset.

Instances are ``SOIL/W<load N>/s<slip>`` (e.g. ``mars_soft/W100/s0.20``); the group
``single-wheel`` is the grid below. Methods: ``rig`` (the MuJoCo testbed, soil forces in the
episode loop's per-substep hook) and ``analytic`` (the steady-state equations directly). The
soil ``custom`` takes its parameters from the ``custom_soil`` config section, e.g.
``--terrains custom/W100/s0.3 --set custom_soil.phi_deg=33``.

The group ``cmu-smooth`` holds one instance per measured CMU trial, ``cmu/b<slip angle>/t<trial>``
(e.g. ``cmu/b30/t012``), run by the methods ``cmu-authors`` and ``cmu-fit-b0`` (the two parameter
sets of :mod:`terrabench.systems.soil.cmu`); each trial stores the measured and the modelled
drawbar pull, lateral force and sinkage (and the modelled torque: none was measured).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.config import check_fields, param, to_dict
from terrabench.soil.presets import HIT_MRII_WHEEL, MARS_SOFT, SOILS
from terrabench.soil.terramechanics import SoilParams, WheelParams, steady_state
from terrabench.systems.base import MethodInfo, System
from terrabench.systems.soil.instances import (  # noqa: F401
    CMU_METHODS,
    LOADS,
    RIG_METHODS,
    SLIP_RANGE,
    SLIPS,
    cmu_instances,
    instance_id,
    parse_cmu,
    parse_instance,
)
from terrabench.systems.soil.task import GRAVITY, RigConfig

SCENARIO = "soil/single-wheel-v1"


@dataclass(frozen=True)
class SoilTestbedConfig:
    """A single-wheel trial's config: the rigid ``wheel``, the testbed settings (``rig``), the
    parameters of the soil named ``custom`` in an instance id (``custom_soil``) and the soil this
    trial runs on (``soil``: set by planning from the instance id, a preset or ``custom_soil``, so
    the parameters are stored and hashed with the trial)."""

    wheel: WheelParams = HIT_MRII_WHEEL
    rig: RigConfig = field(default_factory=RigConfig)
    control_period: float = param(0.01, gt=0, unit="s",
                                  doc="how often the (constant) servo targets are re-applied and the log is sampled")
    custom_soil: SoilParams = replace(MARS_SOFT, name="custom", source="user-set (--set custom_soil.*)")
    soil: SoilParams = MARS_SOFT

    def __post_init__(self) -> None:
        check_fields(self)


class SoilSystem(System):
    """Single-wheel terramechanics testbed (drawbar pull, torque, sinkage vs slip and load)."""

    id = "soil"
    summary = ("the hallway's wheel-soil terramechanics (Bekker / Reece, Wong-Reece, Janosi, slip-sinkage) on a "
               "single rigid wheel: a MuJoCo testbed and the steady-state equations")
    status = ("drawbar pull, torque, sinkage vs slip and load for every soil preset (rig and equations); the CMU "
              "smooth-wheel trials beside the model (`docs/soil.md`)")
    config_cls = SoilTestbedConfig
    instance_format = ("single-wheel: SOIL/W<load N>/s<slip> (a preset or custom; any load > 0, slip in [-1, 1]), "
                       "e.g. mars_soft/W100/s0.2; cmu-smooth: cmu/b<slip angle deg>/t<trial>, e.g. cmu/b30/t012")
    groups = {"single-wheel": f"{len(SOILS)} soils x loads {LOADS} N x slips {SLIPS[0]}..{SLIPS[-1]}",
              "cmu-smooth": "the 189 measured CMU smooth-wheel trials (slip -1..0.9, slip angle 0-90 deg) "
                            "beside the model"}
    default_group = "single-wheel"
    headline_metrics = ("DP_N", "torque_Nm", "sinkage_m", "DP_coeff", "efficiency")
    perf_instances = ("mars_soft/W100/s0.20",)
    smoke = {"methods": ["rig"], "instances": ["mars_soft/W100/s0.20"],
             "overrides": {"rig.settle_s": 0.3, "rig.average_s": 0.1}}
    #: a --set key and two values whose smoke runs the report shows as two variants (the test in
    #: tests/report/test_report_variants.py): the soil rig has no timeout to vary
    report_variant = ("rig.average_s", 0.1, 0.15)
    golden = ({"methods": ["rig"], "instances": ["mars_soft/W100/s0.20"],
               "overrides": {"rig.settle_s": 0.5, "rig.average_s": 0.3}},
              {"methods": ["cmu-fit-b0"], "instances": ["cmu/b0/t029"]})

    def methods(self) -> dict[str, MethodInfo]:
        return {"rig": MethodInfo("rig", "MuJoCo single-wheel rig, soil forces in the per-substep hook", ("mujoco",)),
                "analytic": MethodInfo("analytic", "steady-state terramechanics equations directly", ("analytic",)),
                "cmu-authors": MethodInfo("cmu-authors", "CMU trial vs the model with the authors' tuned parameters",
                                          ("cmu",)),
                "cmu-fit-b0": MethodInfo("cmu-fit-b0", "CMU trial vs the model fitted on slip angle 0", ("cmu",))}

    def default_methods(self) -> list[str]:
        return list(RIG_METHODS + CMU_METHODS)

    def instances(self, group: str | None) -> list[str]:
        grid = [instance_id(s, w, sl) for s in SOILS for w in LOADS for sl in SLIPS]
        if group == "single-wheel":
            return grid
        if group == "cmu-smooth":
            return cmu_instances()
        return grid + cmu_instances()

    def select_instances(self, ids: Sequence[str]) -> list[str]:
        items = [i for i in ids if i]
        if not items:
            raise ValueError("soil instances: an empty list was given; e.g. mars_soft/W100/s0.2 or cmu/b30/t012")
        out = []
        for i in items:
            if i.startswith("cmu/"):
                t = parse_cmu(i)
                out.append(f"cmu/b{i.split('/')[1][1:]}/t{t:03d}")
            else:
                out.append(instance_id(*parse_instance(i)))
        return out

    def seeds_for(self, method: str, instance: str, config: dict[str, Any], seeds: int) -> range:
        # the CMU parameter sets run only on CMU trials, the rig and the equations only on the grid
        is_cmu = instance.startswith("cmu/")
        return range(1) if (method in CMU_METHODS) == is_cmu else range(0)

    def scenario(self, method: str, instance: str) -> str:
        return SCENARIO

    def trial_config(self, method: str, instance: str, cfg: SoilTestbedConfig) -> dict[str, Any]:
        if instance.startswith("cmu/"):
            from terrabench.systems.soil.cmu import points, soil_for

            if method not in CMU_METHODS:
                return to_dict(cfg)  # not run (seeds_for is empty)
            beta = int(points()["beta_deg"][parse_cmu(instance)])
            return to_dict(replace(cfg, soil=soil_for(method, beta)))
        if method in CMU_METHODS:
            return to_dict(cfg)  # not run
        soil, load, _ = parse_instance(instance)
        if not load > cfg.wheel.mass * GRAVITY:
            raise ValueError(f"load {load} N in {instance!r} must exceed the wheel's weight "
                             f"{cfg.wheel.mass * GRAVITY:.3g} N")
        # the soil the trial runs on is part of its config (stored and hashed)
        return to_dict(replace(cfg, soil=cfg.custom_soil if soil == "custom" else SOILS[soil]))

    def make_task(self, spec: TrialSpec, cfg: SoilTestbedConfig):
        from terrabench.systems.soil.task import RigTask

        _, load, slip = parse_instance(spec.instance)
        return RigTask(cfg.soil, cfg.wheel, load, slip, cfg.rig, cfg.control_period)

    def make_controller(self, spec: TrialSpec, cfg: SoilTestbedConfig, task):
        from terrabench.systems.soil.task import RigController

        return RigController(task.v, task.omega)

    def run_trial(self, spec: TrialSpec, *, on_step=None) -> TrialResult:
        if spec.method == "rig":
            return super().run_trial(spec, on_step=on_step)
        if spec.method in CMU_METHODS:
            return self._run_cmu(spec)
        t0 = time.perf_counter()
        cfg = self.load_config(spec.config)
        soil, omega = cfg.soil, cfg.rig.omega
        _, load, slip = parse_instance(spec.instance)
        r = steady_state(load, slip, soil, cfg.wheel, omega)
        dp, tq = float(r["DP_N"]), float(r["torque_Nm"])
        metrics = {"DP_N": dp, "torque_Nm": tq, "sinkage_m": float(r["sinkage_m"]), "slip_measured": slip,
                   "DP_coeff": dp / load, "efficiency": float(r["efficiency"]),
                   "load_N": load, "slip": slip}
        return TrialResult("done", metrics, {}, time.perf_counter() - t0, {"soil": soil.name, "source": soil.source})

    def _run_cmu(self, spec: TrialSpec) -> TrialResult:
        from terrabench.systems.soil import cmu

        t0 = time.perf_counter()
        i = parse_cmu(spec.instance)
        p = cmu.points()
        m = cmu.model_point(spec.method, i)
        fitted = spec.method == "cmu-fit-b0" and int(p["beta_deg"][i]) in cmu.FIT_BETAS
        metrics = {"beta_deg": float(p["beta_deg"][i]), "slip": float(p["slip"][i]), "slip_model": float(p["s"][i]),
                   "lateral_ratio": float(min(p["C"][i], 1e6)), "load_N": float(p["load_N"][i]),
                   "DP_meas_N": float(p["DP_N"][i]), "lateral_meas_N": float(p["lateral_N"][i]),
                   "sinkage_meas_m": float(p["sinkage_m"][i]), "DP_N": m["DP_N"], "lateral_N": m["lateral_N"],
                   "sinkage_m": m["sinkage_m"], "torque_Nm": m["torque_Nm"], "sinkage_capped": m["sinkage_capped"],
                   "fitted": float(fitted), "DP_coeff": m["DP_N"] / float(p["load_N"][i])}
        cfg = self.load_config(spec.config)
        return TrialResult("done", metrics, {}, time.perf_counter() - t0,
                           {"soil": cfg.soil.name, "source": cfg.soil.source, "data": "robomechanics/3d-terramechanics "
                            "all_smooth_data.mat (MIT)", "trial": i})

    def summarize(self, rows: list[dict[str, Any]]):
        from terrabench.systems.soil.report import summary_table

        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.systems.soil.report import write_report

        return write_report(store, Path(out_dir), system=self)


SYSTEM = SoilSystem()
