"""The single-wheel testbed as a hallway Task: the soil forces enter through ``before_substep``.

The rig (:func:`add_rig`: carriage, sled, wheel, two velocity servos) holds a wheel under a vertical load on a
carriage; the carriage's speed servo imposes the slip, the wheel's servo a constant spin. Every
physics step, :class:`~terrabench.soil.mujoco_soil.SoilWheels` replaces the wheel's rigid
contact with the terramechanics forces. After ``settle_s`` the log is averaged over
``average_s``: drawbar pull (the force the carriage holds back), driving torque, sinkage, the
slip the rig actually ran at.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from terrabench.config import check_fields, param
from terrabench.sim.episode import Timing
from terrabench.sim.physics import PhysicsConfig
from terrabench.soil.mujoco_soil import SoilWheels, flat_ground
from terrabench.soil.table import cached_table
from terrabench.soil.terramechanics import SoilParams, WheelParams
from terrabench.systems.base import TaskBase

GRAVITY = 9.81


@dataclass(frozen=True)
class RigConfig:
    """Testbed settings."""

    omega: float = param(1.0, gt=0, unit="rad/s",
                         doc="wheel spin when driving; in skid the hub moves at r omega and the wheel spins at (1 + "
                             "s) omega")
    timestep: float = param(0.001, gt=0, unit="s", doc="MuJoCo step")
    settle_s: float = param(1.5, gt=0, unit="s", doc="time before averaging")
    average_s: float = param(0.5, gt=0, unit="s", doc="averaging window")
    kv_carriage: float = param(2e5, gt=0, unit="N s/m", doc="carriage velocity-servo gain")
    kv_wheel: float = param(2e4, gt=0, unit="N m s/rad", doc="wheel servo gain")
    carriage_mass: float = param(5.0, gt=0, unit="kg",
                                 doc="carriage mass (moves horizontally only, not part of the load)")

    def __post_init__(self) -> None:
        check_fields(self)


def add_rig(spec: mujoco.MjSpec, wheel: WheelParams, load: float, cfg: RigConfig = RigConfig()) -> None:
    """Add the rig (carriage, sled, wheel, two velocity servos) for a vertical ``load`` (N) to ``spec``."""
    sled_mass = load / GRAVITY - wheel.mass
    if sled_mass <= 0:
        raise ValueError(f"load={load!r} is invalid; valid range: load > wheel weight {wheel.mass * GRAVITY:.3g} N")
    car = spec.worldbody.add_body(name="carriage", pos=[0, 0, wheel.radius])
    car.add_joint(name="carriage_x", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[1, 0, 0])
    car.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.05, 0.05, 0.02], pos=[0, 0, 0.3],
                 mass=cfg.carriage_mass, contype=0, conaffinity=0)
    sled = car.add_body(name="sled")
    sled.add_joint(name="sled_z", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])
    sled.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.03, 0.03, 0.03], pos=[0, 0, 0.15],
                  mass=sled_mass, contype=0, conaffinity=0)
    wb = sled.add_body(name="wheel")
    wb.add_joint(name="wheel_spin", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
    wb.add_geom(name="wheel", type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[wheel.radius, wheel.width / 2, 0],
                quat=[np.sqrt(0.5), np.sqrt(0.5), 0, 0], mass=wheel.mass)
    for name, joint, kv in (("carriage_servo", "carriage_x", cfg.kv_carriage),
                            ("wheel_servo", "wheel_spin", cfg.kv_wheel)):
        act = spec.add_actuator(name=name, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_velocity(kv=kv)

COLUMNS = ("DP_N", "torque_Nm", "sinkage_m", "slip", "v_mps", "omega")


class RigTask(TaskBase):
    """One (soil, load, slip) point of the single-wheel sweep."""

    columns = COLUMNS

    def __init__(self, soil: SoilParams, wheel: WheelParams, load: float, slip: float, rig: RigConfig,
                 control_period: float):
        self.soil, self.wheel, self.load, self.slip, self.rig = soil, wheel, load, slip, rig
        self.physics = PhysicsConfig(timestep=rig.timestep, integrator="implicitfast")
        # the protocol ends the trial (status done, in check); the time limit is only a backstop
        self.duration = rig.settle_s + rig.average_s
        self.timing = Timing(control_period, self.duration + 2 * control_period, control_period, control_period)
        # driving: the wheel spins at omega; skid: the hub moves at r omega (locked wheel: spin 0)
        self.v = (1.0 - slip if slip >= 0 else 1.0) * wheel.radius * rig.omega
        self.omega = (1.0 if slip >= 0 else 1.0 + slip) * rig.omega

    def build(self, spec: mujoco.MjSpec) -> None:
        spec.modelname = f"single_wheel_{self.soil.name}"
        spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 1, 0.1], contype=0, conaffinity=0)
        add_rig(spec, self.wheel, self.load, self.rig)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData):
        self.model, self.data = model, data
        table = cached_table(self.soil, self.wheel)
        self.soil_wheels = SoilWheels(model, data, ["wheel"], self.wheel, table, flat_ground(), nominal_load=self.load)
        self.before_substep = self.soil_wheels.before_substep
        cdof, wdof = model.joint("carriage_x").dofadr[0], model.joint("wheel_spin").dofadr[0]
        # start at the static sinkage, moving: the transient is not what the sweep measures
        data.qpos[model.joint("sled_z").qposadr[0]] = -table.static_sinkage(self.load)
        data.qvel[cdof], data.qvel[wdof] = self.v, self.omega
        mujoco.mj_forward(model, data)
        self._dofs = (cdof, wdof)
        return data

    def observe(self):
        return self.data

    def check(self, obs, slow: bool):
        if self.data.time >= self.duration - 0.5 * self.timing.control_period:
            return "done", f"settled {self.rig.settle_s} s, averaged {self.rig.average_s} s"
        return None

    def apply(self, cmd) -> None:
        self.data.ctrl[:] = cmd

    def row(self, obs, cmd) -> tuple[float, ...]:
        d, truth = self.data, self.soil_wheels.truth
        cdof, wdof = self._dofs
        return (-d.actuator_force[0], d.actuator_force[1], truth["sinkage"][0], truth["slip"][0],
                d.qvel[cdof], d.qvel[wdof])

    def power(self, obs) -> float:
        return abs(self.data.actuator_force[1] * self.data.qvel[self._dofs[1]])

    def metrics(self, log) -> dict[str, float]:
        n_avg = max(1, int(round(self.rig.average_s / log.period)))
        tail = {c: float(np.mean(log.column(c)[-n_avg:])) for c in COLUMNS}
        dp, tq = tail["DP_N"], tail["torque_Nm"]
        eff = dp * tail["v_mps"] / (tq * tail["omega"]) if tq > 0 else float("nan")
        return {"DP_N": dp, "torque_Nm": tq, "sinkage_m": tail["sinkage_m"], "slip_measured": tail["slip"],
                "DP_coeff": dp / self.load, "efficiency": eff, "load_N": self.load, "slip": self.slip}

    def info(self) -> dict:
        return {"soil": self.soil.name, "source": self.soil.source}


class RigController:
    """Constant servo targets: carriage speed (m/s) for the slip, wheel spin (rad/s)."""

    def __init__(self, v: float, omega: float):
        self.cmd = np.array([v, omega])

    def __call__(self, obs) -> np.ndarray:
        return self.cmd
