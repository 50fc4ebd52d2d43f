"""The beam contact model (paper Sec. II-C): deflection, contact point and force, scalar and
vectorised, and the potential energy. Frames and conventions: :mod:`.model`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .geometry import GRAVITY, Beam, BeamLayout, RobotParams, _quad_form, com_height, rotation

# --------------------------------------------------------------------------- scalar contact

def _clamp(v: float, lo: float, hi: float) -> float:
    return lo if v < lo else hi if v > hi else v


def _boxmin(F0, p, q, A, B, C, s1, y0, y1):
    """Minimum of F0 + 2ps + 2qy + As^2 + 2Bsy + Cy^2 over s in [0,s1], y in [y0,y1].

    Returns (value, s*, y*). A, C > 0 because the ellipsoid's quadratic form is positive definite.
    """
    det = A * C - B * B
    if det > 1e-30:
        s = (B * q - C * p) / det
        y = (B * p - A * q) / det
        if 0.0 <= s <= s1 and y0 <= y <= y1:
            return F0 + p * s + q * y, s, y
    # the minimum lies on the boundary: check the four edges
    y = _clamp(-q / C, y0, y1)
    best, bs, by = F0 + 2 * q * y + C * y * y, 0.0, y
    qq = q + s1 * B
    y = _clamp(-qq / C, y0, y1)
    v = F0 + 2 * p * s1 + A * s1 * s1 + 2 * qq * y + C * y * y
    if v < best:
        best, bs, by = v, s1, y
    for ye in (y0, y1):
        pp = p + ye * B
        s = _clamp(-pp / A, 0.0, s1)
        v = F0 + 2 * q * ye + C * ye * ye + 2 * pp * s + A * s * s
        if v < best:
            best, bs, by = v, s, ye
    return best, bs, by


class _PlateGeom:
    """Precomputed quantities for one plate against the current robot pose (scalar path)."""

    __slots__ = ("Q", "wx", "wz", "Qw", "F0", "s1", "y0", "y1")

    def __init__(self, Q, x: float, H: float, h_b: float, L: float, y0: float, y1: float):
        qxx, qxy, qxz, qyy, qyz, qzz = Q
        self.Q = Q
        # w = hinge point - robot centre (its y part is carried by the plate coordinate y)
        wx, wz = -x, h_b - H
        self.wx, self.wz = wx, wz
        self.Qw = (qxx * wx + qxz * wz, qxy * wx + qyz * wz, qxz * wx + qzz * wz)
        self.F0 = wx * self.Qw[0] + wz * self.Qw[2]
        self.s1, self.y0, self.y1 = L - h_b, y0, y1

    def g(self, th: float):
        """Penetration function at deflection th: (min quadratic - 1, dg/dth, s*, y*)."""
        qxx, qxy, qxz, qyy, qyz, qzz = self.Q
        st, ct = math.sin(th), math.cos(th)
        Qwx, Qwy, Qwz = self.Qw
        p = st * Qwx + ct * Qwz
        A = st * st * qxx + 2 * st * ct * qxz + ct * ct * qzz
        B = st * qxy + ct * qyz
        val, s, y = _boxmin(self.F0, p, Qwy, A, B, qyy, self.s1, self.y0, self.y1)
        # envelope theorem: derivative of the min is the partial at the minimiser
        upQw = ct * Qwx - st * Qwz
        upQu = ct * (st * qxx + ct * qxz) - st * (st * qxz + ct * qzz)
        upQe = ct * qxy - st * qyz
        dg = 2 * s * (upQw + s * upQu + y * upQe)
        return val - 1.0, dg, s, y


def _solve_theta(pg: _PlateGeom, guess: float, tol: float = 1e-11) -> float:
    """Largest-root deflection on [0, pi/2] given g(0) < 0 (safeguarded Newton)."""
    lo, hi = 0.0, 0.5 * math.pi
    ghi = pg.g(hi)[0]
    if ghi < 0.0:
        return hi  # plate flat and still penetrating: clamp (robot reaches below the hinge)
    th = guess if lo < guess < hi else 0.5 * (lo + hi)
    for _ in range(60):
        gv, dg, _, _ = pg.g(th)
        if gv < 0.0:
            lo = th
        else:
            hi = th
        if abs(gv) < tol or hi - lo < 1e-12:
            break
        nxt = th - gv / dg if dg > 0 else -1.0
        th = nxt if lo < nxt < hi else 0.5 * (lo + hi)
    return th


@dataclass
class ContactState:
    """One beam's contact with the robot at one instant (world frame)."""

    theta: float = 0.0
    """Beam deflection, rad (0 when not touching)."""
    force: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Force of the beam on the robot, N."""
    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Application point, m."""
    in_contact: bool = False
    """Whether the plate touches the robot."""


