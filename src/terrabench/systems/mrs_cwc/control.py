"""Controllers of the MRS-CWC benchmark (spec section 4; paper eqs 6-12).

A controller is built from two parts:

- a *guidance* that gives the leader its reference heading: :class:`TargetDirection` (TDT,
  no map) or :class:`WaypointGuidance` (the A* methods, the only ones given a map);
- a *body law* that turns the observation and that heading into wheel speeds, and for the
  linked variants into a yaw stiffness (:class:`CWCLaw`, CS) or yaw-servo targets
  (:class:`HeadFollowing`, MJ); D uses :class:`FollowByPosition`.

Everything runs once per control period (0.025 s) on an :class:`Observation`.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from terrabench.config import check_fields, param
from terrabench.systems.mrs_cwc.sensing import Observation, wrap, wrap_scalar

STIFFNESS_MODES = ("released", "eq12", "constant")


@dataclass(frozen=True)
class DriveConfig:
    """Differential wheel-speed law shared by leaders and CWC/CS followers."""

    wheel_speed: float = param(1.5, ge=0, unit="rad/s",
                               doc="nominal wheel speed; 1.5 rad/s x 0.05 m = 0.075 m/s (0: a chain that does not "
                                   "drive)")
    turn_gain: float = param(0.6, ge=0, unit="rad/s per rad", doc="differential gain on the heading error")


@dataclass(frozen=True)
class StiffnessLawConfig:
    """The CWC yaw-stiffness law (spec section 4, paper eqs 10-12).

    The control period the law differentiates the yaw rate over is the protocol's
    (``protocol.control_period``), passed to :class:`StiffnessLaw`: one value in one place.
    """

    mode: str = param("released", choices=STIFFNESS_MODES,
                      doc="CWC law: released (latch + sign memory, what produced the tables), eq12 (the paper's "
                          "idealised rule) or constant (K* = k_low always: the CS method)")
    k_low: float = param(5.0, gt=0, unit="N m/rad", doc="soft yaw stiffness")
    k_high: float = param(100.0, gt=0, unit="N m/rad", doc="stiff yaw stiffness")
    k_init: float = param(0.1, gt=0, unit="N m/rad", doc="stiffness at t = 0")
    latch_on: float = param(20.0, ge=0, unit="N m", doc="|tau_env| above which soft latches on")
    latch_off: float = param(1.0, ge=0, unit="N m", doc="|tau_env| below which soft releases")
    inertia: float = param(0.0042181, gt=0, unit="kg m^2", doc="leader yaw inertia used in tau_env")
    motor_gain: float = param(1.2, ge=0, doc="steering torque = motor_gain * (tau_R - tau_L)")
    sign_error_threshold: float = param(0.6, ge=0, unit="rad", doc="|0.5 e| at or above which the sign memory updates")
    memory_rate: float = param(0.1, ge=0, le=1, doc="weight of a new sign in the memory")
    ema: float = param(0.03, gt=0, le=1, doc="weight of K* in the first-order smoothing")
    window: int = param(5, ge=1, doc="number of values in the moving average after the smoothing")

    def __post_init__(self) -> None:
        check_fields(self)


class StiffnessLaw:
    """Computes the common yaw stiffness of all five links from the leader's measurements.

    Call :meth:`update` once per control period with the leader's heading error ``e`` (rad),
    yaw rate (rad/s), wheel torques ``tau_l, tau_r`` (N m) and link-1 relative yaw ``q1`` (rad).
    """

    def __init__(self, cfg: StiffnessLawConfig, control_period: float):
        self.cfg = cfg
        self.period = control_period
        self.k = cfg.k_init
        self.memory = -1.0
        self.soft = False
        self.tau_env = 0.0
        self._prev_rate: float | None = None
        self._history: deque[float] = deque(maxlen=cfg.window)

    def update(self, e: float, yaw_rate: float, tau_l: float, tau_r: float, q1: float) -> float:
        c = self.cfg
        alpha = 0.0 if self._prev_rate is None else (yaw_rate - self._prev_rate) / self.period
        self._prev_rate = yaw_rate
        tau_m = c.motor_gain * (tau_r - tau_l)
        tau_spring = -self.k * q1
        # Sign convention as released (spec section 4): tau_env = I*alpha + tau_m - tau_spring.
        self.tau_env = c.inertia * alpha + tau_m - tau_spring
        big = abs(self.tau_env)
        if c.mode == "constant":
            target = c.k_low
        elif c.mode == "eq12":
            target = c.k_low if (tau_m * tau_spring < 0 or big >= c.latch_on) else c.k_high
        else:
            if abs(0.5 * e) >= c.sign_error_threshold:
                self.memory = (1 - c.memory_rate) * self.memory + c.memory_rate * _sign(tau_spring) * _sign(e)
            if big > c.latch_on:
                self.soft = True
            elif big < c.latch_off:
                self.soft = False
            target = c.k_low if self.soft else (c.k_high if self.memory > 0 else c.k_low)
        # K_prev in the smoothing is the previously applied stiffness (see docs/assumptions.md).
        self._history.append(c.ema * target + (1 - c.ema) * self.k)
        self.k = sum(self._history) / len(self._history)
        return self.k


def _sign(x: float) -> float:
    return (x > 0) - (x < 0)


class Guidance(Protocol):
    def heading(self, obs: Observation) -> float:
        """Reference heading for the leader (rad)."""


class TargetDirection:
    """TDT: head straight for the target's bearing; needs no map."""

    def heading(self, obs: Observation) -> float:
        return obs.target_bearing


