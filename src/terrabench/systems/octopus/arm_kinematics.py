"""Arm forward/inverse kinematics and the gravity-aligned frame {C} (paper eqs. 13-16, 10-12)."""

from __future__ import annotations

import math

import numba
import numpy as np

from terrabench.sim.pymath import hypot
from terrabench.systems.octopus.robot import ARMS, CORNER, RobotConfig

#: the arms' corner signs (sx, sy), arms LF, RF, LR, RR
SIGNS = np.array([[float(CORNER[k][0]), float(CORNER[k][1])] for k in ARMS])


@numba.njit(cache=True)
def tips_into(q, signs, c, out):  # pragma: no cover
    """The one forward-kinematics formula (paper eq. 13 in our convention, d3 = 0), compiled: tip
    centres in {R} (m) of the arms with joints ``q`` (n, 3) (swing, boom, elbow) at corner signs
    ``signs`` (n, 2) (sx, sy), written into ``out`` (n, 3); ``c`` = (mx, my, z0, l1, l2)
    (:func:`fk_constants`). With r = l1 cos(boom) + l2 cos(boom + elbow):
    (sx mx + r sin(swing), sy (my + r cos(swing)), z0 - l1 sin(boom) - l2 sin(boom + elbow)),
    z0 = mz + 0.04 (the boom axis 0.04 m above the mount). libm's sin and cos, as Python's math
    calls them (the same bits, checked in tests/octopus/test_octopus_perf.py). The controller
    fills its own (4, 3) buffer with it every tick (no array made and handed back to Python)."""
    mx, my, z0, l1, l2 = c[0], c[1], c[2], c[3], c[4]
    for a in range(q.shape[0]):
        sw, bm, el = q[a, 0], q[a, 1], q[a, 2]
        reach = l1 * math.cos(bm) + l2 * math.cos(bm + el)
        out[a, 0] = signs[a, 0] * mx + reach * math.sin(sw)
        out[a, 1] = signs[a, 1] * (my + reach * math.cos(sw))
        out[a, 2] = z0 - l1 * math.sin(bm) - l2 * math.sin(bm + el)


@numba.njit(cache=True)
def tips(q, signs, c):  # pragma: no cover
    """:func:`tips_into` as a new (n, 3) array (:func:`fk`, :func:`fk_all`)."""
    out = np.empty((q.shape[0], 3))
    tips_into(q, signs, c, out)
    return out


def fk_constants(cfg: RobotConfig) -> np.ndarray:
    """(mx, my, z0 = mz + 0.04, l1, l2) of :func:`tips`, once per controller (:func:`fk_all`)."""
    mx, my, mz = cfg.arm_mount
    return np.array([mx, my, mz + 0.04, cfg.l1, cfg.l2], dtype=float)