def beam_torque(beam: Beam, theta: float, L: float, gravity: float = GRAVITY) -> float:
    """Torque the robot must apply about the hinge to hold deflection theta (eqs. 4 / 12), N m."""
    return beam.tau0 + beam.k * theta - 0.5 * (L - beam.h_b) * beam.mass * gravity * math.sin(theta)


def contact_scalar(q: Sequence[float], beam: Beam, i: int, robot: RobotParams, layout: BeamLayout,
                   Q=None, guess: float = 0.0, min_lever: float = 1e-3,
                   gravity: float = GRAVITY) -> ContactState:
    """Contact of beam ``i`` with the robot at pose ``q = (x, alpha, beta)``.

    Args:
        q: robot pose (m, rad, rad).
        beam: the beam's parameters.
        i: 0 for the left beam, 1 for the right.
        robot, layout: geometry.
        Q: optional precomputed quadratic form entries from :func:`_quad_form`.
        guess: previous deflection (rad) to warm-start the root finder.
        min_lever: smallest admitted moment arm, m.

    Returns:
        The :class:`ContactState`.
    """
    x, alpha, beta = q
    if Q is None:
        Q = _quad_form(alpha, beta, robot)[0]
    y0, y1 = layout.y_range(i)
    pg = _PlateGeom(Q, x, robot.height, beam.h_b, layout.length, y0, y1)
    if pg.g(0.0)[0] >= 0.0:
        return ContactState()
    th = _solve_theta(pg, guess)
    _, _, s, y = pg.g(th)
    st, ct = math.sin(th), math.cos(th)
    px, py, pz = s * st, y, beam.h_b + s * ct
    # outward ellipsoid normal Q (P - C): eq. 5 written in the world frame
    qxx, qxy, qxz, qyy, qyz, qzz = Q
    rx, ry, rz = px - x, py, pz - robot.height
    nx = qxx * rx + qxy * ry + qxz * rz
    ny = qxy * rx + qyy * ry + qyz * rz
    nz = qxz * rx + qyz * ry + qzz * rz
    nn = math.sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx / nn, ny / nn, nz / nn
    lever = s * (ct * nx - st * nz)
    torque = beam_torque(beam, th, layout.length, gravity)
    f = max(torque, 0.0) / max(lever, min_lever)
    return ContactState(th, (-f * nx, -f * ny, -f * nz), (px, py, pz), True)


def generalized_forces(q, contacts: Sequence[ContactState], robot: RobotParams, gravity: float = GRAVITY,
                       pitch_axis: str = "generalized", e1=None, e2=None) -> tuple[float, float, float]:
    """External generalized forces (Q_x, Q_alpha, Q_beta) from contacts and gravity.

    Units: N, N m, N m. Torques are about the centre of rotation, projected on the roll axis e1
    and on the pitch axis (-y world, or -e2 with ``pitch_axis="principal"``).
    """
    x, alpha, beta = q
    if e1 is None:
        _, e1, e2 = _quad_form(alpha, beta, robot)
    H = robot.height
    qx = qa = qb = 0.0
    for cs in contacts:
        if not cs.in_contact:
            continue
        fx, fy, fz = cs.force
        rx, ry, rz = cs.point[0] - x, cs.point[1], cs.point[2] - H
        tx, ty, tz = ry * fz - rz * fy, rz * fx - rx * fz, rx * fy - ry * fx
        qx += fx
        qa += tx * e1[0] + ty * e1[1] + tz * e1[2]
        if pitch_axis == "generalized":
            qb -= ty
        else:
            qb -= tx * e2[0] + ty * e2[1] + tz * e2[2]
    mgh = robot.mass * gravity * robot.h_c
    ca, sa, cb, sb = math.cos(alpha), math.sin(alpha), math.cos(beta), math.sin(beta)
    qa -= mgh * sa * cb
    qb -= mgh * ca * sb if pitch_axis == "generalized" else mgh * sb
    return qx, qa, qb


