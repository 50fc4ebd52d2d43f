"""Beam-traversal physics model of Xuan, Wang & Li (ellipsoid robot meeting two torsion-spring beams).

Frames and conventions
----------------------
* World: ``x`` forward (the robot drives along +x through the beams at ``x = 0``), ``y`` left,
  ``z`` up; the ground is ``z = 0``.
* Robot state ``q = (x, alpha, beta)`` in (m, rad, rad): ``x`` is the forward position of the
  geometric centre (which is also the centre of rotation, held at height ``H``), ``alpha`` is
  roll and ``beta`` is pitch in the Z-Y'-X' Tait-Bryan convention with zero yaw. We take
  **positive pitch as nose-up** (``R = Ry(-beta) Rx(alpha)``) so the pitch mode reads as a
  positive angle in every plot.
* Beam ``i`` is a massless rigid plate hinged about a line parallel to ``y`` at height
  ``h_b,i``; beam 1 spans ``y in [d/2, d/2 + w]``, beam 2 spans ``y in [-d/2 - w, -d/2]``. A
  deflection ``theta >= 0`` tilts the plate forward: its points are
  ``(s sin(theta), y, h_b + s cos(theta))`` for ``s in [0, L - h_b]``.

Contact model (paper Sec. II-C)
-------------------------------
Because the beam is massless it always rests against the robot: its deflection is the smallest
``theta >= 0`` at which the plate no longer penetrates the ellipsoid. The contact point is the
plate point touching the ellipsoid surface; the force acts along the ellipsoid normal there
(eq. 5) and its magnitude follows from the beam's torque balance about its hinge (eq. 4, or
eq. 12 with preload and beam weight in the physical-experiment variant). The penetration test
at a given ``theta`` is a box-constrained 2-D convex quadratic (plate coordinates ``s, y``
against the ellipsoid's quadratic form) solved in closed form; the deflection is its root in
``theta``. A scalar pure-Python path (Newton, warm-started from the previous step) drives the
time-stepping simulation; a vectorised numpy path (bisection) serves the energy landscape and
the estimator.

Equations of motion (eqs. 1-3)
------------------------------
``M xdd = F_x + Q_x``, ``I1 alphadd = tau_1 + Q_alpha``, ``I2 betadd = tau_2 + Q_beta`` with the
contact and gravity generalized forces ``Q``. As in the paper (and as its feedback law eq. 9
presumes with its diagonal inertia matrix) the coupling and gyroscopic terms are dropped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

#: Gravitational acceleration, m/s^2.
GRAVITY = 9.81

#: Readings of the paper's gap d (see :attr:`BeamLayout.gap_reading`).
GAP_READINGS = ("edge", "centre")


class SimulatedTimeout(Exception):
    """A run reached its simulated-time cap (``protocol.timeout``) before it could finish."""


def _check(name: str, value: float, *, positive: bool = False, nonneg: bool = False) -> None:
    if not np.isfinite(value):
        raise ValueError(f"{name} = {value!r} is not finite")
    if positive and value <= 0:
        raise ValueError(f"{name} = {value!r} is invalid; it must be > 0")
    if nonneg and value < 0:
        raise ValueError(f"{name} = {value!r} is invalid; it must be >= 0")


@dataclass(frozen=True)
class RobotParams:
    """The rigid ellipsoid robot (paper Sec. II-A)."""

    a: float = 0.12
    """Semi-axis along the body's long (roll) axis e1, m."""
    b: float = 0.07
    """Semi-axis along the body's lateral (pitch) axis e2, m."""
    c: float = 0.03
    """Semi-axis along the body's vertical axis e3, m."""
    mass: float = 0.2
    """Robot mass M, kg."""
    h_c: float = 0.02
    """Distance of the centre of mass below the centre of rotation along -e3, m."""
    inertia: tuple[float, float, float] = (2e-3, 5e-3, 7e-3)
    """Principal moments of inertia (I1, I2, I3), kg m^2."""
    height: float = 0.06
    """Height H of the geometric centre (= centre of rotation) above the ground, m."""
    v0: float = 0.05
    """Forward speed before contact (zero inputs), m/s."""

    def __post_init__(self) -> None:
        for n in ("a", "b", "c", "mass", "height"):
            _check(f"robot.{n}", getattr(self, n), positive=True)
        _check("robot.h_c", self.h_c, nonneg=True)
        for i, val in enumerate(self.inertia):
            _check(f"robot.inertia[{i}]", val, positive=True)