def fk(q: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Tip of arm ``k`` in the robot frame {R} (m) for joints (swing, boom, elbow) (rad); the same
    numbers, bit for bit, as that arm's row of :func:`fk_all`."""
    i = ARMS.index(k)
    return tips(np.asarray(q, float).reshape(1, 3), SIGNS[i:i + 1], fk_constants(cfg))[0]


def fk_all(q_arm: np.ndarray, cfg: RobotConfig, consts: np.ndarray | None = None) -> np.ndarray:
    """(4, 3) tips of the four arms (LF, RF, LR, RR) in {R} (m): :func:`fk` for all four in one
    compiled pass; ``consts`` = :func:`fk_constants` of ``cfg`` where the caller keeps them."""
    q = q_arm if (isinstance(q_arm, np.ndarray) and q_arm.shape == (4, 3) and q_arm.dtype == np.float64) \
        else np.asarray(q_arm, float).reshape(4, 3)
    return tips(q, SIGNS, fk_constants(cfg) if consts is None else consts)


def ik_constants(cfg: RobotConfig, k: str) -> np.ndarray:
    """Arm ``k``'s IK constants for :func:`ik_f`, once per controller: the values :func:`ik`'s
    formula forms from ``cfg`` on every call (sx mx, sy, my, mz, l1, l2, l1^2, l2^2, 2 l1 l2, the
    reach l1 + l2 - 1e-6), each formed by the same operations, so the angles keep their bits."""
    sx, sy = CORNER[k]
    mx, my, mz = cfg.arm_mount
    l1, l2 = cfg.l1, cfg.l2
    return np.array([sx * mx, sy, my, mz, l1, l2, l1 * l1, l2 * l2, 2 * l1 * l2, l1 + l2 - 1e-6], dtype=float)


@numba.njit(cache=True)
def ik_f(px, py, pz, c):  # pragma: no cover
    """Joints (swing, boom, elbow) (rad) putting the tip at (px, py, pz) in {R}, knee up, for the arm
    of constants ``c`` (:func:`ik_constants`), compiled. Out-of-reach points are pulled onto the
    reachable sphere (the arm stretches toward them). The bits of the formula on Python floats
    (``tests/octopus/test_octopus_perf.py``): Python's own hypot (:func:`terrabench.sim.pymath.hypot`),
    libm's acos and atan2, and Python's ``min``/``max`` (the first argument kept unless the other
    is strictly beyond it)."""
    l1, l2, l1l1, l2l2, l12, reach = c[4], c[5], c[6], c[7], c[8], c[9]
    dx, dy, r, h = _polar(px, py, pz, c)
    d = hypot(r, h)
    d = reach if reach < d else d  # min(d, reach)
    v = (d * d - l1l1 - l2l2) / l12
    v = v if v < 1.0 else 1.0  # min(1.0, v)
    v = v if v > -1.0 else -1.0  # max(-1.0, v)
    el = math.acos(v)
    return math.atan2(dx, dy), math.atan2(h, r) - math.atan2(l2 * math.sin(el), l1 + l2 * math.cos(el)), el


@numba.njit(cache=True, inline="always")
def _polar(px, py, pz, c):  # pragma: no cover
    """(dx, dy, r, h) of a tip target about the arm's boom axis: the offsets from the mount in the
    arm's frame, their horizontal distance r and the depth h below the boom axis (m)."""
    dx = px - c[0]
    dy = c[1] * py - c[2]
    return dx, dy, hypot(dx, dy), -(pz - c[3] - 0.04)


@numba.njit(cache=True)
def beyond_reach(px, py, pz, c):  # pragma: no cover
    """Whether (px, py, pz) in {R} is out of the reach of the arm of constants ``c``
    (:func:`ik_constants`): :func:`ik_f` would stretch the arm straight toward it."""
    _, _, r, h = _polar(px, py, pz, c)
    return hypot(r, h) > c[9]


def ik(p: np.ndarray, cfg: RobotConfig, k: str) -> np.ndarray:
    """Joints (swing, boom, elbow) (rad) putting arm ``k``'s tip at ``p`` in {R}; knee up
    (:func:`ik_f` as an array)."""
    px, py, pz = p.tolist() if isinstance(p, np.ndarray) else (float(v) for v in p)
    return np.array(ik_f(px, py, pz, ik_constants(cfg, k)))


def rotation_rc(roll: float, pitch: float) -> np.ndarray:
    """{R} -> {C}: the robot frame turned level (yaw unknown, taken as zero): R = Ry(-pitch) Rx(roll).

    ``pitch`` is nose-up positive (a rotation of -pitch about y).
    """
    out = np.empty((3, 3))
    rotation_rc_into(roll, pitch, out)
    return out


@numba.njit(cache=True)
def rotation_rc_into(roll, pitch, out):  # pragma: no cover
    """:func:`rotation_rc` written into ``out`` (3, 3), compiled (libm's sin and cos, as Python's
    math: the same bits; the controller's per-tick level frame fills one buffer with it)."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(-pitch), math.sin(-pitch)
    # Ry(-pitch) @ Rx(roll), multiplied out
    out[0, 0], out[0, 1], out[0, 2] = cp, sp * sr, sp * cr
    out[1, 0], out[1, 1], out[1, 2] = 0.0, cr, -sr
    out[2, 0], out[2, 1], out[2, 2] = -sp, cp * sr, cp * cr
