"""Arm forward/inverse kinematics and the gravity-aligned frame {C} (paper eqs. 13-16, 10-12)."""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.octopus.robot import ARMS, CORNER, RobotConfig, arm_tip_local


def fk(q: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Tip of arm ``k`` in the robot frame {R} (m) for joints (swing, boom, elbow) (rad)."""
    return arm_tip_local(np.asarray(q, float), cfg, k)


_SX = np.array([CORNER[k][0] for k in ARMS], float)
_SY = np.array([CORNER[k][1] for k in ARMS], float)


def fk_all(q_arm: np.ndarray, cfg: RobotConfig) -> np.ndarray:
    """(4, 3) tips of the four arms (LF, RF, LR, RR) in {R} (m): :func:`fk` in one numpy pass."""
    sw, bm, el = q_arm[:, 0], q_arm[:, 1], q_arm[:, 2]
    mx, my, mz = cfg.arm_mount
    reach = cfg.l1 * np.cos(bm) + cfg.l2 * np.cos(bm + el)
    out = np.empty((4, 3))
    out[:, 0] = _SX * mx + reach * np.sin(sw)
    out[:, 1] = _SY * (my + reach * np.cos(sw))
    out[:, 2] = mz + 0.04 - cfg.l1 * np.sin(bm) - cfg.l2 * np.sin(bm + el)
    return out


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
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    return ry @ rx


def tips_level(q_arm: np.ndarray, roll: float, pitch: float, cfg: RobotConfig) -> np.ndarray:
    """(4, 3) tip positions in {C} (origin of {R}, axes level) (m), arms LF, RF, LR, RR."""
    return fk_all(q_arm, cfg) @ rotation_rc(roll, pitch).T
