"""The e-OCTOPUS-like robot as an ``MjSpec`` builder with named parts (names live in :class:`Names`).

Frame of the robot (body ``chassis``): x forward, y left, z up, origin on the main-track pulley
axis, midway between the pulleys. Parts:

* chassis box; two main tracks (``track_L``, ``track_R``): end pulleys (capsules across y) and
  a lower-run box, all moving contact surfaces (``geom_surfacevel``: the pulleys spin, the box
  slides), so no track DOF is simulated;
* four flippers (``flipper_LF, RF, LR, RR``) hinged coaxially with the end pulleys, 250 mm,
  each a pulley + lower-run box + tip pulley, moving surfaces too; angle > 0 lifts the tip;
* four arms (``arm_LF, RF, LR, RR``): swing (about z), boom and elbow (about the axis across
  the arm), capsule links ``l1``, ``l2``, and a tip sphere on two free orthogonal hinges (the
  two-axis passive roller of the paper's Fig. 8).

Arm angle conventions (ours, for every arm alike): swing 0 points the arm straight out to its
side, > 0 turns it toward the front; boom and elbow > 0 turn the link downward. The paper's
signs differ per arm (A_B = +0.6 rear / -0.6 front); docs/assumptions-octopus.md maps them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco

from terrabench.config import param
from terrabench.terrain.mjcf import GROUND_BIT

ARMS = ("LF", "RF", "LR", "RR")
FLIPPERS = ("LF", "RF", "LR", "RR")
ARM_JOINTS = ("swing", "boom", "elbow")
#: a capsule's axis (local z) turned onto the body's +y: pulleys spin about it (surfacevel[5] > 0
#: moves the lower surface backward, i.e. drives forward)
ACROSS = [math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0]
#: (sign x, sign y) of each corner
CORNER = {"LF": (1, 1), "RF": (1, -1), "LR": (-1, 1), "RR": (-1, -1)}


class Names:
    """Every name of the model, in one place."""

    CHASSIS = "chassis"
    ROOT = "root"
    IMU = "imu_quat"
    GYRO = "imu_gyro"
    SIDES = ("L", "R")

    @staticmethod
    def flipper(k: str) -> str:
        return f"flipper_{k}"

    @staticmethod
    def flipper_joint(k: str) -> str:
        return f"flipper_{k}_hinge"

    @staticmethod
    def arm_body(k: str, part: str) -> str:
        return f"arm_{k}_{part}"

    @staticmethod
    def arm_joint(k: str, j: str) -> str:
        return f"arm_{k}_{j}"

    @staticmethod
    def roller_joint(k: str, axis: str) -> str:
        return f"arm_{k}_roller_{axis}"

    @staticmethod
    def tip(k: str) -> str:
        return f"arm_{k}_tip"

    @staticmethod
    def track_geoms(side: str) -> tuple[str, str, str]:
        return (f"track_{side}_front", f"track_{side}_run", f"track_{side}_rear")

    @staticmethod
    def flipper_geoms(k: str) -> tuple[str, str, str]:
        return (f"flipper_{k}_pulley", f"flipper_{k}_run", f"flipper_{k}_tip")

    @staticmethod
    def act(joint: str) -> str:
        return f"{joint}_act"

    @staticmethod
    def pos_sensor(joint: str) -> str:
        return f"{joint}_pos"

    @staticmethod
    def torque_sensor(joint: str) -> str:
        return f"{joint}_torque"


@dataclass(frozen=True)
class RobotConfig:
    """Dimensions (m), masses (kg), limits (rad, N m) and servo gains of the robot."""

    pulley_x: float = param(0.2, gt=0, unit="m", doc="main-track pulley centres at +-pulley_x")
    pulley_r: float = param(0.09, gt=0, unit="m", doc="main-track pulley radius")
    track_y: float = param(0.22, gt=0, unit="m", doc="main-track centre line at +-track_y")
    track_w: float = param(0.1, gt=0, unit="m", doc="main-track width")
    chassis_half: tuple[float, float, float] = param((0.25, 0.17, 0.09), length=3, gt=0, unit="m",
                                                     doc="chassis box half sizes")
    chassis_z: float = param(0.06, ge=0, unit="m", doc="chassis centre above the pulley axis")
    chassis_mass: float = param(56.0, gt=0, unit="kg",
                                doc="chassis mass (the paper: weight concentrated low in the chassis)")
    flipper_len: float = param(0.25, gt=0, unit="m", doc="flipper pivot to tip pulley [P: 250 mm]")
    flipper_tip_r: float = param(0.05, gt=0, unit="m", doc="flipper tip pulley radius")
    flipper_y: float = param(0.31, gt=0, unit="m", doc="flipper centre line at +-flipper_y")
    flipper_w: float = param(0.06, gt=0, unit="m", doc="flipper width")
    flipper_mass: float = param(3.0, gt=0, unit="kg", doc="mass of each flipper")
    flipper_range: tuple[float, float] = param((-1.2, 1.4835), length=2, ge=-math.pi, le=math.pi, unit="rad",
                                               doc="flipper joint range (lower, upper); the upper end is the paper's "
                                                   "85 deg limit")
    flipper_torque: float = param(250.0, gt=0, unit="N m", doc="flipper actuator torque limit")
    flipper_kp: float = param(3000.0, gt=0, unit="N m/rad", doc="flipper position gain")
    arm_mount: tuple[float, float, float] = param((0.2, 0.17, 0.15), length=3, ge=0, unit="m",
                                                  doc="arm base at (+-x, +-y, z) in the chassis frame (the paper's "
                                                      "m/2, n/2)")
    l1: float = param(0.45, gt=0, le=1.5, unit="m",
                      doc="boom length; <= 1.5 m: the compiled robot weighs 94 kg, so one of four supporting arms "
                          "carries about 230 N, which the boom's default 300 N m holds at no more than 1.3 m of lever")
    l2: float = param(0.45, gt=0, le=1.5, unit="m",
                      doc="forearm length; <= 1.5 m, as the boom (an arm that long cannot carry "
                          "the 94 kg robot)")
    link_r: float = param(0.03, gt=0, unit="m", doc="arm link capsule radius")
    tip_r: float = param(0.04, gt=0, unit="m", doc="arm tip sphere radius")
    link_mass: tuple[float, float, float] = param((2.5, 1.5, 0.5), length=3, gt=0, unit="kg",
                                                  doc="(boom, forearm, tip) masses")
    swing_range: tuple[float, float] = param((-1.3, 1.3), length=2, ge=-math.pi, le=math.pi, unit="rad",
                                             doc="swing joint range (lower, upper) in our convention")
    boom_range: tuple[float, float] = param((-1.2, 1.3), length=2, ge=-math.pi, le=math.pi, unit="rad",
                                            doc="boom joint range (lower, upper) in our convention")
    elbow_range: tuple[float, float] = param((-0.3, 2.6), length=2, ge=-math.pi, le=math.pi, unit="rad",
                                             doc="elbow joint range (lower, upper) in our convention")
    arm_torque: tuple[float, float, float] = param((100.0, 300.0, 150.0), length=3, gt=0, unit="N m",
                                                   doc="(swing, boom, elbow) torque limits")
    arm_kp: tuple[float, float, float] = param((800.0, 2500.0, 1500.0), length=3, gt=0, unit="N m/rad",
                                               doc="(swing, boom, elbow) position gains")
    arm_damping: float = param(20.0, ge=0, unit="N m s/rad", doc="joint damping of the arm joints")
    roller_damping: float = param(0.02, ge=0, unit="N m s/rad", doc="joint damping of the tip rollers")
    friction: float = param(1.0, ge=0, doc="sliding friction of the robot geoms (tracks, tips)")
    link_friction: float = param(0.3, ge=0,
                                 doc="sliding friction of the arm links (boom, forearm); MuJoCo takes the larger "
                                     "friction of a pair, so the links get priority 1 and their pairs use this value")
    tip_solref: tuple[float, float] = param((0.008, 1.0), length=2, gt=0, unit="s, -",
                                            doc="arm-tip contact time constant and damping ratio (priority 1): "
                                                "stiffer than the default (0.02, 1) so a pressed tip sinks "
                                                "millimetres, not centimetres")
    joint_speed: tuple[float, float, float, float] = param((4.4, 4.4, 4.4, 4.4), length=4, gt=0, unit="rad/s",
                                                           doc="speed limits of (flipper, swing, boom, elbow): servo "
                                                               "commands move at most this fast and the servos' "
                                                               "velocity gain kv = torque limit / speed limit "
                                                               "saturates at it")
    track_power: float = param(300.0, gt=0, unit="W",
                               doc="crawler drive power limit per side (main track + its two flippers): the crawler "
                                   "speed is cut so that the sampled traction force times the speed stays below it")


def _surface(geom, lin=(0.0, 0.0, 0.0), ang=(0.0, 0.0, 0.0)) -> None:
    # a non-zero initial value keeps MuJoCo's surface-velocity feature compiled in
    geom.surfacevel = [*lin, *ang]


def add_robot(spec: mujoco.MjSpec, pos: tuple[float, float, float], yaw: float, cfg: RobotConfig) -> None:
    """Add the robot, its actuators and its sensors to ``spec`` (start pose ``pos``, ``yaw`` rad)."""
    cap, box, sph = mujoco.mjtGeom.mjGEOM_CAPSULE, mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_SPHERE
    spec.compiler.degree = False  # every angle of this builder is in radians
    hit = dict(contype=0, conaffinity=GROUND_BIT, friction=[cfg.friction, 0.005, 0.0001])
    ch = spec.worldbody.add_body(name=Names.CHASSIS, pos=list(pos),
                                 quat=[math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)])
    ch.add_freejoint(name=Names.ROOT)
    ch.add_geom(name="chassis_box", type=box, size=list(cfg.chassis_half), pos=[0, 0, cfg.chassis_z],
                mass=cfg.chassis_mass, rgba=[0.85, 0.55, 0.1, 1], **hit)
    ch.add_site(name="imu", pos=[0, 0, cfg.chassis_z])
    r, px, w = cfg.pulley_r, cfg.pulley_x, cfg.track_w
    for side, sy in (("L", 1), ("R", -1)):
        y = sy * cfg.track_y
        front, run, rear = Names.track_geoms(side)
        for nm, x in ((front, px), (rear, -px)):
            g = ch.add_geom(name=nm, type=cap, size=[r, w / 2, 0], pos=[x, y, 0], quat=ACROSS,
                            mass=1.0, rgba=[0.15, 0.15, 0.15, 1], **hit)
            _surface(g, ang=(0, 0, 1e-3))
        g = ch.add_geom(name=run, type=box, size=[px, w / 2, 0.02], pos=[0, y, -r + 0.02], mass=1.0,
                        rgba=[0.15, 0.15, 0.15, 1], **hit)
        _surface(g, lin=(-1e-3, 0, 0))
    # flippers
    for k in FLIPPERS:
        sx, sy = CORNER[k]
        fb = ch.add_body(name=Names.flipper(k), pos=[sx * px, sy * cfg.flipper_y, 0])
        # local x points from the pivot to the tip: forward for front, backward for rear flippers
        if sx < 0:
            fb.quat = [0, 0, 0, 1]
        fb.add_joint(name=Names.flipper_joint(k), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, -1, 0],
                     range=list(cfg.flipper_range), limited=True, damping=5.0, armature=0.1)
        fw, L, rt = cfg.flipper_w, cfg.flipper_len, cfg.flipper_tip_r
        pulley, run, tip = Names.flipper_geoms(k)
        m = cfg.flipper_mass / 3
        g = fb.add_geom(name=pulley, type=cap, size=[r, fw / 2, 0], quat=ACROSS, mass=m,
                        rgba=[0.2, 0.2, 0.2, 1], **hit)
        _surface(g, ang=(0, 0, 1e-3))
        g = fb.add_geom(name=run, type=box, size=[L / 2, fw / 2, 0.02], pos=[L / 2, 0, -0.5 * (r + rt) + 0.02],
                        mass=m, rgba=[0.2, 0.2, 0.2, 1], **hit)
        _surface(g, lin=(-1e-3, 0, 0))
        g = fb.add_geom(name=tip, type=cap, size=[rt, fw / 2, 0], pos=[L, 0, 0], quat=ACROSS, mass=m,
                        rgba=[0.2, 0.2, 0.2, 1], **hit)
        _surface(g, ang=(0, 0, 1e-3))
        _servo(spec, Names.flipper_joint(k), cfg.flipper_kp, cfg.flipper_torque, cfg.flipper_range,
               cfg.flipper_torque / cfg.joint_speed[0])
    # arms
    ranges = (cfg.swing_range, cfg.boom_range, cfg.elbow_range)
    for k in ARMS:
        sx, sy = CORNER[k]
        mx, my, mz = cfg.arm_mount
        base = ch.add_body(name=Names.arm_body(k, "base"), pos=[sx * mx, sy * my, mz])
        base.add_joint(name=Names.arm_joint(k, "swing"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, -sy],
                       range=list(cfg.swing_range), limited=True, damping=cfg.arm_damping, armature=0.05)
        base.add_geom(type=cap, size=[0.04, 0.03, 0], mass=0.5, contype=0, conaffinity=0, rgba=[0.3, 0.3, 0.6, 1])
        boom = base.add_body(name=Names.arm_body(k, "boom"), pos=[0, 0, 0.04])
        boom.add_joint(name=Names.arm_joint(k, "boom"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[-sy, 0, 0],
                       range=list(cfg.boom_range), limited=True, damping=cfg.arm_damping, armature=0.05)
        link = {**hit, "friction": [cfg.link_friction, 0.005, 0.0001], "priority": 1}
        boom.add_geom(type=cap, size=[cfg.link_r, 0, 0], fromto=[0, 0, 0, 0, sy * cfg.l1, 0],
                      mass=cfg.link_mass[0], rgba=[0.3, 0.3, 0.7, 1], **link)
        fore = boom.add_body(name=Names.arm_body(k, "fore"), pos=[0, sy * cfg.l1, 0])
        fore.add_joint(name=Names.arm_joint(k, "elbow"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[-sy, 0, 0],
                       range=list(cfg.elbow_range), limited=True, damping=cfg.arm_damping, armature=0.05)
        fore.add_geom(type=cap, size=[cfg.link_r * 0.8, 0, 0],
                      fromto=[0, 0, 0, 0, sy * (cfg.l2 - cfg.tip_r), 0], mass=cfg.link_mass[1],
                      rgba=[0.35, 0.35, 0.75, 1], **link)
        rx = fore.add_body(name=Names.arm_body(k, "roller_x"), pos=[0, sy * cfg.l2, 0])
        rx.add_joint(name=Names.roller_joint(k, "x"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[1, 0, 0],
                     damping=cfg.roller_damping, armature=0.001)
        rx.add_geom(type=sph, size=[0.01, 0, 0], mass=0.05, contype=0, conaffinity=0)
        ry = rx.add_body(name=Names.tip(k))
        # the second roller axis lies in the arm plane across the forearm (fore z): with the
        # first (along the elbow axis) the tip rolls both along and across the arm plane. An axis
        # along the forearm would only spin the ball about the (near vertical) forearm.
        ry.add_joint(name=Names.roller_joint(k, "y"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, 1],
                     damping=cfg.roller_damping, armature=0.001)
        ry.add_geom(name=Names.tip(k), type=sph, size=[cfg.tip_r, 0, 0], mass=cfg.link_mass[2],
                    rgba=[0.9, 0.2, 0.2, 1], priority=1, solref=list(cfg.tip_solref), **hit)
        for j, rng, tq, kp, w in zip(ARM_JOINTS, ranges, cfg.arm_torque, cfg.arm_kp, cfg.joint_speed[1:]):
            _servo(spec, Names.arm_joint(k, j), kp, tq, rng, tq / w)
    # sensors: IMU orientation, encoders of every actuated joint, flipper and elbow torques
    spec.add_sensor(name=Names.IMU, type=mujoco.mjtSensor.mjSENS_FRAMEQUAT, objtype=mujoco.mjtObj.mjOBJ_SITE,
                    objname="imu")
    spec.add_sensor(name=Names.GYRO, type=mujoco.mjtSensor.mjSENS_GYRO, objtype=mujoco.mjtObj.mjOBJ_SITE,
                    objname="imu")
    for j in actuated_joints():
        spec.add_sensor(name=Names.pos_sensor(j), type=mujoco.mjtSensor.mjSENS_JOINTPOS,
                        objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=j)
    for j in torque_joints():
        spec.add_sensor(name=Names.torque_sensor(j), type=mujoco.mjtSensor.mjSENS_ACTUATORFRC,
                        objtype=mujoco.mjtObj.mjOBJ_ACTUATOR, objname=Names.act(j))


def actuated_joints() -> list[str]:
    """Flipper joints (LF, RF, LR, RR), then each arm's swing, boom, elbow."""
    return [Names.flipper_joint(k) for k in FLIPPERS] + [Names.arm_joint(k, j) for k in ARMS for j in ARM_JOINTS]


def torque_joints() -> list[str]:
    """The joints whose torque the robot measures: the four flippers, then the four elbows."""
    return [Names.flipper_joint(k) for k in FLIPPERS] + [Names.arm_joint(k, "elbow") for k in ARMS]


def _servo(spec: mujoco.MjSpec, joint: str, kp: float, torque: float, rng: tuple[float, float], kv: float) -> None:
    """Position servo with gain ``kp``, velocity gain ``kv`` (at the speed limit the velocity term
    alone takes the whole ``torque``: a driven or back-driven joint saturates there)."""
    a = spec.add_actuator(name=Names.act(joint), target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
    a.set_to_position(kp=kp, kv=kv)
    a.forcelimited = True
    a.forcerange = [-torque, torque]
    a.ctrllimited = True
    a.ctrlrange = list(rng)
