"""The paper's CLM rules as small pure functions on measured values, and the command both
controllers send (OCTOPUS, Control system; eqs. 19-29). :class:`~terrabench.systems.octopus.clm.
CLMController` strings the rules together; each is unit-tested on its own (tests/octopus)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: elbow angle the lift phase straightens to (rad): the lifted tip then clears ~0.65 m
ELBOW_LIFT = 0.3
#: terrain cases of the four-tip exploration (:func:`terrain_case`)
FLAT, UP, DOWN, UNDETECTABLE = "flat", "up-step", "down-step", "undetectable"


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
    z = rear_tips_c[:, 2].tolist()
    h1 = abs((z[0] + z[1]) / 2 if len(z) == 2 else float(np.mean(rear_tips_c[:, 2])))  # (np.mean's value)
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
        c[0] = c[0] + min(max(target[0] - c[0], -d_swing), d_swing)  # np.clip's value, NaN kept
        # arm stop case 1: the swing is blocked (it lags its command): lower it where it is
        if abs(target[0] - q[0]) < 0.03 or abs(c[0] - q[0]) > 0.25:
            c[0] = q[0]
            return 3, c
        return 2, c
    if phase == 3:
        c[1] = c[1] + d_lift * (1.0 if c[1] < target[1] + 0.5 else 0.0)
        c[2] = c[2] + min(max(target[2] - c[2], -d_lift), d_lift)
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
    stage: int = 0  # the climb's stage (logged): 0 none, CLM's clm.STAGE_NAMES otherwise
    moving_arm: int = -1  # index of the arm in transfer, -1 none (logged)
