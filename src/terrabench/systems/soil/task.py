"""The single-wheel testbed as a hallway Task: the soil forces enter through ``before_substep``.

The rig (:func:`terrabench.soil.testbed.add_rig`) holds a wheel under a vertical load on a
carriage; the carriage's speed servo imposes the slip, the wheel's servo a constant spin. Every
physics step, :class:`~terrabench.soil.mujoco_soil.SoilWheels` replaces the wheel's rigid
contact with the terramechanics forces. After ``settle_s`` the log is averaged over
``average_s``: drawbar pull (the force the carriage holds back), driving torque, sinkage, the
slip the rig actually ran at.
"""

from __future__ import annotations

import functools

import mujoco
import numpy as np

from terrabench.sim.episode import Timing
from terrabench.sim.physics import PhysicsConfig
from terrabench.soil.mujoco_soil import SoilWheels, flat_ground
from terrabench.soil.table import SoilTable
from terrabench.soil.terramechanics import SoilParams, WheelParams, kappa_from_slip
from terrabench.soil.testbed import RigConfig, add_rig
from terrabench.systems.base import TaskBase

@functools.lru_cache(maxsize=8)
def soil_table(soil: SoilParams, wheel: WheelParams) -> SoilTable:
    """The (sinkage, slip) look-up table of a soil and wheel, built once per process."""
    return SoilTable(soil, wheel)


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
        self.v = float(kappa_from_slip(slip)) * wheel.radius * rig.omega

    def build(self, spec: mujoco.MjSpec) -> None:
        spec.modelname = f"single_wheel_{self.soil.name}"
        spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 1, 0.1], contype=0, conaffinity=0)
        add_rig(spec, self.wheel, self.load, self.rig)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData):
        self.model, self.data = model, data
        table = soil_table(self.soil, self.wheel)
        self.soil_wheels = SoilWheels(model, data, ["wheel"], self.wheel, table, flat_ground(), nominal_load=self.load)
        self.before_substep = self.soil_wheels.before_substep
        cdof, wdof = model.joint("carriage_x").dofadr[0], model.joint("wheel_spin").dofadr[0]
        # start at the static sinkage, moving: the transient is not what the sweep measures
        data.qpos[model.joint("sled_z").qposadr[0]] = -table.static_sinkage(self.load)
        data.qvel[cdof], data.qvel[wdof] = self.v, self.rig.omega
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