@dataclass(frozen=True)
class WaypointConfig:
    """Waypoint following of the A* methods (spec section 4)."""

    reach_radius: float = param(0.5, gt=0, unit="m",
                                doc="advance when the leader is this close to the current waypoint")
    patience: float = param(90.0, gt=0, unit="s", doc="advance anyway after this long on one waypoint")


class WaypointGuidance:
    """Follow a list of waypoints (n, 2) in world XY (m); the last one is the target."""

    def __init__(self, waypoints: np.ndarray, cfg: WaypointConfig = WaypointConfig()):
        wp = np.asarray(waypoints, float)
        if wp.ndim != 2 or wp.shape[1] != 2 or len(wp) == 0:
            raise ValueError(f"waypoints must have shape (n, 2), got {wp.shape}")
        self.wp, self.cfg = wp, cfg
        self.index = 0
        self._since = 0.0

    def heading(self, obs: Observation) -> float:
        p = obs.pos[0, :2]
        d = np.hypot(self.wp[:, 0] - p[0], self.wp[:, 1] - p[1])
        last = len(self.wp) - 1
        i = self.index
        if i < last:
            later = i + 1 + int(np.argmin(d[i + 1 :]))
            if d[later] < d[i]:
                i = later
            elif d[i] < self.cfg.reach_radius or obs.t - self._since > self.cfg.patience:
                i += 1
        if i != self.index:
            self.index, self._since = i, obs.t
        return math.atan2(self.wp[i, 1] - p[1], self.wp[i, 0] - p[0])


class Command:
    """What a body law returns each period.

    Attributes:
        wheel_speed: (n, 2) [left, right] targets for the velocity servos (rad/s);
            ``wheel_flat`` is the same memory as one row [l0, r0, l1, r1, ...].
        yaw_stiffness: common yaw-spring stiffness (N m/rad), or None to leave it.
        yaw_target: (n-1,) yaw-servo targets (rad), or None.
        tau_env: the body law's last |tau_env| estimate (N m), NaN where it has none; logged.
    """

    __slots__ = ("wheel_speed", "wheel_flat", "yaw_stiffness", "yaw_target", "tau_env")

    def __init__(self, n: int):
        self.wheel_speed = np.zeros((n, 2))
        self.wheel_flat = self.wheel_speed.reshape(-1)  # a view: [l0, r0, l1, r1, ...]
        self.yaw_stiffness: float | None = None
        self.yaw_target: np.ndarray | None = None
        self.tau_env = float("nan")


class BodyLaw(Protocol):
    def __call__(self, obs: Observation, heading_ref: float, cmd: Command) -> None:
        """Fill ``cmd`` in place."""

    #: the last |tau_env| estimate (N m), NaN where the law has none
    tau_env: float


def _drive(out: list[float], e: float, drive: DriveConfig) -> None:
    """Append one unit's [left, right] = [v - g e, v + g e] (as ``(-(g e)) + v``, ``g e + v``:
    the rounding of the vectorised law this replaced, bitwise)."""
    m = e * drive.turn_gain
    out += ((-m) + drive.wheel_speed, m + drive.wheel_speed)


class CWCLaw:
    """CWC and CS: followers copy the predecessor's heading; yaw stiffness from the law.

    Written on Python floats: for six units one numpy call costs more than the arithmetic it
    does, and this runs every control period (the wrap is :func:`wrap_scalar`, bitwise equal
    to the array :func:`wrap`).
    """

    def __init__(self, n: int, drive: DriveConfig, law: StiffnessLawConfig, control_period: float):
        self.drive, self.law = drive, StiffnessLaw(law, control_period)

    @property
    def tau_env(self) -> float:
        return self.law.tau_env

    def __call__(self, obs: Observation, heading_ref: float, cmd: Command) -> None:
        yaw = obs.yaw.tolist()
        e0 = wrap_scalar(heading_ref - yaw[0])
        out: list[float] = []
        _drive(out, e0, self.drive)
        for ahead, behind in zip(yaw, yaw[1:]):
            _drive(out, wrap_scalar(ahead - behind), self.drive)
        cmd.wheel_flat[:] = out
        tl, tr = obs.wheel_torque[0].tolist()
        cmd.yaw_stiffness = self.law.update(e0, float(obs.yaw_rate[0]), tl, tr, float(obs.joint_yaw[0]))