@dataclass(frozen=True)
class BeamLayout:
    """Where the two beams stand and how big they are (paper Sec. II-A)."""

    gap: float = 0.12
    """Gap d between the two beams, m (centred on the x axis); what it spans is ``gap_reading``."""
    width: float = 0.05
    """Width w of each plate along y, m."""
    length: float = 0.16
    """Height L of each beam's top edge above the ground when vertical, m."""
    gap_reading: str = "edge"
    """How d is measured (paper Sec. II-A, "The gap width between two beams is d = 0.12 m"):
    ``"edge"``: between the plates' inner edges (the free gap is d; plates at |y| in
    [d/2, d/2 + w]); ``"centre"``: between the plates' centre lines (the free gap is d - w;
    plates at |y| in [(d - w)/2, (d + w)/2])."""

    def __post_init__(self) -> None:
        for n in ("gap", "width", "length"):
            _check(f"layout.{n}", getattr(self, n), positive=True)
        if self.gap_reading not in GAP_READINGS:
            raise ValueError(f"layout.gap_reading = {self.gap_reading!r}; valid: {', '.join(GAP_READINGS)}")
        if self.inner_gap <= 0:
            raise ValueError(f"layout.gap = {self.gap!r} m read centre-to-centre leaves no free gap between "
                             f"plates {self.width!r} m wide; it must exceed the width")

    @property
    def inner_gap(self) -> float:
        """Free gap between the plates' inner edges, m."""
        return self.gap if self.gap_reading == "edge" else self.gap - self.width

    def y_range(self, i: int) -> tuple[float, float]:
        """Lateral extent (y0, y1) in m of beam ``i`` (0 = left, +y; 1 = right, -y)."""
        if self.gap_reading == "edge":
            lo, hi = 0.5 * self.gap, 0.5 * self.gap + self.width
        else:
            lo, hi = 0.5 * (self.gap - self.width), 0.5 * (self.gap + self.width)
        return (lo, hi) if i == 0 else (-hi, -lo)


@dataclass(frozen=True)
class Beam:
    """One beam's mechanical parameters (the unknowns of the estimation)."""

    k: float
    """Torsion-spring stiffness, N m/rad."""
    h_b: float = 0.0
    """Height of the deflection point (hinge) above the ground, m."""
    tau0: float = 0.0
    """Preload torque holding the beam upright (experiment variant, eq. 12), N m."""
    mass: float = 0.0
    """Beam mass M_B (experiment variant, eq. 12; the simulated beams are massless), kg."""

    def __post_init__(self) -> None:
        _check("beam.k", self.k, nonneg=True)
        _check("beam.tau0", self.tau0, nonneg=True)
        _check("beam.mass", self.mass, nonneg=True)
        _check("beam.h_b", self.h_b)