def potential_energy(q, beams: Sequence[Beam], robot: RobotParams, layout: BeamLayout,
                     gravity: float = GRAVITY) -> float:
    """Eq. 8 at one pose: M g Z_com + sum 1/2 k theta^2 (+ preload/weight terms), J."""
    x, alpha, beta = q
    Q = _quad_form(alpha, beta, robot)[0]
    e = robot.mass * gravity * float(com_height(alpha, beta, robot))
    for i, bm in enumerate(beams):
        th = contact_scalar(q, bm, i, robot, layout, Q=Q, gravity=gravity).theta
        e += bm.tau0 * th + 0.5 * bm.k * th * th
        e += 0.5 * (layout.length - bm.h_b) * bm.mass * gravity * (math.cos(th) - 1.0)
    return e


# --------------------------------------------------------------------------- vectorised contact

def _quad_form_vec(alpha: np.ndarray, beta: np.ndarray, robot: RobotParams):
    R = rotation(alpha, beta)
    d = np.array([1 / robot.a ** 2, 1 / robot.b ** 2, 1 / robot.c ** 2])
    Qm = np.einsum("...ik,k,...jk->...ij", R, d, R)
    return (Qm[..., 0, 0], Qm[..., 0, 1], Qm[..., 0, 2], Qm[..., 1, 1], Qm[..., 1, 2], Qm[..., 2, 2])


def _boxmin_vec(F0, p, q, A, B, C, s1, y0, y1):
    """Vectorised :func:`_boxmin`; returns (value, s*, y*) arrays."""
    det = A * C - B * B
    with np.errstate(divide="ignore", invalid="ignore"):
        s_in = (B * q - C * p) / det
        y_in = (B * p - A * q) / det
    inside = (det > 1e-30) & (s_in >= 0) & (s_in <= s1) & (y_in >= y0) & (y_in <= y1)
    best = np.where(inside, F0 + p * s_in + q * y_in, np.inf)
    bs = np.where(inside, s_in, 0.0)
    by = np.where(inside, y_in, 0.0)
    cands = []
    y = np.clip(-q / C, y0, y1)
    cands.append((F0 + 2 * q * y + C * y * y, np.zeros_like(y), y))
    qq = q + s1 * B
    y = np.clip(-qq / C, y0, y1)
    cands.append((F0 + 2 * p * s1 + A * s1 * s1 + 2 * qq * y + C * y * y, np.broadcast_to(s1, y.shape), y))
    for ye in (y0, y1):
        pp = p + ye * B
        s = np.clip(-pp / A, 0.0, s1)
        cands.append((F0 + 2 * q * ye + C * ye * ye + 2 * pp * s + A * s * s, s, np.broadcast_to(ye, s.shape)))
    for v, s, y in cands:
        better = (~inside) & (v < best)
        best = np.where(better, v, best)
        bs = np.where(better, s, bs)
        by = np.where(better, y, by)
    return best, bs, by