@dataclass(frozen=True)
class HeadFollowingConfig:
    """MJ (ACM-R4-like) head-following control (spec section 4)."""

    follower_wheel_speed: float = param(math.pi / 2, gt=0, unit="rad/s",
                                        doc="constant wheel speed of the followers (units 2-6)")
    dead_band: float = param(math.radians(25.0), ge=0, le=math.pi, unit="rad",
                             doc="|e| below which the head joint target is 0")
    head_angle: float = param(math.radians(35.0), ge=0, le=math.pi, unit="rad",
                              doc="head joint target magnitude outside the dead band")
    ema: float = param(0.03, gt=0, le=1, doc="smoothing weight of the head target")
    delay_steps: int = param(20, ge=1, doc="control periods by which each joint repeats its predecessor's command")
    compliance: float = param(0.01, ge=0, unit="rad/(N m)", doc="torque-to-angle compliance")


class HeadFollowing:
    """MJ: the head joint bends toward the target; each joint repeats it 0.5 s later."""

    tau_env = float("nan")

    def __init__(self, n: int, drive: DriveConfig, cfg: HeadFollowingConfig):
        self.drive, self.cfg = drive, cfg
        self.a = 0.0
        # history[j] holds joint j's past compliant-free commands, newest last
        self._history = [deque([0.0] * cfg.delay_steps, maxlen=cfg.delay_steps) for _ in range(n - 1)]
        self._targets = np.zeros(n - 1)

    def __call__(self, obs: Observation, heading_ref: float, cmd: Command) -> None:
        c = self.cfg
        e0 = wrap_scalar(heading_ref - float(obs.yaw[0]))
        lead: list[float] = []
        _drive(lead, e0, self.drive)
        cmd.wheel_flat[:2] = lead
        cmd.wheel_flat[2:] = c.follower_wheel_speed
        target = 0.0 if abs(e0) < c.dead_band else math.copysign(c.head_angle, e0)
        self.a = c.ema * target + (1 - c.ema) * self.a
        base = self.a
        for j, hist in enumerate(self._history):
            delayed = hist[0]  # the predecessor's command delay_steps periods ago
            hist.append(base)
            self._targets[j] = base - c.compliance * obs.yaw_torque[j]
            base = delayed
        cmd.yaw_target = self._targets


@dataclass(frozen=True)
class FollowConfig:
    """D: follow the predecessor's position (spec section 4)."""

    bearing_gain: float = param(10.0, ge=0, doc="gain on the bearing error before the differential term (spec: 10)")
    speed_gain: float = param(5.0, ge=0, unit="rad/s/m", doc="wheel speed per metre of excess distance")
    stop_distance: float = param(0.1, ge=0, unit="m", doc="followers stop within this distance")
    max_wheel_speed: float = param(6.0, gt=0, unit="rad/s",
                                   doc="cap on a follower's wheel-speed command; the spec gives none, and without one "
                                       "a follower that falls a few metres behind is commanded tens of rad/s, races, "
                                       "and MuJoCo diverges (docs/assumptions.md)")


class FollowByPosition:
    """D: six free units; each follower steers to its predecessor's position."""

    tau_env = float("nan")

    def __init__(self, n: int, drive: DriveConfig, cfg: FollowConfig):
        self.drive, self.cfg = drive, cfg

    def __call__(self, obs: Observation, heading_ref: float, cmd: Command) -> None:
        c, d = self.cfg, self.drive
        e0 = wrap(heading_ref - obs.yaw[0])
        cmd.wheel_speed[0, 0] = d.wheel_speed - d.turn_gain * e0
        cmd.wheel_speed[0, 1] = d.wheel_speed + d.turn_gain * e0
        rel = obs.pos[:-1, :2] - obs.pos[1:, :2]
        dist = np.hypot(rel[:, 0], rel[:, 1])
        err = c.bearing_gain * wrap(np.arctan2(rel[:, 1], rel[:, 0]) - obs.yaw[1:])
        base = c.speed_gain * (dist - c.stop_distance)
        go = dist > c.stop_distance
        cap = c.max_wheel_speed
        cmd.wheel_speed[1:, 0] = np.where(go, np.clip(base - d.turn_gain * err, -cap, cap), 0.0)
        cmd.wheel_speed[1:, 1] = np.where(go, np.clip(base + d.turn_gain * err, -cap, cap), 0.0)
