"""The MRS-CWC robot chain, built with :class:`mujoco.MjSpec` (spec section 3).

Six two-wheeled units 0.30 m apart. Link variants (one robot build each):

- ``"spring"`` (CWC and CS): yaw, pitch and roll spring hinges at the joint point 0.15 m
  behind each unit, two 0.4 kg link masses between them; yaw stiffness is set at run time.
- ``"motor"`` (MJ): a position-controlled yaw hinge and a pitch spring, one 1.3 kg link mass.
- ``"none"`` (D): six independent units, each with its own free joint.

All names live in :class:`Names`; everything a controller may read is a MuJoCo sensor.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from terrabench.config import check_fields, param
from terrabench.terrain.mjcf import GROUND_BIT

LINK_VARIANTS = ("spring", "motor", "none")
#: How the wheel motors are realised (``ChainConfig.wheel_drive``).
WHEEL_DRIVES = ("servo", "constraint")
#: Yaw hinges turn about -z so that the joint angle is (predecessor yaw - follower yaw): the
#: "relative yaw between robot k and robot k+1" of the stiffness law, and a positive MJ command
#: bends the chain's front to the left.
YAW_AXIS = (0.0, 0.0, -1.0)
#: Collision shapes of the wheels (``ChainConfig.wheel_shape``).
WHEEL_SHAPES = ("cylinder", "sphere")
ROBOT_BIT = 2  # robot bodies collide with each other and the ground; wheels only with the ground


@dataclass(frozen=True)
class ChainConfig:
    """Dimensions, masses, drives and contacts of the chain (spec section 3; paper Fig. 2)."""

    n_units: int = param(6, ge=1, doc="number of units (1: a leader alone)")
    spacing: float = param(0.30, gt=0, unit="m", doc="distance between consecutive unit centres")
    joint_offset: float = param(0.15, gt=0, unit="m", doc="joint point behind each unit centre")
    body_radius: float = param(0.05, gt=0, unit="m", doc="body capsule radius")
    body_length: float = param(0.20, gt=0, unit="m", doc="body capsule length, end to end")
    body_mass: float = param(3.374, gt=0, unit="kg", doc="body mass of one unit")
    com_drop: float = param(0.10, ge=0, unit="m", doc="centre of mass below the capsule centre")
    body_inertia_per_kg: tuple[float, float, float] = param((0.00125, 0.003177, 0.003177), length=3, gt=0, unit="m^2",
                                                            doc="principal inertia / mass about (longitudinal, "
                                                                "lateral, vertical)")
    wheel_radius: float = param(0.05, gt=0, unit="m", doc="wheel radius")
    wheel_width: float = param(0.02, gt=0, unit="m", doc="wheel width")
    wheel_mass: float = param(1.57, gt=0, unit="kg", doc="mass of each wheel")
    wheel_shape: str = param("cylinder", choices=WHEEL_SHAPES,
                             doc="collision shape of the wheels against the ground: cylinder (the released model) or "
                                 "sphere of the wheel radius (cheaper narrow phase against the height field, ~1.14x, "
                                 "but it changes group-B outcomes materially: docs/mrs-cwc-findings.md, 'Wheel "
                                 "geometry'); the wheel's mass and inertia stay the cylinder's in both")
    track_half: float = param(0.06, gt=0, unit="m", doc="lateral offset of each wheel")
    axle_drop: float = param(0.025, ge=0, unit="m", doc="axle below the body centre")
    wheel_friction: float = param(2.0, ge=0,
                                  doc="effective wheel-ground friction coefficient (Bullet multiplies the pair's 1.0 "
                                      "and 2.0)")
    wheel_kv: float = param(100.0 / 1.5, gt=0, unit="N m s/rad",
                            doc="velocity-servo gain of the wheel motors; 100/1.5 makes the stall torque at the "
                                "nominal 1.5 rad/s equal to the 100 N m limit")
    wheel_torque_limit: float = param(100.0, gt=0, unit="N m",
                                      doc="wheel motor torque limit; the servo drive enforces it in the trial loop on "
                                          "the commanded speed error (a hard clamp inside MuJoCo turns the 0.002 kg "
                                          "m^2 wheels into a bang-bang oscillator: 100 N m x 5 ms / 0.002 kg m^2 = "
                                          "250 rad/s per step)")
    wheel_drive: str = param("servo", choices=WHEEL_DRIVES,
                             doc="wheel motor model: servo, a MuJoCo velocity actuator tau = wheel_kv (w_cmd - w) "
                                 "with the limit applied by the loop; or constraint, Bullet's motor: a velocity "
                                 "constraint solved with the contacts that holds w = w_cmd with any torque up to "
                                 "wheel_torque_limit and slips beyond it (a fixed tendon q_wheel + q_ref with "
                                 "frictionloss wheel_torque_limit, q_ref a world reference hinge of armature "
                                 "drive_ref_armature whose speed the trial sets to -w_cmd every control period; the "
                                 "wheel torque is the reference dof's qfrc_constraint; docs/mrs-cwc-findings.md, "
                                 "'Calibration against the released logs')")
    drive_solref: tuple[float, float] = param((0.01, 1.0), length=2, gt=0,
                                              doc="MuJoCo solref (timeconst s, dampratio) of the constraint drive: "
                                                  "the creep under a load torque T on a free wheel is about T (1-d)/d "
                                                  "/ (I_w b), b = 2/(d timeconst); timeconst 0.01 s is 2 physics "
                                                  "steps, MuJoCo's stiffest safe value")
    drive_solimp: tuple[float, float, float, float, float] = param((0.9999, 0.9999, 0.001, 0.5, 2.0), length=5, gt=0,
                                                                   doc="MuJoCo solimp of the constraint drive: d = "
                                                                       "0.9999 with solref's 0.01 s gives ~0.0003 "
                                                                       "rad/s per N m of creep, a servo of ~4000 N m "
                                                                       "s/rad solved implicitly")
    drive_ref_armature: float = param(1e4, gt=0, unit="kg m^2",
                                      doc="inertia of each drive reference hinge (constraint drive); 100 N m for a "
                                          "control period moves it by 100 x 0.025 / 1e4 = 2.5e-4 rad/s")
    wheel_solref: tuple[float, float] = param((0.02, 1.0), length=2, gt=0,
                                              doc="MuJoCo solref (timeconst s, dampratio) of the wheel-ground contact "
                                                  "(MuJoCo's default): a soft contact lets a wheel creep tangentially "
                                                  "at a speed proportional to its friction force; Bullet's static "
                                                  "friction does not creep")
    wheel_solimp: tuple[float, float, float, float, float] = param((0.9, 0.95, 0.001, 0.5, 2.0), length=5, gt=0,
                                                                   doc="MuJoCo solimp of the wheel-ground contact "
                                                                       "(MuJoCo's default)")
    noslip_iterations: int = param(0, ge=0,
                                   doc="MuJoCo noslip post-solver iterations for this scene (0 = off): it removes the "
                                       "creep of all friction rows (contacts and drive tendons), making static "
                                       "friction hard as in Bullet's sequential-impulse solver")
    bumper_radius: float = param(0.09, gt=0, unit="m", doc="leader bumper disc radius")
    bumper_thickness: float = param(0.02, gt=0, unit="m", doc="leader bumper disc thickness")
    bumper_mass: float = param(2.8, gt=0, unit="kg", doc="leader bumper mass")
    bumper_ahead: float = param(0.12, ge=0, unit="m", doc="bumper centre ahead of the leader centre")
    bumper_up: float = param(0.05, ge=0, unit="m", doc="bumper centre above the leader centre")
    bumper_touches_ground: bool = param(True,
                                        doc="whether the bumper collides with the terrain (the released scene) or "
                                            "only with the other units: a diagnostic switch for leaders that rest on "
                                            "their bumper with their wheels in the air "
                                            "(benchmarks/leader_contact_study.py, docs/mrs-cwc-findings.md)")
    link_mass_spring: float = param(0.4, gt=0, unit="kg", doc="each of the two link masses of the spring variant")
    link_mass_motor: float = param(1.3, gt=0, unit="kg", doc="link mass of the motor variant")
    k_pitch: float = param(15.0, gt=0, unit="N m/rad", doc="pitch spring stiffness")
    k_roll: float = param(30.0, gt=0, unit="N m/rad", doc="roll spring stiffness")
    k_yaw_init: float = param(0.1, gt=0, unit="N m/rad", doc="yaw stiffness at t = 0")
    link_damping: float = param(0.5, ge=0, unit="N m s/rad",
                                doc="viscous damping of every link hinge; the released scenes say 0, but Bullet's "
                                    "constraint solver dissipates, and with exactly 0 a chain tumbling in free flight "
                                    "after the drop gains energy until it blows up (docs/assumptions.md); 0.5 gives "
                                    "the K = 5 yaw mode a damping ratio below 0.2")
    yaw_kp: float = param(50.0, gt=0, lt=100, unit="N m/rad",
                          doc="MJ yaw servo position gain; torque is unlimited, but the compliance term "
                              "(command - tau/100) closes a loop of gain yaw_kp/100 at the control rate, which "
                              "oscillates at 100 and above")
    yaw_kv: float = param(5.0, ge=0, unit="N m s/rad", doc="MJ yaw servo damping")

    def __post_init__(self) -> None:
        check_fields(self)


class Names:
    """Every name the chain model defines, in one place."""

    @staticmethod
    def unit(k: int) -> str:
        return f"unit{k}"

    @staticmethod
    def wheel(k: int, side: str) -> str:
        return f"unit{k}_wheel_{side}"

    @staticmethod
    def motor(k: int, side: str) -> str:
        return f"unit{k}_motor_{side}"

    @staticmethod
    def link_joint(k: int, axis: str) -> str:
        """Joint between unit k-1 and unit k (k >= 1), axis in yaw|pitch|roll."""
        return f"link{k}_{axis}"

    yaw_servo = staticmethod(lambda k: f"link{k}_yaw_servo")
    #: reference hinge and coupling tendon of a wheel under ``wheel_drive="constraint"``
    drive_ref = staticmethod(lambda k, side: f"unit{k}_drive_ref_{side}")
    drive_tendon = staticmethod(lambda k, side: f"unit{k}_drive_{side}")
    SIDES = ("left", "right")


def _unit_body(parent: mujoco.MjsBody, k: int, pos, cfg: ChainConfig, leader: bool) -> mujoco.MjsBody:
    m, (ix, iy, iz) = cfg.body_mass, cfg.body_inertia_per_kg
    body = parent.add_body(name=Names.unit(k), pos=list(pos))
    body.explicitinertial = True
    body.mass = m
    body.ipos = [0, 0, -cfg.com_drop]
    body.inertia = [m * ix, m * iy, m * iz]
    half_cyl = max(cfg.body_length / 2 - cfg.body_radius, 1e-4)
    body.add_geom(
        name=f"{Names.unit(k)}_body",
        type=mujoco.mjtGeom.mjGEOM_CAPSULE,
        size=[cfg.body_radius, half_cyl, 0],
        quat=[np.sqrt(0.5), 0, np.sqrt(0.5), 0],  # capsule axis along x
        contype=ROBOT_BIT,
        conaffinity=GROUND_BIT | ROBOT_BIT,
        condim=1,  # body friction ~0 in the released scenes
        priority=1,
        friction=[0, 0, 0],
        mass=0,
        rgba=[0.9, 0.45, 0.1, 1] if leader else [0.2, 0.45, 0.8, 1],
    )
    body.add_site(name=f"{Names.unit(k)}_imu")
    for side, sgn in (("left", 1.0), ("right", -1.0)):
        wb = body.add_body(name=Names.wheel(k, side), pos=[0, sgn * cfg.track_half, -cfg.axle_drop])
        wb.add_joint(name=Names.wheel(k, side), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
        r, w, m = cfg.wheel_radius, cfg.wheel_width, cfg.wheel_mass
        if cfg.wheel_shape == "cylinder":
            shape = dict(type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[r, w / 2, 0],
                         quat=[np.sqrt(0.5), np.sqrt(0.5), 0, 0], mass=m)  # cylinder axis along y
        else:  # the cylinder's mass and inertia, a sphere's contact
            wb.explicitinertial = True
            wb.mass = m
            wb.ipos, wb.iquat = [0, 0, 0], [1, 0, 0, 0]
            wb.inertia = [m * (3 * r * r + w * w) / 12, m * r * r / 2, m * (3 * r * r + w * w) / 12]
            shape = dict(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[r, 0, 0], mass=0)
        wb.add_geom(
            **shape,
            contype=0,
            conaffinity=GROUND_BIT,
            condim=3,
            priority=1,
            friction=[cfg.wheel_friction, 0.005, 0.0001],
            solref=list(cfg.wheel_solref),
            solimp=list(cfg.wheel_solimp),
            rgba=[0.1, 0.1, 0.1, 1],
        )
    if leader:
        bumper = body.add_body(name="bumper", pos=[cfg.bumper_ahead, 0, cfg.bumper_up])
        bumper.add_geom(
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[cfg.bumper_radius, cfg.bumper_thickness / 2, 0],
            mass=cfg.bumper_mass,
            contype=ROBOT_BIT,
            conaffinity=(GROUND_BIT if cfg.bumper_touches_ground else 0) | ROBOT_BIT,
            condim=1,
            priority=1,
            friction=[0, 0, 0],
            rgba=[0.9, 0.8, 0.2, 1],
        )
    return body


def _small_mass(body: mujoco.MjsBody, mass: float) -> None:
    body.explicitinertial = True
    body.mass = mass
    i = 0.4 * mass * 0.02**2  # a 2 cm solid sphere
    body.inertia = [i, i, i]


def _hinge(body: mujoco.MjsBody, name: str, axis, stiffness: float, damping: float) -> None:
    j = body.add_joint(name=name, type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(axis), stiffness=stiffness)
    j.damping = [damping, 0.0, 0.0]


def add_chain(
    spec: mujoco.MjSpec,
    variant: str,
    start: tuple[float, float, float],
    cfg: ChainConfig = ChainConfig(),
) -> None:
    """Add the chain to ``spec`` with the leader at ``start`` heading +x, followers along -x."""
    if variant not in LINK_VARIANTS:
        raise ValueError(f"unknown link variant {variant!r}; valid: {', '.join(LINK_VARIANTS)}")
    x0, y0, z0 = start
    world = spec.worldbody
    if variant == "none":
        for k in range(cfg.n_units):
            b = _unit_body(world, k, (x0 - k * cfg.spacing, y0, z0), cfg, leader=k == 0)
            b.add_freejoint(name=f"{Names.unit(k)}_free")
    else:
        parent = _unit_body(world, 0, (x0, y0, z0), cfg, leader=True)
        parent.add_freejoint(name=f"{Names.unit(0)}_free")
        rest = cfg.spacing - cfg.joint_offset
        for k in range(1, cfg.n_units):
            yaw = parent.add_body(name=f"link{k}_a", pos=[-cfg.joint_offset, 0, 0])
            if variant == "spring":
                _small_mass(yaw, cfg.link_mass_spring)
                _hinge(yaw, Names.link_joint(k, "yaw"), YAW_AXIS, cfg.k_yaw_init, cfg.link_damping)
                pitch = yaw.add_body(name=f"link{k}_b")
                _small_mass(pitch, cfg.link_mass_spring)
                _hinge(pitch, Names.link_joint(k, "pitch"), (0, 1, 0), cfg.k_pitch, cfg.link_damping)
                child = _unit_body(pitch, k, (-rest, 0, 0), cfg, leader=False)
                _hinge(child, Names.link_joint(k, "roll"), (1, 0, 0), cfg.k_roll, cfg.link_damping)
                child.joints[0].pos = [rest, 0, 0]
            else:
                _small_mass(yaw, cfg.link_mass_motor)
                _hinge(yaw, Names.link_joint(k, "yaw"), YAW_AXIS, 0.0, cfg.link_damping)
                child = _unit_body(yaw, k, (-rest, 0, 0), cfg, leader=False)
                _hinge(child, Names.link_joint(k, "pitch"), (0, 1, 0), cfg.k_pitch, cfg.link_damping)
                child.joints[0].pos = [rest, 0, 0]
                spec.add_actuator(
                    name=Names.yaw_servo(k),
                    target=Names.link_joint(k, "yaw"),
                    trntype=mujoco.mjtTrn.mjTRN_JOINT,
                ).set_to_position(kp=cfg.yaw_kp, kv=cfg.yaw_kv)
            parent = child
    for k in range(cfg.n_units):
        for side in Names.SIDES:
            act = spec.add_actuator(
                name=Names.motor(k, side),
                target=Names.wheel(k, side),
                trntype=mujoco.mjtTrn.mjTRN_JOINT,
            )
            act.set_to_velocity(kv=cfg.wheel_kv if cfg.wheel_drive == "servo" else 0.0)
    if cfg.wheel_drive == "constraint":
        _add_constraint_drive(spec, cfg)
    if cfg.noslip_iterations:
        spec.option.noslip_iterations = cfg.noslip_iterations
    _add_sensors(spec, variant, cfg)


def drive_ref_dof(model: mujoco.MjModel) -> int | None:
    """First dof address of the constraint drive's reference hinges (``2 n_units`` consecutive
    dofs in (unit, left/right) order), or None when the chain has the servo drive."""
    try:
        return int(model.jnt_dofadr[model.joint(Names.drive_ref(0, "left")).id])
    except KeyError:
        return None


def _add_constraint_drive(spec: mujoco.MjSpec, cfg: ChainConfig) -> None:
    """Bullet-like wheel motors: per wheel a world reference hinge and a friction tendon.

    The tendon length is ``q_wheel + q_ref`` (the reference turns about -y), so holding its
    rate at 0 holds the wheel at ``-qvel_ref``; its frictionloss caps the holding torque at the
    motor limit. The reference bodies come after the chain, so their dofs are the last
    ``2 n_units`` dofs, in (unit, left/right) order.
    """
    # MuJoCo 4.0 picks the sparse Jacobian from nv >= 60 (MRS-D with this drive); with it these
    # cross-tree friction tendons are solved wrongly (six free units in the air, no contact:
    # wheels at 280 rad/s against 1.5 commanded; dense: 1.5). Dense is exact and fast enough.
    spec.option.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    for k in range(cfg.n_units):
        for side in Names.SIDES:
            ref = spec.worldbody.add_body(name=Names.drive_ref(k, side))
            _small_mass(ref, 1.0)
            j = ref.add_joint(name=Names.drive_ref(k, side), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, -1, 0])
            j.armature = cfg.drive_ref_armature
            ten = spec.add_tendon(name=Names.drive_tendon(k, side))
            ten.frictionloss = cfg.wheel_torque_limit
            ten.solref_friction = list(cfg.drive_solref)
            ten.solimp_friction = list(cfg.drive_solimp)
            ten.wrap_joint(Names.wheel(k, side), 1.0)
            ten.wrap_joint(Names.drive_ref(k, side), 1.0)


def _add_sensors(spec: mujoco.MjSpec, variant: str, cfg: ChainConfig) -> None:
    """What the real chain measures: unit pose (IMU + odometry), joint angles, wheel states."""
    S = mujoco.mjtSensor
    for k in range(cfg.n_units):
        site = f"{Names.unit(k)}_imu"
        spec.add_sensor(name=f"{Names.unit(k)}_pos", type=S.mjSENS_FRAMEPOS,
                        objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
        # the body x axis in the world frame: heading = atan2(x_y, x_x) (an IMU/compass)
        spec.add_sensor(name=f"{Names.unit(k)}_xaxis", type=S.mjSENS_FRAMEXAXIS,
                        objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
        spec.add_sensor(name=f"{Names.unit(k)}_angvel", type=S.mjSENS_FRAMEANGVEL,
                        objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
    for k in range(cfg.n_units):
        for side in Names.SIDES:
            spec.add_sensor(name=f"{Names.wheel(k, side)}_vel", type=S.mjSENS_JOINTVEL,
                            objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=Names.wheel(k, side))
    for k in range(cfg.n_units):
        for side in Names.SIDES:
            spec.add_sensor(name=f"{Names.motor(k, side)}_torque", type=S.mjSENS_ACTUATORFRC,
                            objtype=mujoco.mjtObj.mjOBJ_ACTUATOR, objname=Names.motor(k, side))
    if variant != "none":
        for k in range(1, cfg.n_units):
            spec.add_sensor(name=f"{Names.link_joint(k, 'yaw')}_angle", type=S.mjSENS_JOINTPOS,
                            objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=Names.link_joint(k, "yaw"))
    if variant == "motor":
        for k in range(1, cfg.n_units):
            spec.add_sensor(name=f"{Names.yaw_servo(k)}_torque", type=S.mjSENS_ACTUATORFRC,
                            objtype=mujoco.mjtObj.mjOBJ_ACTUATOR, objname=Names.yaw_servo(k))
            spec.add_sensor(name=f"{Names.link_joint(k, 'yaw')}_vel", type=S.mjSENS_JOINTVEL,
                            objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=Names.link_joint(k, "yaw"))
