"""A simple six-wheeled box rover (MjSpec) for soil tests and the speed benchmark.

Names: chassis body ``chassis`` (free joint), wheel bodies/geoms/joints ``wheel_<i>``
(i = 0..5, front-left, front-right, middle-left, ...), velocity actuators ``motor_<i>``.
Each wheel body's origin is its centre and its local y axis the axle.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from terrabench.sim.physics import PhysicsConfig
from terrabench.soil.terramechanics import WheelParams


@dataclass(frozen=True)
class RoverConfig:
    """Attributes:
        chassis_size: half sizes (m).  chassis_mass: (kg).
        wheelbase: front-to-rear axle distance (m).  track: left-right wheel distance (m).
        axle_drop: axle below the chassis centre (m).  kv: wheel servo gain (N m s/rad).
        physics: the scene's MuJoCo options (1 ms step; MuJoCo's own solver iterations and
            collision tolerance).  friction: wheel-ground friction for the rigid variant.
    """

    chassis_size: tuple[float, float, float] = (0.5, 0.35, 0.1)
    chassis_mass: float = 50.0
    wheelbase: float = 0.9
    track: float = 0.8
    axle_drop: float = 0.15
    kv: float = 200.0
    physics: PhysicsConfig = field(default_factory=lambda: PhysicsConfig(timestep=0.001, iterations=100,
                                                                         ccd_tolerance=1e-6))
    friction: float = 0.8


def wheel_name(i: int) -> str:
    return f"wheel_{i}"


def build_rover(wheel: WheelParams, cfg: RoverConfig = RoverConfig(), hfield=None) -> mujoco.MjSpec:
    """Spec of the rover on a plane (or on ``hfield = (h, x, y)``, see terrain.mjcf.add_heightfield)."""
    spec = mujoco.MjSpec()
    cfg.physics.apply(spec)
    if hfield is None:
        spec.worldbody.add_geom(name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[20, 20, 0.1],
                                friction=[cfg.friction, 0.005, 0.0001])
    else:
        from terrabench.terrain.mjcf import add_heightfield

        h, x, y = hfield
        add_heightfield(spec, h, x, y, name="ground", friction=cfg.friction)
    z0 = wheel.radius + cfg.axle_drop
    ch = spec.worldbody.add_body(name="chassis", pos=[0, 0, z0 + 0.01])
    ch.add_freejoint(name="chassis")
    ch.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=list(cfg.chassis_size), mass=cfg.chassis_mass,
                contype=0, conaffinity=0)
    ch.add_site(name="imu")
    i = 0
    for x in (cfg.wheelbase / 2, 0.0, -cfg.wheelbase / 2):
        for y in (cfg.track / 2, -cfg.track / 2):
            wb = ch.add_body(name=wheel_name(i), pos=[x, y, -cfg.axle_drop])
            wb.add_joint(name=wheel_name(i), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
            wb.add_geom(name=wheel_name(i), type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                        size=[wheel.radius, wheel.width / 2, 0], quat=[np.sqrt(0.5), np.sqrt(0.5), 0, 0],
                        mass=wheel.mass, friction=[cfg.friction, 0.005, 0.0001])
            act = spec.add_actuator(name=f"motor_{i}", target=wheel_name(i), trntype=mujoco.mjtTrn.mjTRN_JOINT)
            act.set_to_velocity(kv=cfg.kv)
            i += 1
    spec.add_sensor(name="accel", type=mujoco.mjtSensor.mjSENS_ACCELEROMETER, objtype=mujoco.mjtObj.mjOBJ_SITE,
                    objname="imu")
    return spec
