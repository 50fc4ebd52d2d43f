"""Arm forward/inverse kinematics and the gravity-aligned frame {C} (paper eqs. 13-16, 10-12)."""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.octopus.robot import ARMS, CORNER, RobotConfig

_SXL = [float(CORNER[k][0]) for k in ARMS]
_SYL = [float(CORNER[k][1]) for k in ARMS]


def _tip(sw: float, bm: float, el: float, sx: float, sy: float, cfg: RobotConfig) -> tuple[float, float, float]:
    """The one forward-kinematics formula (paper eq. 13 in our convention, d3 = 0): tip centre of
    the arm at corner (sx, sy) in {R} (m), on Python floats. With r = l1 cos(boom) + l2 cos(boom +
    elbow): (sx mx + r sin(swing), sy (my + r cos(swing)), mz + 0.04 - l1 sin(boom) - l2 sin(boom +
    elbow)), the boom axis 0.04 m above the mount."""
    mx, my, mz = cfg.arm_mount
    l1, l2 = cfg.l1, cfg.l2
    reach = l1 * math.cos(bm) + l2 * math.cos(bm + el)
    return (sx * mx + reach * math.sin(sw), sy * (my + reach * math.cos(sw)),
            mz + 0.04 - l1 * math.sin(bm) - l2 * math.sin(bm + el))


def fk(q: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Tip of arm ``k`` in the robot frame {R} (m) for joints (swing, boom, elbow) (rad); the same
    numbers, bit for bit, as that arm's row of :func:`fk_all`."""
    sw, bm, el = (float(v) for v in q)
    sx, sy = CORNER[k]
    return np.array(_tip(sw, bm, el, float(sx), float(sy), cfg))


def fk_all(q_arm: np.ndarray, cfg: RobotConfig) -> np.ndarray:
    """(4, 3) tips of the four arms (LF, RF, LR, RR) in {R} (m): :func:`fk` for all four in one
    call, on Python floats (numpy's per-call cost exceeds this arithmetic)."""
    return np.array([_tip(sw, bm, el, sx, sy, cfg) for (sw, bm, el), sx, sy in zip(q_arm.tolist(), _SXL, _SYL)])


def ik(p: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Joints (swing, boom, elbow) (rad) putting arm ``k``'s tip at ``p`` in {R}; knee up.

    Out-of-reach points are pulled onto the reachable sphere (the arm stretches toward them).
    """
    sx, sy = CORNER[k]
    mx, my, mz = cfg.arm_mount
    dx = p[0] - sx * mx
    dy = sy * p[1] - my
    sw = math.atan2(dx, dy)
    r = math.hypot(dx, dy)
    h = -(p[2] - mz - 0.04)  # depth below the boom axis
    l1, l2 = cfg.l1, cfg.l2
    d = min(math.hypot(r, h), l1 + l2 - 1e-6)
    c = (d * d - l1 * l1 - l2 * l2) / (2 * l1 * l2)
    el = math.acos(max(-1.0, min(1.0, c)))
    bm = math.atan2(h, r) - math.atan2(l2 * math.sin(el), l1 + l2 * math.cos(el))
    return np.array([sw, bm, el])


def rotation_rc(roll: float, pitch: float) -> np.ndarray:
    """{R} -> {C}: the robot frame turned level (yaw unknown, taken as zero): R = Ry(-pitch) Rx(roll).

    ``pitch`` is nose-up positive (a rotation of -pitch about y).
    """
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(-pitch), math.sin(-pitch)
    # Ry(-pitch) @ Rx(roll), multiplied out
    return np.array([[cp, sp * sr, sp * cr], [0.0, cr, -sr], [-sp, cp * sr, cp * cr]])
