"""Single-wheel testbed: a MuJoCo rig and the analytic steady state it should reproduce.

The rig (``build_rig``): world -> ``carriage`` (slide x, velocity-servoed to impose slip)
-> ``sled`` (free slide z, carries the load) -> ``wheel`` (hinge y, velocity-servoed to a
constant omega). Load = (sled + wheel mass) x g. In steady state the carriage servo holds
back the drawbar pull (DP = -carriage force) and the wheel servo supplies the soil's
resisting torque (T = wheel actuator force). Wheel forces come from
:class:`~terrabench.soil.mujoco_soil.SoilWheels` on a flat plane at z = 0.

Both sweeps return rows (dicts) with: soil, load_N, slip, DP_N, torque_Nm, sinkage_m,
DP_coeff, efficiency, source ("analytic" | "mujoco"); the MuJoCo rows also carry
slip_measured (the slip the rig actually ran at, from its measured speeds).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

import mujoco
import numpy as np

from terrabench.soil.mujoco_soil import SoilWheels, flat_ground
from terrabench.soil.table import SoilTable
from terrabench.soil.terramechanics import SoilParams, WheelParams, kappa_from_slip, steady_state

GRAVITY = 9.81


@dataclass(frozen=True)
class RigConfig:
    """Testbed settings.

    Attributes:
        omega: wheel spin (rad/s).
        timestep: MuJoCo step (s).
        settle_s: time before averaging (s).  average_s: averaging window (s).
        kv_carriage: carriage velocity-servo gain (N s/m).  kv_wheel: wheel servo gain (N m s/rad).
        carriage_mass: (kg); moves horizontally only, not part of the load.
    """

    omega: float = 1.0
    timestep: float = 0.001
    settle_s: float = 1.5
    average_s: float = 0.5
    kv_carriage: float = 2e5
    kv_wheel: float = 2e4
    carriage_mass: float = 5.0


def build_rig(wheel: WheelParams, load: float, cfg: RigConfig = RigConfig()) -> mujoco.MjModel:
    """The single-wheel rig for a vertical ``load`` (N) (> wheel weight), compiled."""
    spec = mujoco.MjSpec()
    spec.option.timestep = cfg.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    add_rig(spec, wheel, load, cfg)
    return spec.compile()


def add_rig(spec: mujoco.MjSpec, wheel: WheelParams, load: float, cfg: RigConfig = RigConfig()) -> None:
    """Add the rig (carriage, sled, wheel, two velocity servos) to ``spec``."""
    sled_mass = load / GRAVITY - wheel.mass
    if sled_mass <= 0:
        raise ValueError(f"load={load!r} is invalid; valid range: load > wheel weight {wheel.mass * GRAVITY:.3g} N")
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 1, 0.1], contype=0, conaffinity=0)
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
    for name, joint, kv in (("carriage_servo", "carriage_x", cfg.kv_carriage), ("wheel_servo", "wheel_spin", cfg.kv_wheel)):
        act = spec.add_actuator(name=name, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_velocity(kv=kv)


def rig_point(soil: SoilParams | SoilTable, wheel: WheelParams, load: float, slip: float,
              cfg: RigConfig = RigConfig()) -> dict:
    """Run the rig at (load, slip) to steady state; one row (source "mujoco")."""
    table = soil if isinstance(soil, SoilTable) else SoilTable(soil, wheel)
    m = build_rig(wheel, load, cfg)
    d = mujoco.MjData(m)
    sw = SoilWheels(m, d, ["wheel"], wheel, table, flat_ground(), nominal_load=load)
    v = float(kappa_from_slip(slip)) * wheel.radius * cfg.omega
    d.qpos[m.joint("sled_z").qposadr[0]] = -table.static_sinkage(load)
    d.qvel[m.joint("carriage_x").dofadr[0]] = v
    d.qvel[m.joint("wheel_spin").dofadr[0]] = cfg.omega
    d.ctrl[:] = [v, cfg.omega]
    n_settle, n_avg = int(cfg.settle_s / cfg.timestep), int(cfg.average_s / cfg.timestep)
    acc = np.zeros(5)
    cdof = m.joint("carriage_x").dofadr[0]
    for k in range(n_settle + n_avg):
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
        if k >= n_settle:
            acc += (-d.actuator_force[0], d.actuator_force[1], sw.truth["sinkage"][0],
                    sw.truth["slip"][0], d.qvel[cdof])
    dp, tq, z, s_meas, vx = acc / n_avg
    return _row(table.soil.name, load, slip, dp, tq, z, vx, cfg.omega, "mujoco", slip_measured=s_meas)


def _row(name, load, slip, dp, tq, z, v, omega, source, **extra) -> dict:
    eff = dp * v / (tq * omega) if tq > 0 else float("nan")
    row = {"soil": name, "load_N": float(load), "slip": float(slip), "DP_N": float(dp),
           "torque_Nm": float(tq), "sinkage_m": float(z), "DP_coeff": float(dp / load),
           "efficiency": float(eff), "source": source}
    row.update({k: float(v) for k, v in extra.items()})
    return row


def analytic_sweep(soil: SoilParams, wheel: WheelParams, loads: Iterable[float], slips: Iterable[float],
                   omega: float = 1.0) -> list[dict]:
    """Steady-state equations directly (sinkage from W(z, s) = load): rows, source "analytic"."""
    loads, slips = list(loads), list(slips)
    L, S = np.meshgrid(np.asarray(loads, float), np.asarray(slips, float), indexing="ij")
    r = steady_state(L, S, soil, wheel, omega)
    rows = []
    for i, load in enumerate(loads):
        for j, s in enumerate(slips):
            rows.append(_row(soil.name, load, s, r["DP_N"][i, j], r["torque_Nm"][i, j], r["sinkage_m"][i, j],
                             r["v_mps"][i, j], omega, "analytic"))
    return rows


def sweep(soil: SoilParams, wheel: WheelParams, loads: Iterable[float], slips: Iterable[float],
          cfg: RigConfig = RigConfig()) -> list[dict]:
    """The MuJoCo rig at every (load, slip): rows, source "mujoco"."""
    table = SoilTable(soil, wheel)
    return [rig_point(table, wheel, load, s, cfg) for load in loads for s in slips]
