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

The code is split by concern: :mod:`.geometry` (parameters, orientation), :mod:`.contact` (the
contact model and the potential energy) and :mod:`.dynamics` (the equations of motion and their
stepping). This module is their one import point.
"""

from __future__ import annotations

from .contact import (
    ContactState,
    beam_torque,
    contact_force_vec,
    contact_scalar,
    deflection_vec,
    first_contact_x,
    generalized_forces,
    potential_energy,
)
from .dynamics import Controller, SimLog, SimulatedTimeout, simulate
from .geometry import (
    GAP_READINGS,
    GRAVITY,
    Beam,
    BeamLayout,
    ModelConfig,
    RobotParams,
    com_height,
    critical_stiffness,
    rotation,
)

__all__ = ["GAP_READINGS", "GRAVITY", "Beam", "BeamLayout", "ContactState", "Controller", "ModelConfig",
           "RobotParams", "SimLog", "SimulatedTimeout", "beam_torque", "com_height", "contact_force_vec",
           "contact_scalar", "critical_stiffness", "deflection_vec", "first_contact_x", "generalized_forces",
           "potential_energy", "rotation", "simulate"]
