"""Equations of motion (eqs. 1-3) and their time stepping. Frames and conventions: :mod:`.model`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from .contact import ContactState, contact_scalar, generalized_forces
from .geometry import ModelConfig, _quad_form


class SimulatedTimeout(Exception):
    """A run reached its simulated-time cap (``protocol.timeout``) before it could finish."""


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