@dataclass(frozen=True)
class ModelConfig:
    """Everything the forward model needs."""

    robot: RobotParams = field(default_factory=RobotParams)
    """Robot geometry and inertia."""
    layout: BeamLayout = field(default_factory=BeamLayout)
    """Beam positions and sizes."""
    beams: tuple[Beam, Beam] = (Beam(0.25), Beam(0.27))
    """True parameters of the left and right beam."""
    dt: float = 2e-4
    """Integration time step, s (paper Sec. II-B)."""
    gravity: float = GRAVITY
    """Gravitational acceleration, m/s^2."""
    pitch_axis: str = "generalized"
    """Axis the pitch equation projects torques on: ``"generalized"`` (world -y, the axis beta
    turns about, which keeps the dynamics the gradient of the eq.-8 energy) or ``"principal"``
    (body e2 as literally printed in eq. 2). They coincide at zero roll."""
    min_lever: float = 1e-3
    """Smallest moment arm, m, used when a contact force passes (nearly) through a hinge."""
    damping: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Viscous damping on (x, alpha, beta) in N s/m, N m s/rad, N m s/rad (paper: none)."""

    def __post_init__(self) -> None:
        _check("dt", self.dt, positive=True)
        _check("gravity", self.gravity, nonneg=True)
        if self.pitch_axis not in ("generalized", "principal"):
            raise ValueError(f"pitch_axis = {self.pitch_axis!r}; valid: 'generalized', 'principal'")
        if len(self.beams) != 2:
            raise ValueError(f"beams must hold exactly 2 Beam objects, got {len(self.beams)}")
        for i, d in enumerate(self.damping):
            _check(f"damping[{i}]", d, nonneg=True)


def critical_stiffness(robot: RobotParams = RobotParams(), layout: BeamLayout = BeamLayout(),
                       gravity: float = GRAVITY) -> float:
    """Critical stiffness k_0 = M g h_c / arccos(H/L)^2 (paper Sec. II-G), N m/rad."""
    return robot.mass * gravity * robot.h_c / math.acos(robot.height / layout.length) ** 2


# --------------------------------------------------------------------------- orientation

def rotation(alpha: np.ndarray | float, beta: np.ndarray | float) -> np.ndarray:
    """Body-to-world rotation ``Ry(-beta) Rx(alpha)`` (positive beta = nose up).

    Args:
        alpha: roll, rad, any shape S.
        beta: pitch, rad, broadcastable with alpha.

    Returns:
        Array of shape S + (3, 3); columns are the body axes e1, e2, e3 in world coordinates.
    """
    alpha, beta = np.broadcast_arrays(np.asarray(alpha, float), np.asarray(beta, float))
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    z = np.zeros_like(ca)
    return np.stack([
        np.stack([cb, -sb * sa, -sb * ca], -1),
        np.stack([z, ca, -sa], -1),
        np.stack([sb, cb * sa, cb * ca], -1),
    ], -2)


def com_height(alpha, beta, robot: RobotParams):
    """Height of the centre of mass, m (same shape as the broadcast inputs)."""
    return robot.height - robot.h_c * np.cos(alpha) * np.cos(beta)


def _quad_form(alpha: float, beta: float, robot: RobotParams):
    """Entries of Q = R diag(1/a^2,1/b^2,1/c^2) R^T (scalar floats) and the body axes."""
    ca, sa, cb, sb = math.cos(alpha), math.sin(alpha), math.cos(beta), math.sin(beta)
    r00, r01, r02 = cb, -sb * sa, -sb * ca
    r10, r11, r12 = 0.0, ca, -sa
    r20, r21, r22 = sb, cb * sa, cb * ca
    d0, d1, d2 = 1.0 / robot.a ** 2, 1.0 / robot.b ** 2, 1.0 / robot.c ** 2
    qxx = r00 * r00 * d0 + r01 * r01 * d1 + r02 * r02 * d2
    qxy = r00 * r10 * d0 + r01 * r11 * d1 + r02 * r12 * d2
    qxz = r00 * r20 * d0 + r01 * r21 * d1 + r02 * r22 * d2
    qyy = r10 * r10 * d0 + r11 * r11 * d1 + r12 * r12 * d2
    qyz = r10 * r20 * d0 + r11 * r21 * d1 + r12 * r22 * d2
    qzz = r20 * r20 * d0 + r21 * r21 * d1 + r22 * r22 * d2
    e1 = (r00, r10, r20)
    e2 = (r01, r11, r21)
    return (qxx, qxy, qxz, qyy, qyz, qzz), e1, e2


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


# --------------------------------------------------------------------------- simulation

#: Signature of a controller: (t, q, v, contacts) -> (F_x, tau_1, tau_2).
Controller = Callable[[float, tuple, tuple, Sequence[ContactState]], tuple]


@dataclass
class SimLog:
    """Per-step record of a simulation (arrays filled by :func:`simulate`)."""

    t: np.ndarray
    """Time, s, shape (T,)."""
    q: np.ndarray
    """Pose (x, alpha, beta), shape (T, 3)."""
    v: np.ndarray
    """Velocity, shape (T, 3)."""
    u: np.ndarray
    """Inputs (F_x, tau_1, tau_2), shape (T, 3)."""
    force: np.ndarray
    """Total beam force on the robot, N, shape (T, 3)."""
    theta: np.ndarray
    """Deflections of the two beams, rad, shape (T, 2)."""
    t_contact: float
    """Time of first contact, s (NaN if never)."""
    outcome: str
    """"passed", "fell", "timeout" or "stopped" (stop callback)."""


def simulate(cfg: ModelConfig, q0: Sequence[float], v0: Sequence[float], t_end: float,
             controller: Controller, control_period: float = 2e-3, x_exit: float | None = None,
             stop: Callable[[float, tuple, tuple, float], bool] | None = None,
             fixed_x_speed: float | None = None) -> SimLog:
    """Integrate eqs. 1-3 with semi-implicit Euler at ``cfg.dt``.

    Args:
        cfg: model configuration (true beams).
        q0, v0: initial pose and velocity (m, rad, rad; m/s, rad/s, rad/s).
        t_end: simulated time limit, s.
        controller: called every ``control_period`` s; the input is held in between (ZOH).
        x_exit: the run ends as "passed" once x >= x_exit with neither beam touching.
        stop: optional ``stop(t, q, v, t_contact) -> bool`` ending the run as "stopped".
        fixed_x_speed: if given, x is driven kinematically at this speed (the experiment's
            servo-driven carriage) and only roll and pitch are dynamic.

    Returns:
        The :class:`SimLog`. A pose with |alpha| or |beta| >= 90 deg ends the run as "fell".
    """
    robot, layout, beams = cfg.robot, cfg.layout, cfg.beams
    dt = cfg.dt
    M = robot.mass
    I1, I2 = robot.inertia[0], robot.inertia[1]
    cx, ca_, cb_ = cfg.damping
    n_ctrl = max(1, int(round(control_period / dt)))
    n_max = int(math.ceil(t_end / dt))
    x, al, be = (float(v) for v in q0)
    vx, va, vb = (float(v) for v in v0)
    guesses = [0.0, 0.0]
    u = (0.0, 0.0, 0.0)
    ts, qs, vs, us, fs, ths = [], [], [], [], [], []
    t_contact = math.nan
    outcome = "timeout"
    half_pi = 0.5 * math.pi
    for n in range(n_max + 1):
        t = n * dt
        Q, e1, e2 = _quad_form(al, be, robot)
        q = (x, al, be)
        contacts = []
        for i in range(2):
            cs = contact_scalar(q, beams[i], i, robot, layout, Q=Q, guess=guesses[i],
                                min_lever=cfg.min_lever, gravity=cfg.gravity)
            guesses[i] = cs.theta
            contacts.append(cs)
        touching = contacts[0].in_contact or contacts[1].in_contact
        if touching and math.isnan(t_contact):
            t_contact = t
        if n % n_ctrl == 0:
            u = tuple(float(c) for c in controller(t, q, (vx, va, vb), contacts))
        ts.append(t)
        qs.append(q)
        vs.append((vx, va, vb))
        us.append(u)
        fs.append(tuple(contacts[0].force[j] + contacts[1].force[j] for j in range(3)))
        ths.append((contacts[0].theta, contacts[1].theta))
        if abs(al) >= half_pi or abs(be) >= half_pi:
            outcome = "fell"
            break
        if x_exit is not None and x >= x_exit and not touching:
            outcome = "passed"
            break
        if stop is not None and stop(t, q, (vx, va, vb), t_contact):
            outcome = "stopped"
            break
        if n == n_max:
            break
        Qx, Qa, Qb = generalized_forces(q, contacts, robot, cfg.gravity, cfg.pitch_axis, e1, e2)
        if fixed_x_speed is None:
            vx += dt * (u[0] + Qx - cx * vx) / M
        else:
            vx = fixed_x_speed
        va += dt * (u[1] + Qa - ca_ * va) / I1
        vb += dt * (u[2] + Qb - cb_ * vb) / I2
        x += dt * vx
        al += dt * va
        be += dt * vb
    return SimLog(np.asarray(ts), np.asarray(qs), np.asarray(vs), np.asarray(us), np.asarray(fs),
                  np.asarray(ths), t_contact, outcome)


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
