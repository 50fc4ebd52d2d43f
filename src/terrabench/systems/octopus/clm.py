"""Compound locomotion mode (CLM): four arms walk while the crawlers drive (paper, Control system).

The rules are small pure functions on measured values (each unit-tested); :class:`CLMController`
strings them together: terrain exploration from the arm tips, the COG height and the travel past
the edge, the front-flipper torque rule, the crawl gait with three-phase arm transfers ended by
the elbow-torque contact signal, the arm stop cases, and the step-climbing sequence (eqs. 28-29).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from terrabench.config import param
from terrabench.systems.base import Transition, events_info
from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus.robot import ARMS, CORNER, RobotConfig

FLAT, UP, DOWN, UNDETECTABLE = "flat", "up-step", "down-step", "undetectable"
GAIT_ORDER = ("RR", "RF", "LR", "LF")  # inferred from the paper's Fig. 14 description
ARM_INDEX = {k: i for i, k in enumerate(ARMS)}
#: elbow angle the lift phase straightens to (rad): the lifted tip then clears ~0.65 m
ELBOW_LIFT = 0.3


@dataclass(frozen=True)
class CLMConfig:
    """CLM parameters (rad per 0.02 s tick unless said otherwise).

    Attributes:
        track_speed: crawler surface speed in compound mode (m/s).
        climb_track_speed: crawler speed while lifting on a step (m/s).
        sigma: (sigma1, sigma2, sigma3) terrain-case thresholds (m).
        t0: flipper torque threshold T0 (N m).
        d_a: flipper step dA of the torque rule.
        a0: front flipper limit A0 (rad) (85 deg).
        d_b_flip: flipper step dB at the limit.
        flipper_start: front flipper angle on flat ground (rad); rear flippers start at 0.
        arm_ab: boom lift angle A_B of a transfer (our sign: < 0 is up) (rad).
        d_swing: swing step dA of a transfer; d_lift: boom/elbow step dB of a transfer.
        k_boom: boom gain K of eqs. 19-21 (per tick).
        contact_torque: elbow-torque change that signals a tip contact (N m).
        hit_torque: elbow-torque change of a supporting arm that signals a collision (N m).
        press: a supporting tip's target sits this far below its measured height (m): a press of
            bounded force, so the crawlers carry most of the load (eqs. 22-27, :meth:`_support`).
        arm_moving: supporting arms follow the body (eqs. 22-27); False (a control for the
            tests) keeps their joint targets fixed in {R}, so their tips roll with the body.
        reach_min: (front, rear) arms: a foothold behind this x in {R} is out of range (m); the
            crawlers wait for its transfer.
        lower_dz: a lowering tip's target descends this much a tick (m) (0.5 m/s), three times
            that while more than 0.15 m above the target height.
        tau_filter: per-tick weight of the elbow torque in its free-motion reference while lowering.
        settle_dz, settle_ticks: a landed tip that moves less than settle_dz (m) a tick for
            settle_ticks ticks has settled: it is a support.
        heading_gain, heading_dv: the heading hold (:func:`steer`): the gyro yaw rate integrated
            stands for the operator's move direction; crawler speeds differ by gain x heading
            (m/s per rad), at most heading_dv (m/s).
        phase_timeout: a transfer's lift or swing phase that has not finished in this long moves on
            to the next phase from where the arm is (s); a blocked swing first lifts the arm
            ``extra_lift`` rad higher (boom) and swings again, until the arm lands where it was sent.
        release_d_e, release_d_f: boom and flipper steps of the release (rad/tick): quasi-static
            (0.25 and 0.5 rad/s), where eqs. 28-29's dE and dF would drop the body in 0.7 s.
        release_tilt: the nose rising this much while releasing means the COG is not over the
            top yet (rad): the climb resumes and drives ``release_more`` m further (m).
        tilt_contact: the body pitching or rolling this much while an arm lowers = that arm's tip
            carries load: it has landed (rad).
        stall_dz: a lowering tip this far above its target has landed (stopped following) (m).
        pit_depth: no ground this far below the transfer target: a pit (arm stop case 3) (m).
        reach_max: a foothold farther than this from its arm's mount, horizontally, is out of
            range too (m) (l1 + l2 = 0.9 m reaches 0.87 m at the ground's depth).
        targets: transfer target tips in {R} (x, |y|, z) for (front, rear) arms (m), Table 2's analogue.
        d_c, d_d: arm stop thresholds dC (x) and dD (z) (m).
        gait_pause: support time between two transfers (s).
        d_f: flipper step dF of eq. 29 (the lift moves tip targets, not booms, so eq. 28's dE has
            no field; the release steps are release_d_e and release_d_f).
        climb_distance: L of eqs. 28-29, travel past the edge before release (m) (0.6 x 0.5 m).
        h2: H2 of the COG-height rule: height of the robot origin above the track bottom less the
            tip radius (m) (fixed, like the paper's COG).
        release_boom: boom angle the arms return to on release (rad).
        lift_margin: while lifting, booms hold once H exceeds H_EST by this (m) (our addition: eq. 28
            read literally keeps lowering the booms until S > L and tips the robot over).
        pitch_cap: while lifting, front booms hold above this pitch, rear booms below minus it (rad).
        flip_min: lowest flipper command while climbing (rad).
        max_lead: largest lead of a joint command over the measured angle (rad).
        edge_angle, edge_time: a front flipper steeper than edge_angle in the level frame (encoder +
            IMU pitch) that has stopped rising for edge_time (s) is, with an up-step sensed, an edge
            ahead as the limit A0 is: at a low riser the edge presses near the pivot and the torque
            rule stalls below the limit (the CLM riser stalls at 100-250 mm).
        mount_pitch: the nose pitched up this much (IMU) with an up-step sensed (four tips down)
            also starts a climb: the crawlers are mounting an edge with the rear below it, as on the
            next terrace after a release; the lift then raises the rear first (pitch_cap).
        max_resumes: releases of one climb that may go back to climbing when the nose rises
            (release_tilt); after them the release walks on, and the walk's triggers (mount_pitch)
            start a fresh climb with H_EST re-estimated from the four tips (the next terrace).
            With 0 the 450 mm sweep step fails 2/3 (its four-tip case is past sigma2, so no walk
            trigger), with 3 it climbs 3/3.
        guard_pitch: the paper's real-time stability monitor in the walk: beyond this nose-up
            pitch (below the ~0.93 rad static tip-back angle on the rear flippers) the crawlers back
            off; without it CLM walked its front arms up the 500-550 mm risers it cannot climb and
            turned over (3 of 6 sweep trials, after 60 s).
        climb_hold: while the lifted body drives, the supporting tips hold their footholds (their
            targets move back by the crawler travel, as in walking), so a front tip on a short tread
            does not roll into the next riser and block the climb.
    """

    track_speed: float = param(0.1, gt=0, unit="m/s", doc="crawler surface speed in compound mode")
    climb_track_speed: float = param(0.06, gt=0, unit="m/s", doc="crawler speed while lifting on a step")
    sigma: tuple[float, float, float] = param((0.05, 0.45, 0.45), length=3, ge=0, unit="m",
                                              doc="(sigma1, sigma2, sigma3) terrain-case thresholds")
    t0: float = param(40.0, gt=0, unit="N m", doc="flipper torque threshold T0")
    d_a: float = param(0.02, gt=0, unit="rad/tick", doc="flipper step dA of the torque rule")
    a0: float = param(1.4835, ge=-math.pi, le=math.pi, unit="rad", doc="front flipper limit A0")
    d_b_flip: float = param(0.02, gt=0, unit="rad/tick", doc="flipper step dB at the limit")
    flipper_start: float = param(0.5, ge=-math.pi, le=math.pi, unit="rad", doc="front flipper angle on flat ground")
    arm_ab: float = param(-0.6, ge=-math.pi, le=math.pi, unit="rad",
                          doc="boom lift angle A_B of a transfer (< 0 is up)")
    d_swing: float = param(0.04, gt=0, unit="rad/tick", doc="swing step of a transfer")
    d_lift: float = param(0.04, gt=0, unit="rad/tick", doc="boom/elbow step of a transfer")
    k_boom: float = param(0.15, ge=0, unit="1/tick", doc="boom gain K of eqs. 19-21")
    contact_torque: float = param(20.0, gt=0, unit="N m", doc="elbow-torque change that signals a tip contact")
    hit_torque: float = param(45.0, gt=0, unit="N m",
                              doc="elbow-torque change of a supporting arm that signals a collision")
    press: float = param(0.005, ge=0, unit="m", doc="a supporting tip's target this far below its measured height")
    arm_moving: bool = param(True, doc="supporting arms follow the body (eqs. 22-27); False keeps their targets fixed")
    reach_min: tuple[float, float] = param((0.2, -0.9), length=2, unit="m",
                                           doc="(front, rear) arms: a foothold behind this x in {R} is out of range")
    reach_max: float = param(0.8, gt=0, unit="m", doc="a foothold farther than this from its arm mount is out of range")
    lower_dz: float = param(0.01, gt=0, unit="m/tick", doc="descent of a lowering tip's target per tick")
    tau_filter: float = param(0.15, ge=0, le=1, doc="per-tick weight of the elbow torque in its free-motion reference")
    settle_dz: float = param(0.0005, gt=0, unit="m/tick", doc="a landed tip moving less than this a tick is settling")
    settle_ticks: int = param(5, ge=1, doc="ticks of settling before a landed tip is a support")
    stall_dz: float = param(0.04, gt=0, unit="m", doc="a lowering tip this far above its target has landed")
    tilt_contact: float = param(0.01, gt=0, unit="rad", doc="body tilt while an arm lowers that means its tip landed")
    heading_gain: float = param(0.2, ge=0, unit="m/s/rad",
                                doc="crawler speed difference per rad of heading error (0: no heading hold)")
    heading_dv: float = param(0.03, ge=0, unit="m/s", doc="largest crawler speed difference of the heading hold")
    extra_lift: float = param(0.5, ge=0, unit="rad", doc="extra boom lift after a blocked swing")
    phase_timeout: float = param(3.0, gt=0, unit="s",
                                 doc="a transfer's lift or swing phase unfinished this long moves on")
    release_d_e: float = param(0.005, gt=0, unit="rad/tick", doc="boom step of the release")
    release_d_f: float = param(0.01, gt=0, unit="rad/tick", doc="flipper step of the release")
    release_tilt: float = param(0.08, gt=0, unit="rad", doc="nose rise while releasing that resumes the climb")
    release_more: float = param(0.15, ge=0, unit="m", doc="extra drive after a resumed climb")
    pit_depth: float = param(0.45, gt=0, unit="m", doc="no ground this far below the transfer target: a pit")
    targets: tuple[tuple[float, float, float], tuple[float, float, float]] = param(
        ((0.75, 0.55, -0.05), (-0.45, 0.55, -0.05)), length=2, unit="m",
        doc="transfer target tips in {R} (x, |y|, z) for (front, rear) arms")
    d_c: float = param(0.1, gt=0, unit="m", doc="arm stop threshold dC (x)")
    d_d: float = param(0.08, gt=0, unit="m", doc="arm stop threshold dD (z)")
    gait_pause: float = param(0.4, ge=0, unit="s", doc="support time between two transfers")
    d_f: float = param(0.0873, gt=0, unit="rad/tick", doc="flipper step dF of eq. 29")
    climb_distance: float = param(0.3, gt=0, unit="m", doc="L of eqs. 28-29: travel past the edge before release")
    h2: float = param(0.05, unit="m",
                      doc="H2 of the COG-height rule (origin above the track bottom less the tip radius)")
    release_boom: float = param(0.0, ge=-math.pi, le=math.pi, unit="rad",
                                doc="boom angle the arms return to on release")
    max_lead: float = param(0.35, gt=0, unit="rad", doc="largest lead of a joint command over the measured angle")
    pitch_cap: float = param(0.25, gt=0, le=math.pi / 2, unit="rad", doc="while lifting, booms hold beyond this pitch")
    lift_margin: float = param(0.03, ge=0, unit="m", doc="while lifting, booms hold once H exceeds H_EST by this")
    flip_min: float = param(-0.8, ge=-math.pi, le=math.pi, unit="rad", doc="lowest flipper command while climbing")
    lift_dz: float = param(0.002, gt=0, unit="m/tick", doc="lift: every tip target moves down by this a tick")
    flip_lead: float = param(0.05, ge=0, unit="rad",
                             doc="flipper command kept within this of the measured angle (eq. 29)")
    flip_wait: float = param(0.5, ge=0, doc="front flippers wait while H < flip_wait x H_EST")
    edge_angle: float = param(1.2, gt=0, le=math.pi, unit="rad",
                              doc="a front flipper this steep (level frame), no longer rising, with an up-step: climb")
    edge_time: float = param(1.0, ge=0, unit="s", doc="the steep front flipper has stopped rising this long")
    mount_pitch: float = param(0.35, gt=0, le=math.pi / 2, unit="rad",
                               doc="the nose pitched up this much with an up-step sensed starts the climb")
    max_resumes: int = param(3, ge=0, doc="releases of one climb that may resume it (nose rising) before walking on")
    guard_pitch: float = param(0.9, gt=0, le=math.pi / 2, unit="rad",
                               doc="walking with the nose up beyond this, the crawlers back off")
    climb_hold: bool = param(True, doc="while climbing, supporting tips hold their footholds (arm moving)")


# ---------------------------------------------------------------------------- pure rules
def terrain_case(z: np.ndarray, sigma: tuple[float, float, float]) -> str:
    """Terrain case from the four tip heights z (LF, RF, LR, RR) in {C} (paper's cases 1-3).

    The paper's P1..P4 are LF, RF, RR, LR, so its z1 - z4 is LF - LR and z2 - z3 is RF - RR.
    """
    s1, s2, s3 = sigma
    a, b = z[0] - z[2], z[1] - z[3]
    if abs(a) < s1 and abs(b) < s1:
        return FLAT
    if s1 < a < s2 and s1 < b < s2:
        return UP
    if -s3 < a < -s1 and -s3 < b < -s1:
        return DOWN
    return UNDETECTABLE


def step_height(z: np.ndarray) -> float:
    """H_EST = (z1 + z2 - z3 - z4) / 2: front tips above rear tips (m) (eq. 9)."""
    return float((z[0] + z[1] - z[2] - z[3]) / 2)


def terrain_angles(p: np.ndarray) -> tuple[float, float]:
    """Terrain pitch and roll (rad) from the tips p (4, 3) in {C} (eqs. 7-8, as angles).

    T_P: front pair vs rear pair; T_R: left pair vs right pair.
    """
    dxp = p[0, 0] + p[1, 0] - p[2, 0] - p[3, 0]
    dzp = p[0, 2] + p[1, 2] - p[2, 2] - p[3, 2]
    dyr = p[0, 1] + p[2, 1] - p[1, 1] - p[3, 1]
    dzr = p[0, 2] + p[2, 2] - p[1, 2] - p[3, 2]
    return math.atan2(dzp, dxp), math.atan2(dzr, dyr)


def cog_height(rear_tips_c: np.ndarray, h2: float) -> float:
    """H = H1 - H2 (m) (eqs. 10-12): how high the robot stands above its rear-arm contacts.

    H1 = |Z_C| of the rear tips' midpoint P in {C} (level frame at the robot origin, from the
    IMU roll and pitch); H2 the fixed height of the origin above the track bottom less the tip
    radius (the COG is fixed in the paper). H is then the track bottom's height above the
    ground the rear arms stand on: once H > H_EST the tracks clear the step.
    """
    h1 = abs(float(np.mean(rear_tips_c[:, 2])))
    return h1 - h2


def travel(s: float, track_speed: float, pitch: float, dt: float) -> float:
    """S += L cos(R_P), L = track_speed * dt (m) (the travel past the edge, no slip)."""
    return s + track_speed * dt * math.cos(pitch)


def steer(v: float, heading: float, gain: float, dv_max: float) -> tuple[float, float]:
    """(left, right) crawler speeds (m/s) that turn the robot back to its start heading.

    ``heading`` (rad, > 0 turned left) is the integrated gyro yaw rate: it stands for the paper's
    operator, who gave the move direction. The sides differ by ``gain`` x heading, at most
    ``dv_max`` each way (a robot waiting with ``v`` = 0 turns in place).
    """
    dv = max(-dv_max, min(dv_max, gain * heading))
    return v + dv, v - dv


def flipper_rule(a_prev: float, tau_prev: float, t0: float, d_a: float, a0: float, d_b: float) -> tuple[float, str]:
    """Front-flipper angle command from the last angle and torque (cases 1-3); returns (A, case).

    Case 3 (at the limit A0) comes first: the limit means an obstacle ahead.
    """
    if a_prev > a0 - 1e-3:
        return a_prev - d_b, "limit"
    if abs(tau_prev) < t0:
        return a_prev, "low"
    return a_prev - d_a * math.copysign(1.0, tau_prev), "high"


def arm_stop_case(p_actual: np.ndarray, p_target: np.ndarray, d_c: float, d_d: float) -> str:
    """Where a transferred tip stopped relative to its target (arm stop cases 1-3, else reached)."""
    dx = abs(p_actual[0] - p_target[0])
    dz = p_actual[2] - p_target[2]
    if dx > d_c:
        return "blocked"   # case 1: an obstacle between the arm and the target
    if dz > d_d:
        return "on-top"    # case 2: stopped on top of an obstacle
    if dz < -d_d:
        return "pit"       # case 3: stopped in a pit
    return "reached"


def contact_detected(tau: float, tau_ref: float, threshold: float) -> bool:
    """Elbow-torque contact signal: the torque rises by ``threshold`` above its free-motion value.

    Our elbow torque > 0 turns the forearm down; a tip pressed up by the ground pushes it up, so
    the servo's torque jumps in the down direction (the paper's "torque reaches the setting value").
    """
    return tau - tau_ref > threshold


def transfer_step(phase: int, q: np.ndarray, cmd: np.ndarray, target: np.ndarray, ab: float,
                  d_swing: float, d_lift: float, k: float) -> tuple[int, np.ndarray]:
    """One tick of the three-phase arm transfer (eqs. 19-21); returns (phase, new command).

    Phase 1 lifts boom and elbow until the boom reaches A_B; phase 2 swings to the target swing;
    phase 3 lowers boom and elbow toward (and past) the target until contact (checked by the
    caller). Phase 4 = the joints hit their lower bound without contact (a deep pit).
    """
    c = cmd.copy()
    if phase == 1:
        c[1] = q[1] + k * (ab - q[1]) - 0.02
        c[2] = max(c[2] - d_lift, ELBOW_LIFT)
        if q[1] <= ab + 0.03 and q[2] <= ELBOW_LIFT + 0.05:
            return 2, c
        return 1, c
    if phase == 2:
        c[0] = c[0] + float(np.clip(target[0] - c[0], -d_swing, d_swing))
        # arm stop case 1: the swing is blocked (it lags its command): lower it where it is
        if abs(target[0] - q[0]) < 0.03 or abs(c[0] - q[0]) > 0.25:
            c[0] = q[0]
            return 3, c
        return 2, c
    if phase == 3:
        c[1] = c[1] + d_lift * (1.0 if c[1] < target[1] + 0.5 else 0.0)
        c[2] = c[2] + float(np.clip(target[2] - c[2], -d_lift, d_lift))
        if c[1] >= target[1] + 0.5 - 1e-9:
            return 4, c
        return 3, c
    return phase, c


def climb_rule(boom: float, flip: float, h: float, h_est: float, s: float, l_set: float,
               d_e: float, d_f: float, boom_rest: float) -> tuple[float, float, bool]:
    """Eqs. 28-29: (boom, flipper) commands and whether the release has begun.

    While H < H_EST or S < L: booms down (+dE, our sign) and flippers down (-dF).
    Then: booms back up (-dE) while above their rest angle, flippers up (+dF) while below 0.
    """
    if h < h_est or s < l_set:
        return boom + d_e, flip - d_f, False
    nb = boom - d_e if boom > boom_rest else boom
    nf = flip + d_f if flip < 0.0 else flip
    return nb, min(nf, 0.0) if flip < 0.0 else nf, True


# ---------------------------------------------------------------------------- command
@dataclass
class Command:
    """Track speeds (m/s, left/right), flipper angle targets (4,) and arm joint targets (4, 3) (rad)."""

    track: np.ndarray = field(default_factory=lambda: np.zeros(2))
    flip: np.ndarray = field(default_factory=lambda: np.zeros(4))
    arm: np.ndarray = field(default_factory=lambda: np.zeros((4, 3)))
    mode: int = 0  # controller state code (logged)
    moving_arm: int = -1  # index of the arm in transfer, -1 none (logged)


# ---------------------------------------------------------------------------- controller
WALK, CLIMB, RELEASE, INIT = 0, 1, 2, 3
#: names of the controller states (the logged ``mode`` codes) in events and timelines
MODE_NAMES = {WALK: "walk", CLIMB: "climb", RELEASE: "release", INIT: "init"}
#: arm sub-states in events: ``"<arm>.support"`` / ``"<arm>.transfer"``
SUPPORT, TRANSFER = "support", "transfer"


class CLMController:
    """The CLM state machine: ``obs -> Command``."""

    def __init__(self, cfg: CLMConfig, robot: RobotConfig, dt: float = 0.02):
        self.cfg, self.robot, self.dt = cfg, robot, dt
        self.cmd = Command()
        self.targets = {k: self._target(k) for k in ARMS}
        self.phase = {k: 0 for k in ARMS}  # 0 support, 1-3 transfer phases
        self.tau_ref = np.zeros(4)
        self.t3 = np.zeros(4)
        self.contact = np.zeros(4, bool)
        self.tip_c = np.zeros((4, 3))
        self.tip_r = np.zeros((4, 3))
        self.foot = np.zeros((4, 3))  # footholds of the supporting arms in {R} (m)
        self.tip_z = self.prev_tip_z = np.zeros(4)
        self.low_z = np.zeros(4)
        self.phase_t = np.zeros(4)  # time in the current lift/swing phase (s)
        self.extra_lift = np.zeros(4)  # boom lift beyond A_B after a blocked swing (rad)
        self.att0 = (0.0, 0.0)  # IMU pitch and roll when the lowering began (rad)
        self.landing = np.zeros(4, bool)  # landed, pressing, not yet settled
        self.still = np.zeros(4, int)  # tip height target of a lowering arm in {R} (m)
        self.tp = 0.0  # terrain pitch T_P of the last four-tip exploration (rad)
        self.out_of_reach = False
        self.out_arm = ""  # the last arm whose foothold left its range (diagnostics)
        self.flip_prev, self.flip_still = 0.0, 0.0  # the front flipper angle and how long it has held (s)
        self.guarding = False  # the walk's pitch guard is backing the crawlers off
        self.caster = np.zeros(4, bool)  # landed beyond its range: rolls with the body until its turn
        self.queue: list[str] = list(ARMS)  # place all four arms first (init)
        self.next_gait = 0
        self.pause_until = 0.0
        self.state = INIT
        self.s = 0.0
        self.h_est = 0.0
        self.last_case = FLAT
        self.started = False
        self.queue_reason: dict[str, str] = {}
        self.s_release = cfg.climb_distance
        self.heading = 0.0  # integrated gyro yaw rate (rad): the operator's move direction is 0
        self.release_pitch = 0.0
        self.resumes = 0  # releases of this climb that resumed it
        self.events: list[Transition] = []

    def info(self) -> dict:
        return events_info(self.events)

    def _goto(self, t: float, dst: int, reason: str) -> None:
        """Change the controller state, recording the transition."""
        self.events.append(Transition(t, MODE_NAMES[self.state], MODE_NAMES[dst], reason))
        self.state = dst

    def _arm_event(self, t: float, k: str, src: str, dst: str, reason: str) -> None:
        self.events.append(Transition(t, f"{k}.{src}", f"{k}.{dst}", reason))

    def _target(self, k: str) -> np.ndarray:
        front, rear = self.cfg.targets
        x, y, z = front if k[1] == "F" else rear
        return np.array([x, y if k[0] == "L" else -y, z])

    # ---------------------------------------------------------------- helpers
    def _start(self, obs) -> None:
        c = self.cmd
        c.arm[:] = obs.q_arm
        c.flip[:] = [self.cfg.flipper_start, self.cfg.flipper_start, 0.0, 0.0]
        self.started = True

    def _lead(self, obs) -> None:
        m = self.cfg.max_lead
        q = obs.q_arm
        np.minimum(np.maximum(self.cmd.arm, q - m, out=self.cmd.arm), q + m, out=self.cmd.arm)

    def _transfer(self, obs) -> int:
        """Advance the arm in transfer (if any); returns its index or -1."""
        cfg = self.cfg
        moving = [k for k in ARMS if self.phase[k]]
        if not moving:
            if obs.t < self.pause_until or self.landing.any():
                return -1
            if self.queue:
                k = self.queue.pop(0)
            elif self.state == WALK:
                k = GAIT_ORDER[self.next_gait % 4]
                self.next_gait += 1
            else:
                return -1
            self.phase[k] = 1
            self.contact[ARM_INDEX[k]] = False
            self._arm_event(obs.t, k, SUPPORT, TRANSFER, self.queue_reason.pop(k, "gait turn"))
            moving = [k]
        k = moving[0]
        i = ARM_INDEX[k]
        q = obs.q_arm[i]
        tgt = ak.ik(self.targets[k], self.robot, k)
        ph = self.phase[k]
        if ph == 3:
            # lower: the tip target descends straight down over the transfer target (IK), so the
            # tip lands where it was sent; contact = the elbow torque signal, or the tip stops
            # following its descent (encoders)
            self.t3[i] += self.dt
            tx, ty, tz = self.targets[k]
            # fast while high above the expected ground, then slow for a soft touch
            self.low_z[i] -= cfg.lower_dz * (3.0 if self.low_z[i] > tz + 0.15 else 1.0)
            touched = abs(obs.tau_elbow[i] - self.tau_ref[i]) > cfg.contact_torque
            # blocked: the tip lags its target and has stopped descending (a servo lag alone
            # while the target falls fast is not a contact)
            stopped = self.tip_r[i, 2] - self.prev_tip_z[i] > -0.25 * cfg.lower_dz
            blocked = stopped and self.tip_r[i, 2] - self.low_z[i] > cfg.stall_dz
            # or the body tilts while the arm descends: the arm has started to carry it (IMU)
            tilted = max(abs(obs.pitch - self.att0[0]), abs(obs.roll - self.att0[1])) > cfg.tilt_contact
            if self.t3[i] > 0.2 and (touched or blocked or tilted):
                self._land(obs, k, i)
                return i
            # the free-motion reference follows the slow changes (gravity, servo lag, the IK's
            # posture): a contact is a jump above it
            self.tau_ref[i] += cfg.tau_filter * (obs.tau_elbow[i] - self.tau_ref[i])
            new_ph = 4 if self.low_z[i] < tz - cfg.pit_depth else 3
            c = ak.ik(np.array([tx, ty, self.low_z[i]]), self.robot, k)
        else:
            ab = max(cfg.arm_ab - self.extra_lift[i], self.robot.boom_range[0] + 0.05)
            new_ph, c = transfer_step(ph, q, self.cmd.arm[i], tgt, ab, cfg.d_swing, cfg.d_lift, cfg.k_boom)
            # arm stop case 1 in time: a swing the arm cannot finish (a link against an obstacle)
            # lifts the arm higher and swings again, once; a lift or a second blocked swing goes on
            # to the next phase from where the arm is
            self.phase_t[i] = self.phase_t[i] + self.dt if new_ph == ph else 0.0
            if self.phase_t[i] > cfg.phase_timeout:
                self.phase_t[i] = 0.0
                if ph == 2 and self.extra_lift[i] < cfg.extra_lift:
                    self.extra_lift[i] = cfg.extra_lift
                    new_ph = 1
                    self._arm_event(obs.t, k, TRANSFER, TRANSFER,
                                    f"swing blocked for {cfg.phase_timeout:g} s: lift {cfg.extra_lift:g} rad higher")
                else:
                    new_ph = ph + 1
                    self._arm_event(obs.t, k, TRANSFER, TRANSFER,
                                    f"phase {ph} blocked for {cfg.phase_timeout:g} s: next phase")
                    if ph == 2:
                        c[0] = q[0]
        if ph == 2 and new_ph == 3:
            self.tau_ref[i] = obs.tau_elbow[i]
            self.t3[i] = 0.0
            # the descent starts at the tip's height or lower, where the arm reaches the target
            # without its boom against its upper stop (a knee-up whip that would look like a stop)
            tx, ty, tz = self.targets[k]
            z, lo = float(self.tip_r[i, 2]), self.robot.boom_range[0] + 0.1
            while z > tz and ak.ik(np.array([tx, ty, z]), self.robot, k)[1] < lo:
                z -= 0.02
            self.low_z[i] = z
            self.att0 = (obs.pitch, obs.roll)
        self.cmd.arm[i] = c
        if new_ph == 4:  # joint limit without contact: a deep pit; the arm stays where it is
            self._arm_event(obs.t, k, TRANSFER, SUPPORT, "no ground within reach (pit)")
            self.phase[k] = 0
            self.pause_until = obs.t + cfg.gait_pause
        else:
            self.phase[k] = new_ph
        return i

    def _land(self, obs, k: str, i: int) -> None:
        """The lowering arm stopped (contact signal): it presses (see :meth:`_support`) and is a
        support once its tip has settled (:meth:`_settle`)."""
        cfg = self.cfg
        self.phase[k] = 0
        self.landing[i], self.still[i] = True, 0
        p = self.tip_r[i].copy()
        self.foot[i] = p
        self.cmd.arm[i] = ak.ik(p - np.array([0.0, 0.0, cfg.press]), self.robot, k)

    def _settle(self, obs, k: str, i: int) -> None:
        """A landing tip that has stopped moving (encoders) for ``settle_ticks`` is a support:
        its elbow torque becomes the collision reference and the arm stop case is recorded."""
        cfg = self.cfg
        self.still[i] = self.still[i] + 1 if abs(self.tip_z[i] - self.prev_tip_z[i]) < cfg.settle_dz else 0
        if self.still[i] < cfg.settle_ticks:
            return
        self.landing[i], self.contact[i] = False, True
        self.tau_ref[i] = obs.tau_elbow[i]
        case = arm_stop_case(self.tip_r[i], self.targets[k], cfg.d_c, cfg.d_d)
        self._arm_event(obs.t, k, TRANSFER, SUPPORT, f"landed: {case}")
        if case == "reached":
            self.extra_lift[i] = 0.0
        self.pause_until = obs.t + cfg.gait_pause

    def _support(self, obs, v: float) -> bool:
        """Arm moving (eqs. 22-27): each supporting arm's joints follow the body so its tip holds
        its foothold; returns True when a foothold has left its arm's working range.

        The body moves L = v dt a tick along the terrain, at T_P - R_P to its own x axis (T_P the
        terrain pitch from the last four-tip exploration, R_P the IMU pitch), so a foothold moves
        by -L (cos, 0, sin)(T_P - R_P) in {R}. Its height is not predicted but sensed: the target
        sits ``press`` below the tip's measured height (encoders), a press of a bounded force
        (the servo stiffness times ``press``) whatever the body does, so the crawlers carry the
        rest of the load.
        """
        cfg = self.cfg
        mx, my, _ = self.robot.arm_mount
        a = self.tp - obs.pitch
        dx = v * self.dt * math.cos(a)
        out = False
        for i, k in enumerate(ARMS):
            if self.phase[k] or not (self.contact[i] or self.landing[i]):
                continue
            if self.landing[i]:
                self._settle(obs, k, i)
            f = self.foot[i]
            sx, sy = CORNER[k]
            beyond = (f[0] < cfg.reach_min[0 if sx > 0 else 1]
                      or math.hypot(f[0] - sx * mx, f[1] - sy * my) > cfg.reach_max)
            if self.landing[i]:
                # a foothold already beyond the range where the arm landed (a pitched body's
                # descent ends far out): no transfer now brings it back, so the crawlers do not
                # wait for it; the arm rolls with the body (a caster) until its next turn
                self.caster[i] = beyond
            if cfg.arm_moving and not self.caster[i]:
                f[0] -= dx
            f[2] = self.tip_r[i, 2] - cfg.press
            self.cmd.arm[i] = ak.ik(f, self.robot, k)
            if beyond and not self.caster[i]:
                out = True
                self.out_arm = k
                if k in self.queue[1:]:
                    # the crawlers wait for this arm: its transfer comes first
                    self.queue.remove(k)
                    self.queue.insert(0, k)
        return out

    # ---------------------------------------------------------------- climbing
    def _climb(self, obs) -> None:
        """Eqs. 28-29 with a vertical lift and the crawlers loaded (docs/assumptions-octopus.md).

        Lift: every tip target in {R} moves straight down by ``lift_dz`` a tick (IK), so the
        chassis rises vertically on its rolling tips; a boom-only lift (eq. 28 read literally)
        also swings the chassis along the arm planes, backward here, with nothing to stop it.
        The lift holds once H > H_EST + ``lift_margin`` (the track bottom just above the top),
        the front booms hold while the nose is above ``pitch_cap`` (the rear ones below minus it).
        Flippers: eq. 29, all down; the front ones press onto the top with a torque-limited
        lead, so the front crawlers carry load and drive; the rear ones push on the ground.
        S (eq. 5, track odometry) counts from the moment H reaches H_EST: before that the
        crawler front is against the riser and cannot advance. Release (S > L and H > H_EST):
        booms up by dE a tick to their rest angle, flippers up by dF to 0, then walk.
        """
        cfg, c = self.cfg, self.cmd
        c.track[:] = cfg.climb_track_speed
        h = cog_height(self.tip_c[2:], cfg.h2)
        if self.state == CLIMB:
            if h >= self.h_est:
                self.s = travel(self.s, cfg.climb_track_speed, obs.pitch, self.dt)
                if cfg.climb_hold:
                    # arm moving while driving on the lifted body: each tip keeps its foothold
                    # (it does not roll forward into the next riser)
                    self.lift_tgt[:, 0] -= cfg.climb_track_speed * self.dt * math.cos(self.tp - obs.pitch)
            if h < self.h_est + cfg.lift_margin:
                for i in range(len(ARMS)):
                    front = i < 2
                    if (front and obs.pitch > cfg.pitch_cap) or (not front and obs.pitch < -cfg.pitch_cap):
                        continue
                    self.lift_tgt[i, 2] -= cfg.lift_dz
            for i, k in enumerate(ARMS):
                c.arm[i] = ak.ik(self.lift_tgt[i], self.robot, k)
            for f in range(4):
                # eq. 29 (A' - dF), the command kept within flip_lead of the measured angle:
                # a flipper that meets the top (front) or the ground (rear) presses with kp * lead
                front = f < 2
                if front and h < cfg.flip_wait * self.h_est:
                    continue  # the tip is still below the edge: it stays raised against the riser
                c.flip[f] = max(c.flip[f] - cfg.d_f, obs.q_flip[f] - cfg.flip_lead, cfg.flip_min)
            if self.s > self.s_release and h > self.h_est:
                self.release_pitch = obs.pitch
                self._goto(obs.t, RELEASE, f"H = {h:.3f} m > H_EST, S = {self.s:.3f} m > {self.s_release:.2f} m")
        else:  # RELEASE (eqs. 28-29 second cases), at quasi-static rates
            if obs.pitch - self.release_pitch > cfg.release_tilt and self.resumes < cfg.max_resumes:
                self.resumes += 1
                # the nose rises while the booms come up: the rear is dropping, the COG is not yet
                # over the top (odometry counted slip): lift again and drive on
                self.s_release = self.s + cfg.release_more
                self.lift_tgt = self.tip_r.copy()
                self._goto(obs.t, CLIMB, f"pitch rose {obs.pitch - self.release_pitch:.2f} rad > "
                           f"{cfg.release_tilt} while releasing: drive {cfg.release_more} m more")
                return
            for i in range(4):
                if c.arm[i, 1] > cfg.release_boom:
                    c.arm[i, 1] = max(c.arm[i, 1] - cfg.release_d_e, cfg.release_boom)
            for f in range(4):
                if c.flip[f] < 0.0:
                    c.flip[f] = min(c.flip[f] + cfg.release_d_f, 0.0)
            if all(c.arm[i, 1] <= cfg.release_boom + 1e-9 for i in range(4)) and (c.flip >= -1e-9).all():
                # back to walking on the top: arms re-placed, front flippers to their cruise angle
                self._goto(obs.t, WALK, "booms and flippers released")
                self.queue = list(GAIT_ORDER)
                c.flip[:2] = cfg.flipper_start
                self.contact[:] = False

    # ---------------------------------------------------------------- main
    def __call__(self, obs) -> Command:
        cfg, c = self.cfg, self.cmd
        if not self.started:
            self._start(obs)
        # one forward-kinematics pass a tick: the tips in {R} (encoders) and in {C} (+ IMU)
        self.tip_r = ak.fk_all(obs.q_arm, self.robot)
        self.tip_c = self.tip_r @ ak.rotation_rc(obs.roll, obs.pitch).T
        self.prev_tip_z, self.tip_z = self.tip_z, self.tip_r[:, 2].copy()
        self.heading += obs.yaw_rate * self.dt
        z = self.tip_c[:, 2]
        if self.state == INIT:
            c.track[:] = 0.0
            self._support(obs, 0.0)
            i = self._transfer(obs)
            if i < 0 and not self.queue and not any(self.phase.values()) and not self.landing.any():
                self._goto(obs.t, WALK, "four arms placed")
            c.mode, c.moving_arm = self.state, i
            self._lead(obs)
            return c
        if self.state == WALK:
            # the crawlers wait while a foothold is out of its arm's range (its transfer is due)
            v = 0.0 if self.out_of_reach else cfg.track_speed
            if obs.pitch > cfg.guard_pitch:
                # the paper's stability monitor: nose up toward the tip-back angle (~0.93 rad on the
                # rear flippers, ccm.tip_back_angle): the crawlers back off instead of pushing on
                v = -cfg.track_speed
                if not self.guarding:
                    self.events.append(Transition(obs.t, "walk", "walk", f"pitch {obs.pitch:.2f} rad > "
                                                  f"{cfg.guard_pitch}: crawlers back off"))
            self.guarding = obs.pitch > cfg.guard_pitch
            c.track[0], c.track[1] = steer(v, self.heading, cfg.heading_gain, cfg.heading_dv)
            self.out_of_reach = self._support(obs, v)
            for f in (0, 1):
                c.flip[f], _ = flipper_rule(obs.q_flip[f], obs.tau_flip[f], cfg.t0, cfg.d_a, cfg.a0, cfg.d_b_flip)
            # a supporting arm pushed hard (collision): it is transferred next
            for i, k in enumerate(ARMS):
                if (self.phase[k] == 0 and self.contact[i] and k not in self.queue
                        and contact_detected(obs.tau_elbow[i], self.tau_ref[i], cfg.hit_torque)):
                    self.queue.insert(0, k)
                    self.queue_reason[k] = (f"collision: elbow torque {obs.tau_elbow[i] - self.tau_ref[i]:+.0f} N m"
                                            f" > {cfg.hit_torque:g}")
            i = self._transfer(obs)
            all_down = self.contact.all() and not any(self.phase.values())
            if all_down:
                self.tp = terrain_angles(self.tip_c)[0]
            self.last_case = terrain_case(z, cfg.sigma) if all_down else self.last_case
            at_limit = max(obs.q_flip[0], obs.q_flip[1]) > cfg.a0 - 0.1
            # a low riser presses near the flipper pivot: the torque rule stalls below the limit,
            # so a front flipper raised this steep in the level frame (encoder + IMU pitch) that
            # has stopped rising for edge_time also means an edge ahead
            qf = max(obs.q_flip[0], obs.q_flip[1])
            self.flip_still = self.flip_still + self.dt if abs(qf - self.flip_prev) < 0.02 else 0.0
            if self.flip_still == 0.0:
                self.flip_prev = qf
            steep = qf + obs.pitch > cfg.edge_angle and self.flip_still > cfg.edge_time
            # the nose pitched up this much with an up-step sensed: the crawlers are mounting an
            # edge with the rear below it (the next terrace after a release): lift the rear too
            mounting = obs.pitch > cfg.mount_pitch
            if all_down and self.last_case == UP and (at_limit or steep or mounting):
                # per terrace: the nearer (lower) front tip's height over the rear tips
                self.h_est = min(z[0], z[1]) - 0.5 * (z[2] + z[3])
                self.s, self.s_release, self.resumes = 0.0, cfg.climb_distance, 0
                self.lift_tgt = np.array([ak.fk(obs.q_arm[i], self.robot, k) for i, k in enumerate(ARMS)])
                why = ("front flippers at the limit" if at_limit else
                       f"a front flipper steep ({qf + obs.pitch:.2f} rad) and still" if steep else
                       f"nose up {obs.pitch:.2f} rad")
                self._goto(obs.t, CLIMB, f"up-step, H_EST = {self.h_est:.3f} m, {why}")
            c.mode, c.moving_arm = self.state, i
            self._lead(obs)
            return c
        # CLIMB / RELEASE: eqs. 28-29 (lift, drive, release); see _climb
        self._climb(obs)
        c.mode, c.moving_arm = self.state, -1
        self._lead(obs)
        return c
