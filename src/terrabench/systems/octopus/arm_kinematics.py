"""Arm forward/inverse kinematics and the gravity-aligned frame {C} (paper eqs. 13-16, 10-12)."""

from __future__ import annotations

import math

import numba
import numpy as np

from terrabench.systems.octopus.robot import ARMS, CORNER, RobotConfig

_SX = np.array([float(CORNER[k][0]) for k in ARMS])
_SY = np.array([float(CORNER[k][1]) for k in ARMS])


@numba.njit(cache=True)
def _tips(q, sx, sy, mx, my, z0, l1, l2, out):  # pragma: no cover
    """The one forward-kinematics formula (paper eq. 13 in our convention, d3 = 0), compiled:
    tip centres in {R} (m) of the arms with joints ``q`` (n, 3) (swing, boom, elbow) at corner
    signs (``sx``, ``sy``) into ``out`` (n, 3). With r = l1 cos(boom) + l2 cos(boom + elbow):
    (sx mx + r sin(swing), sy (my + r cos(swing)), z0 - l1 sin(boom) - l2 sin(boom + elbow)),
    z0 = mz + 0.04 (the boom axis 0.04 m above the mount). libm's sin and cos, as Python's math
    calls them (the same bits, checked in tests/octopus/test_octopus_perf.py)."""
    for a in range(q.shape[0]):
        sw, bm, el = q[a, 0], q[a, 1], q[a, 2]
        reach = l1 * math.cos(bm) + l2 * math.cos(bm + el)
        out[a, 0] = sx[a] * mx + reach * math.sin(sw)
        out[a, 1] = sy[a] * (my + reach * math.cos(sw))
        out[a, 2] = z0 - l1 * math.sin(bm) - l2 * math.sin(bm + el)


def fk_constants(cfg: RobotConfig) -> tuple[float, float, float, float, float]:
    """(mx, my, z0 = mz + 0.04, l1, l2) of :func:`_tips`, once per controller (:func:`fk_all`)."""
    mx, my, mz = cfg.arm_mount
    return float(mx), float(my), mz + 0.04, float(cfg.l1), float(cfg.l2)


def fk(q: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Tip of arm ``k`` in the robot frame {R} (m) for joints (swing, boom, elbow) (rad); the same
    numbers, bit for bit, as that arm's row of :func:`fk_all`."""
    sx, sy = CORNER[k]
    out = np.empty((1, 3))
    _tips(np.asarray(q, float).reshape(1, 3), np.array([float(sx)]), np.array([float(sy)]), *fk_constants(cfg), out)
    return out[0]


def fk_all(q_arm: np.ndarray, cfg: RobotConfig, consts: tuple[float, ...] | None = None) -> np.ndarray:
    """(4, 3) tips of the four arms (LF, RF, LR, RR) in {R} (m): :func:`fk` for all four in one
    compiled pass; ``consts`` = :func:`fk_constants` of ``cfg`` where the caller keeps them."""
    out = np.empty((4, 3))
    _tips(np.asarray(q_arm, float).reshape(4, 3), _SX, _SY, *(consts or fk_constants(cfg)), out)
    return out


def ik_constants(cfg: RobotConfig, k: str) -> tuple[float, ...]:
    """Arm ``k``'s IK constants for :func:`ik_f`, once per controller: the values :func:`ik`'s
    formula forms from ``cfg`` on every call (sx mx, sy, my, mz, l1, l2, l1^2, l2^2, 2 l1 l2, the
    reach l1 + l2 - 1e-6), each formed by the same operations, so the angles keep their bits."""
    sx, sy = CORNER[k]
    mx, my, mz = cfg.arm_mount
    l1, l2 = cfg.l1, cfg.l2
    return (sx * mx, sy, my, mz, l1, l2, l1 * l1, l2 * l2, 2 * l1 * l2, l1 + l2 - 1e-6)


def ik_f(px: float, py: float, pz: float, c: tuple[float, ...]) -> tuple[float, float, float]:
    """Joints (swing, boom, elbow) (rad) putting the tip at (px, py, pz) in {R}, knee up, for the arm
    of constants ``c`` (:func:`ik_constants`); on Python floats (numpy's per-call cost exceeds
    this arithmetic). Out-of-reach points are pulled onto the reachable sphere (the arm stretches
    toward them)."""
    _, _, _, _, l1, l2, l1l1, l2l2, l12, reach = c
    dx, dy, r, h = _polar(px, py, pz, c)
    d = min(math.hypot(r, h), reach)
    el = math.acos(max(-1.0, min(1.0, (d * d - l1l1 - l2l2) / l12)))
    return (math.atan2(dx, dy), math.atan2(h, r) - math.atan2(l2 * math.sin(el), l1 + l2 * math.cos(el)), el)


def _polar(px: float, py: float, pz: float, c: tuple[float, ...]) -> tuple[float, float, float, float]:
    """(dx, dy, r, h) of a tip target about the arm's boom axis: the offsets from the mount in the
    arm's frame, their horizontal distance r and the depth h below the boom axis (m)."""
    sxmx, sy, my, mz = c[0], c[1], c[2], c[3]
    dx = px - sxmx
    dy = sy * py - my
    return dx, dy, math.hypot(dx, dy), -(pz - mz - 0.04)


def beyond_reach(px: float, py: float, pz: float, c: tuple[float, ...]) -> bool:
    """Whether (px, py, pz) in {R} is out of the reach of the arm of constants ``c``
    (:func:`ik_constants`): :func:`ik_f` would stretch the arm straight toward it."""
    _, _, r, h = _polar(px, py, pz, c)
    return math.hypot(r, h) > c[9]


def ik(p: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Joints (swing, boom, elbow) (rad) putting arm ``k``'s tip at ``p`` in {R}; knee up
    (:func:`ik_f` as an array)."""
    px, py, pz = p.tolist() if isinstance(p, np.ndarray) else (float(v) for v in p)
    return np.array(ik_f(px, py, pz, ik_constants(cfg, k)))


def rotation_rc(roll: float, pitch: float) -> np.ndarray:
    """{R} -> {C}: the robot frame turned level (yaw unknown, taken as zero): R = Ry(-pitch) Rx(roll).

    ``pitch`` is nose-up positive (a rotation of -pitch about y).
    """
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(-pitch), math.sin(-pitch)
    # Ry(-pitch) @ Rx(roll), multiplied out
    return np.array([[cp, sp * sr, sp * cr], [0.0, cr, -sr], [-sp, cp * sr, cp * cr]])
