"""Beam-traversal model parameters and the robot's orientation (Xuan, Wang & Li).

The robot, the beams, their layout and the model settings as frozen dataclasses, the critical
stiffness formula and the orientation helpers. Frames and conventions: :mod:`.model`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from terrabench.config import ConfigError, check_fields, param

#: Gravitational acceleration, m/s^2.
GRAVITY = 9.81

#: Readings of the paper's gap d (see :attr:`BeamLayout.gap_reading`).
GAP_READINGS = ("edge", "centre")



@dataclass(frozen=True)
class RobotParams:
    """The rigid ellipsoid robot (paper Sec. II-A)."""

    a: float = param(0.12, gt=0, unit="m", doc="Semi-axis along the body's long (roll) axis e1, m")
    """Semi-axis along the body's long (roll) axis e1, m."""
    b: float = param(0.07, gt=0, unit="m", doc="Semi-axis along the body's lateral (pitch) axis e2, m")
    """Semi-axis along the body's lateral (pitch) axis e2, m."""
    c: float = param(0.03, gt=0, unit="m", doc="Semi-axis along the body's vertical axis e3, m")
    """Semi-axis along the body's vertical axis e3, m."""
    mass: float = param(0.2, gt=0, unit="kg", doc="Robot mass M, kg")
    """Robot mass M, kg."""
    h_c: float = param(0.02, ge=0, unit="m",
                       doc="Distance of the centre of mass below the centre of rotation along -e3, m")
    """Distance of the centre of mass below the centre of rotation along -e3, m."""
    inertia: tuple[float, float, float] = param((2e-3, 5e-3, 7e-3), length=3, gt=0, unit="kg m^2",
                                                doc="Principal moments of inertia (I1, I2, I3), kg m^2")
    """Principal moments of inertia (I1, I2, I3), kg m^2."""
    height: float = param(0.06, gt=0, unit="m",
                          doc="Height H of the geometric centre (= centre of rotation) above the ground, m")
    """Height H of the geometric centre (= centre of rotation) above the ground, m."""
    v0: float = param(0.05, ge=0, unit="m/s", doc="Forward speed before contact (zero inputs), m/s")
    """Forward speed before contact (zero inputs), m/s."""

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class BeamLayout:
    """Where the two beams stand and how big they are (paper Sec. II-A)."""

    gap: float = param(0.12, gt=0, unit="m", doc="Gap d between the two beams, m (centred on the x axis)")
    """Gap d between the two beams, m (centred on the x axis); what it spans is ``gap_reading``."""
    width: float = param(0.05, gt=0, unit="m", doc="Width w of each plate along y, m")
    """Width w of each plate along y, m."""
    length: float = param(0.16, gt=0, unit="m",
                          doc="Height L of each beam's top edge above the ground when vertical, m")
    """Height L of each beam's top edge above the ground when vertical, m."""
    gap_reading: str = param("edge", choices=GAP_READINGS, doc="How d is measured (paper Sec")
    """How d is measured (paper Sec. II-A, "The gap width between two beams is d = 0.12 m"):
    ``"edge"``: between the plates' inner edges (the free gap is d; plates at |y| in
    [d/2, d/2 + w]); ``"centre"``: between the plates' centre lines (the free gap is d - w;
    plates at |y| in [(d - w)/2, (d + w)/2])."""

    def __post_init__(self) -> None:
        check_fields(self)
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

    k: float = param(ge=0, unit="N m/rad", doc="Torsion-spring stiffness")
    """Torsion-spring stiffness, N m/rad."""
    h_b: float = param(0.0, unit="m", doc="Height of the deflection point (hinge) above the ground")
    """Height of the deflection point (hinge) above the ground, m."""
    tau0: float = param(0.0, ge=0, unit="N m", doc="Preload torque holding the beam upright (eq. 12)")
    """Preload torque holding the beam upright (experiment variant, eq. 12), N m."""
    mass: float = param(0.0, ge=0, unit="kg", doc="Beam mass M_B (eq. 12; the simulated beams are massless)")
    """Beam mass M_B (experiment variant, eq. 12; the simulated beams are massless), kg."""

    def __post_init__(self) -> None:
        try:
            check_fields(self)
        except ConfigError as e:
            raise e.under("beam") from None


@dataclass(frozen=True)
class ModelConfig:
    """Everything the forward model needs."""

    robot: RobotParams = field(default_factory=RobotParams)
    """Robot geometry and inertia."""
    layout: BeamLayout = field(default_factory=BeamLayout)
    """Beam positions and sizes."""
    beams: tuple[Beam, Beam] = (Beam(0.25), Beam(0.27))
    """True parameters of the left and right beam."""
    dt: float = param(2e-4, gt=0, unit="s", doc="Integration time step (paper Sec. II-B)")
    """Integration time step, s (paper Sec. II-B)."""
    gravity: float = param(GRAVITY, ge=0, unit="m/s^2", doc="Gravitational acceleration")
    """Gravitational acceleration, m/s^2."""
    pitch_axis: str = param("generalized", choices=("generalized", "principal"),
                            doc="Axis the pitch equation projects torques on")
    """Axis the pitch equation projects torques on: ``"generalized"`` (world -y, the axis beta
    turns about, which keeps the dynamics the gradient of the eq.-8 energy) or ``"principal"``
    (body e2 as literally printed in eq. 2). They coincide at zero roll."""
    min_lever: float = param(1e-3, gt=0, unit="m", doc="Smallest moment arm of a contact force about a hinge")
    """Smallest moment arm, m, used when a contact force passes (nearly) through a hinge."""
    damping: tuple[float, float, float] = param((0.0, 0.0, 0.0), ge=0, length=3,
                                                doc="Viscous damping on (x, alpha, beta)")
    """Viscous damping on (x, alpha, beta) in N s/m, N m s/rad, N m s/rad (paper: none)."""

    def __post_init__(self) -> None:
        check_fields(self)
        if len(self.beams) != 2:
            raise ValueError(f"beams must hold exactly 2 Beam objects, got {len(self.beams)}")


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