def deflection_vec(x, alpha, beta, h_b, i: int, robot: RobotParams, layout: BeamLayout,
                   iters: int = 40, return_contact: bool = False):
    """Vectorised beam deflection theta(x, alpha, beta) for beam ``i``.

    Args:
        x, alpha, beta: pose arrays (m, rad, rad), mutually broadcastable to shape S.
        h_b: hinge height(s), m, broadcastable to S.
        i: 0 (left beam) or 1 (right beam).
        iters: bisection iterations on [0, pi/2] (40 gives ~1e-12 rad).
        return_contact: also return contact point (S+(3,)), unit outward normal (S+(3,)) and
            the moment arm ``lever`` (S) of a unit normal force about the hinge.

    Returns:
        theta (S) in rad, or (theta, point, normal, lever, touching) with ``return_contact``.
    """
    x, alpha, beta, h_b = np.broadcast_arrays(*(np.asarray(v, float) for v in (x, alpha, beta, h_b)))
    shape = x.shape
    x, alpha, beta, h_b = (v.ravel() for v in (x, alpha, beta, h_b))
    Q = _quad_form_vec(alpha, beta, robot)
    qxx, qxy, qxz, qyy, qyz, qzz = Q
    y0, y1 = layout.y_range(i)
    wx, wz = -x, h_b - robot.height
    Qwx, Qwy, Qwz = qxx * wx + qxz * wz, qxy * wx + qyz * wz, qxz * wx + qzz * wz
    F0 = wx * Qwx + wz * Qwz
    s1 = layout.length - h_b

    def gfun(th, idx):
        st, ct = np.sin(th), np.cos(th)
        p = st * Qwx[idx] + ct * Qwz[idx]
        A = st * st * qxx[idx] + 2 * st * ct * qxz[idx] + ct * ct * qzz[idx]
        B = st * qxy[idx] + ct * qyz[idx]
        return _boxmin_vec(F0[idx], p, Qwy[idx], A, B, qyy[idx], s1[idx], y0, y1)

    theta = np.zeros(x.shape)
    all_idx = np.arange(x.size)
    touching = gfun(np.zeros(x.size), all_idx)[0] < 1.0
    idx = np.nonzero(touching)[0]
    if idx.size:
        lo = np.zeros(idx.size)
        hi = np.full(idx.size, 0.5 * np.pi)
        flat_pen = gfun(hi, idx)[0] < 1.0
        for _ in range(iters):
            mid = 0.5 * (lo + hi)
            pen = gfun(mid, idx)[0] < 1.0
            lo = np.where(pen, mid, lo)
            hi = np.where(pen, hi, mid)
        th = np.where(flat_pen, 0.5 * np.pi, hi)
        theta[idx] = th
    if not return_contact:
        return theta.reshape(shape)
    point = np.zeros(x.shape + (3,))
    normal = np.zeros(x.shape + (3,))
    lever = np.zeros(x.shape)
    if idx.size:
        th = theta[idx]
        _, s, y = gfun(th, idx)
        st, ct = np.sin(th), np.cos(th)
        P = np.stack([s * st, y, h_b[idx] + s * ct], -1)
        r = P - np.stack([x[idx], np.zeros(idx.size), np.full(idx.size, robot.height)], -1)
        n = np.stack([qxx[idx] * r[:, 0] + qxy[idx] * r[:, 1] + qxz[idx] * r[:, 2],
                      qxy[idx] * r[:, 0] + qyy[idx] * r[:, 1] + qyz[idx] * r[:, 2],
                      qxz[idx] * r[:, 0] + qyz[idx] * r[:, 1] + qzz[idx] * r[:, 2]], -1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        point[idx] = P
        normal[idx] = n
        lever[idx] = s * (ct * n[:, 0] - st * n[:, 2])
    return (theta.reshape(shape), point.reshape(shape + (3,)), normal.reshape(shape + (3,)),
            lever.reshape(shape), touching.reshape(shape))


def contact_force_vec(q: np.ndarray, beams: Sequence[Beam], robot: RobotParams, layout: BeamLayout,
                      min_lever: float = 1e-3, gravity: float = GRAVITY) -> np.ndarray:
    """Total beam force on the robot for many poses (what the force sensor measures).

    Args:
        q: poses, shape (N, 3) (m, rad, rad).
        beams: the two beams.

    Returns:
        Forces, shape (N, 3), N, world frame.
    """
    q = np.atleast_2d(np.asarray(q, float))
    total = np.zeros((q.shape[0], 3))
    for i, bm in enumerate(beams):
        th, _, n, lever, touch = deflection_vec(q[:, 0], q[:, 1], q[:, 2], bm.h_b, i, robot, layout,
                                                return_contact=True)
        torque = bm.tau0 + bm.k * th - 0.5 * (layout.length - bm.h_b) * bm.mass * gravity * np.sin(th)
        f = np.where(touch, np.maximum(torque, 0.0) / np.maximum(lever, min_lever), 0.0)
        total -= f[:, None] * n
    return total


def first_contact_x(robot: RobotParams, layout: BeamLayout, alpha: float = 0.0, beta: float = 0.0,
                    tol: float = 1e-9) -> float:
    """Smallest robot-centre x (m) at which the robot at (alpha, beta) touches a vertical beam
    (bisection between x = -(a + L + 1) m, far behind, and the beam plane x = 0).

    Raises:
        ValueError: if the robot passes the beam plane without touching (gap wider than it).
    """
    beam = Beam(1.0)

    def touches(x: float) -> bool:
        return any(contact_scalar((x, alpha, beta), beam, i, robot, layout).in_contact for i in range(2))

    lo, hi = -(robot.a + layout.length + 1.0), 0.0
    if not touches(hi):
        raise ValueError(f"the robot (half-width b = {robot.b} m) at roll {math.degrees(alpha):.1f} deg, pitch "
                         f"{math.degrees(beta):.1f} deg passes a free gap of {layout.inner_gap:.3f} m without "
                         "touching a beam")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if touches(mid):
            hi = mid
        else:
            lo = mid
    return hi
