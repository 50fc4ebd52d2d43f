"""The single-wheel soil testbed as a system: slip sweeps at several loads for each soil preset.

Instances are ``SOIL/W<load N>/s<slip>`` (e.g. ``mars_soft/W100/s0.20``); the group
``single-wheel`` is the grid below. Methods: ``rig`` (the MuJoCo testbed, soil forces in the
episode loop's per-substep hook) and ``analytic`` (the steady-state equations directly). The
soil ``custom`` takes its parameters from the ``custom_soil`` config section, e.g.
``--terrains custom/W100/s0.3 --set custom_soil.phi_deg=33``.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.config import to_dict
from terrabench.soil.presets import HIT_MRII_WHEEL, MARS_SOFT, SOILS
from terrabench.soil.terramechanics import SoilParams, WheelParams, steady_state
from terrabench.soil.testbed import GRAVITY, RigConfig
from terrabench.systems.base import MethodInfo, System, check_finite_positive

SCENARIO = "soil/single-wheel-v1"
LOADS = (50.0, 100.0, 150.0, 370.0)
SLIPS = (-0.2, -0.1, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)
#: documented slip range of an instance: skid down to -0.9, slip up to 1 (spinning in place)
SLIP_RANGE = (-0.9, 1.0)
_ID = re.compile(r"(?P<soil>[a-z_]+)/W(?P<load>[0-9.]+)/s(?P<slip>-?[0-9.]+)")


@dataclass(frozen=True)
class SoilTestbedConfig:
    """A single-wheel trial's config.

    Attributes:
        wheel: the rigid wheel (radius, width, mass).
        rig: testbed settings (spin, physics step, settle and averaging times, servo gains).
        control_period: how often the (constant) servo targets are re-applied and the log is
            sampled (s).
        custom_soil: parameters of the soil named ``custom`` in an instance id.
        soil: the soil this trial runs on: set by planning from the instance id (a preset, or
            ``custom_soil``), so the parameters are stored and hashed with the trial.
    """

    wheel: WheelParams = HIT_MRII_WHEEL
    rig: RigConfig = field(default_factory=RigConfig)
    control_period: float = 0.01
    custom_soil: SoilParams = replace(MARS_SOFT, name="custom", source="user-set (--set custom_soil.*)")
    soil: SoilParams = MARS_SOFT

    def __post_init__(self) -> None:
        check_finite_positive("control_period", self.control_period, "s")
        check_finite_positive("rig.settle_s", self.rig.settle_s, "s")
        check_finite_positive("rig.average_s", self.rig.average_s, "s")


def parse_instance(iid: str) -> tuple[str, float, float]:
    """``"mars_soft/W100/s0.20"`` -> (soil, load N, slip); ValueError naming what is wrong."""
    m = _ID.fullmatch(iid)
    if not m:
        raise ValueError(f"soil instance {iid!r} must look like SOIL/W<load N>/s<slip>, e.g. mars_soft/W100/s0.2")
    soil, load, slip = m["soil"], float(m["load"]), float(m["slip"])
    valid = sorted(SOILS) + ["custom"]
    if soil not in valid:
        raise ValueError(f"soil {soil!r} in {iid!r} is unknown; valid: {', '.join(valid)}")
    if not SLIP_RANGE[0] <= slip <= SLIP_RANGE[1]:
        raise ValueError(f"slip {slip} in {iid!r} is outside the documented range [{SLIP_RANGE[0]}, {SLIP_RANGE[1]}]")
    if not load > 0:
        raise ValueError(f"load {load} N in {iid!r} must be positive")
    return soil, load, slip


def instance_id(soil: str, load: float, slip: float) -> str:
    return f"{soil}/W{load:g}/s{slip:.2f}"


class SoilSystem(System):
    """Single-wheel terramechanics testbed (drawbar pull, torque, sinkage vs slip and load)."""

    id = "soil"
    summary = "Single rigid wheel on loose soil (Bekker / Wong-Reece / Janosi): slip and load sweeps"
    config_cls = SoilTestbedConfig
    groups = {"single-wheel": f"{len(SOILS)} soils x loads {LOADS} N x slips {SLIPS[0]}..{SLIPS[-1]}"}
    default_group = "single-wheel"
    headline_metrics = ("DP_N", "torque_Nm", "sinkage_m", "DP_coeff", "efficiency")
    perf_instances = ("mars_soft/W100/s0.20",)
    smoke = {"methods": ["rig"], "instances": ["mars_soft/W100/s0.20"], "overrides": {"rig.settle_s": 0.3, "rig.average_s": 0.1}}

    def methods(self) -> dict[str, MethodInfo]:
        return {"rig": MethodInfo("rig", "MuJoCo single-wheel rig, soil forces in the per-substep hook", ("mujoco",)),
                "analytic": MethodInfo("analytic", "steady-state terramechanics equations directly", ("analytic",))}

    def default_methods(self) -> list[str]:
        return ["rig", "analytic"]

    def instances(self, group: str | None) -> list[str]:
        return [instance_id(s, w, sl) for s in SOILS for w in LOADS for sl in SLIPS]

    def select_instances(self, ids: Sequence[str]) -> list[str]:
        items = [i for i in ids if i]
        if not items:
            raise ValueError("soil instances: an empty list was given; e.g. mars_soft/W100/s0.2")
        return [instance_id(*parse_instance(i)) for i in items]

    def scenario(self, method: str, instance: str) -> str:
        return SCENARIO

    def trial_config(self, method: str, instance: str, cfg: SoilTestbedConfig) -> dict[str, Any]:
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

        return RigController(task.v, task.rig.omega)

    def run_trial(self, spec: TrialSpec, *, on_step=None) -> TrialResult:
        if spec.method == "rig":
            return super().run_trial(spec, on_step=on_step)
        t0 = time.perf_counter()
        cfg = self.load_config(spec.config)
        soil, omega = cfg.soil, cfg.rig.omega
        _, load, slip = parse_instance(spec.instance)
        r = steady_state(load, slip, soil, cfg.wheel, omega)
        dp, tq, v = float(r["DP_N"]), float(r["torque_Nm"]), float(r["v_mps"])
        metrics = {"DP_N": dp, "torque_Nm": tq, "sinkage_m": float(r["sinkage_m"]), "slip_measured": slip,
                   "DP_coeff": dp / load, "efficiency": dp * v / (tq * omega) if tq > 0 else float("nan"),
                   "load_N": load, "slip": slip}
        return TrialResult("done", metrics, {}, time.perf_counter() - t0, {"soil": soil.name, "source": soil.source})

    def summarize(self, rows: list[dict[str, Any]]):
        from terrabench.systems.soil.report import summary_table

        return summary_table(rows)

    def report(self, store, out_dir: Path) -> Path:
        from terrabench.systems.soil.report import write_report

        return write_report(store, Path(out_dir))


SYSTEM = SoilSystem()
