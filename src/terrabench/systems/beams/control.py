"""Feedback-linearising trajectory tracking (paper Sec. II-I, eq. 9) and the energy cost (eq. 11)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from terrabench.config import param

from .contact import contact_scalar, generalized_forces
from .geometry import Beam, BeamLayout, RobotParams, _quad_form
from .planning import Plan


@dataclass(frozen=True)
class ControlConfig:
    """Tracking controller settings."""

    period: float = param(2e-3, gt=0, unit="s", doc="Control period, s (paper: 0.002)")
    """Control period, s (paper: 0.002)."""
    omega_n: float = param(10.0, gt=0, unit="rad/s",
                           doc="Closed-loop natural frequency of each coordinate's error dynamics, rad/s")
    """Closed-loop natural frequency of each coordinate's error dynamics, rad/s."""
    zeta: float = param(1.0, gt=0, doc="Closed-loop damping ratio")
    """Closed-loop damping ratio."""
    fx_max: float = param(2.0, gt=0, unit="N", doc="|F_x| limit, N (paper)")
    """|F_x| limit, N (paper)."""
    tau_max: float = param(0.1, gt=0, unit="N m", doc="|tau_1|, |tau_2| limit, N m (paper)")
    """|tau_1|, |tau_2| limit, N m (paper)."""


class TrackingController:
    """u = M (qdd_d - Kd (qd - qd_d) - Kp (q - q_d)) - F_ext(q), saturated (eq. 9).

    ``F_ext`` (contacts with the *believed* beams plus gravity) is predicted by the same physics
    model; with the true beams and no saturation the error dynamics are exactly linear. The
    paper writes ``+F(q)`` with ``F`` the force the inputs must cancel; here ``F_ext`` is the
    external generalized force itself, hence the minus sign.
    """

    def __init__(self, plan: Plan, t0: float, believed: Sequence[Beam], robot: RobotParams,
                 layout: BeamLayout, cfg: ControlConfig = ControlConfig(), gravity: float = 9.81,
                 pitch_axis: str = "generalized"):
        self.plan, self.t0, self.beams = plan, t0, tuple(believed)
        self.robot, self.layout, self.cfg = robot, layout, cfg
        self.gravity, self.pitch_axis = gravity, pitch_axis
        self.mass = np.array([robot.mass, robot.inertia[0], robot.inertia[1]])
        self.kp = cfg.omega_n ** 2
        self.kd = 2.0 * cfg.zeta * cfg.omega_n
        self.lim = np.array([cfg.fx_max, cfg.tau_max, cfg.tau_max])
        self._guess = [0.0, 0.0]

    def predicted_forces(self, q) -> np.ndarray:
        """External generalized forces (N, N m, N m) the model predicts at pose q."""
        Q, e1, e2 = _quad_form(q[1], q[2], self.robot)
        cs = []
        for i, b in enumerate(self.beams):
            c = contact_scalar(q, b, i, self.robot, self.layout, Q=Q, guess=self._guess[i], gravity=self.gravity)
            self._guess[i] = c.theta
            cs.append(c)
        return np.array(generalized_forces(q, cs, self.robot, self.gravity, self.pitch_axis, e1, e2))

    def __call__(self, t, q, v, contacts) -> tuple[float, float, float]:
        qd, vd, ad = self.plan.desired(t - self.t0)
        q = np.asarray(q, float)
        v = np.asarray(v, float)
        acc = ad - self.kd * (v - vd) - self.kp * (q - qd)
        u = self.mass * acc - self.predicted_forces(q)
        return tuple(np.clip(u, -self.lim, self.lim))


def energy_cost(u: np.ndarray, v: np.ndarray, dt: float) -> float:
    """Eq. 11: actuator work counting positive power only, J.

    Args:
        u: inputs (F_x, tau_1, tau_2) at each control step, shape (m, 3).
        v: rates (v_x, omega_1, omega_2) at the same instants, shape (m, 3).
        dt: control period, s.
    """
    p = np.asarray(u, float) * np.asarray(v, float)
    return float(np.maximum(p, 0.0).sum() * dt)


def hold_constant(fx: float, tau1: float = 0.0, tau2: float = 0.0, after_contact: bool = True):
    """Open-loop input: zero before first contact, then constant (paper Sec. III-A)."""
    state = {"c": not after_contact}

    def ctrl(t, q, v, contacts):
        if contacts[0].in_contact or contacts[1].in_contact:
            state["c"] = True
        return (fx, tau1, tau2) if state["c"] else (0.0, 0.0, 0.0)

    return ctrl

