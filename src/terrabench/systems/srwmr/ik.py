"""Constraint-saturated inverse kinematics (the paper's eq. 41, lost; reconstructed).

Every control period (10 ms) the nominal command ``u_nom = (vx, vy, wz, ddelta_L, ddelta_R)``
(body twist in the body frame and the two rocker closing rates) is projected onto the set the
motion constraints allow one step ahead:

    u* = argmin (u - u_nom)' W (u - u_nom)   s.t.   G u <= h,   lb <= u <= ub

with the linearised MC#3 (wheelbase reduction), MC#4 (roll asymmetry), MC#5 (yaw deflection
asymmetry), MC#6 (rocker rate against the side speed), MC#7 (forward-speed change), MC#8
(yaw-rate change) and MC#9 (roll rate), 16 rows, and the speed/rate bounds. Solved with DAQP
through ``qpsolvers``; infeasible (no u in the set) means halt. The wheel commands then follow
from :func:`terrabench.systems.srwmr.kinematics.inverse_kinematics`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numba
import numpy as np
import qpsolvers

from terrabench.config import check_fields, param
from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.kinematics import hinge_rise, rocker_jacobian, wheelbase_front_middle
from terrabench.systems.srwmr.robot import RobotConfig

N_U = 5
N_INEQ = 16


@dataclass(frozen=True)
class IKLimits:
    """Bounds of the command (the robot's drive limits) and the QP weights."""

    v_max: float = param(0.06, gt=0.0, le=1.0, unit="m/s", doc="body speed bound")
    w_max: float = param(0.1, gt=0.0, le=2.0, unit="rad/s", doc="yaw-rate bound")
    rate_max: float = param(0.05, gt=0.0, le=1.0, unit="rad/s", doc="rocker closing-rate bound")
    weights: tuple[float, float, float, float, float] = param((1.0, 1.0, 1.0, 4.0, 4.0), gt=0.0, le=1e6, length=5,
                                                              doc="diagonal QP weights W: vx, vy, wz, rates L, R")
    delta_range: tuple[float, float] = param((-0.60, 1.15), ge=-3.14, le=3.14, length=2, unit="rad",
                                             doc="closing angles the rockers may reach (lower, upper): 0.05 rad "
                                                 "inside the rocker joint's stops (robot.rocker_range, delta = -q)")

    def __post_init__(self) -> None:
        check_fields(self)
        if not self.delta_range[0] < self.delta_range[1]:
            raise ValueError(f"limits.delta_range={self.delta_range!r} is invalid; valid: lower < upper (rad)")


@dataclass
class IKState:
    """What the IK needs from the observation: closing angles (2,), previous command (5,)."""

    delta: np.ndarray
    u_prev: np.ndarray


def build_qp(
    cfg: RobotConfig,
    st: IKState,
    kappa: np.ndarray,
    sc: mc.Scales,
    lim: IKLimits,
    ts: float,
    J: np.ndarray | None = None,
    wb: np.ndarray | None = None,
    dz: np.ndarray | None = None,
):
    """(G, h, lb, ub) of one control step: the linearised MC#3-#9 rows (see the module docstring),
    computed by :func:`_qp_kernel` into fresh arrays (bitwise the oracle ``build_qp_reference`` in
    tests/srwmr/srwmr_reference.py, tested).
    ``J``, ``wb``, ``dz``: the rocker Jacobian, front-middle wheelbases and hinge rise at
    ``st.delta`` if the caller already has them."""
    d = np.asarray(st.delta, float)
    J = rocker_jacobian(cfg, d) if J is None else J
    wb = wheelbase_front_middle(cfg, d) if wb is None else wb
    dz = hinge_rise(J) if dz is None else dz
    out = np.zeros((N_INEQ, N_U)), np.zeros(N_INEQ), np.zeros(N_U), np.zeros(N_U)
    u_prev = np.asarray(st.u_prev, float)
    _qp_kernel(np.asarray(J, float), d, np.asarray(wb, float), np.asarray(dz, float), np.asarray(kappa, float),
               u_prev, u_prev, kernel_consts(cfg, sc, lim, ts), *out)
    return out


def kernel_consts(cfg: RobotConfig, sc: mc.Scales, lim: IKLimits, ts: float) -> np.ndarray:
    """The scalars :func:`_qp_kernel` reads after ``u_nom`` (its ``k``), in its order."""
    return np.array((cfg.wheelbase_fm, cfg.track / 2, ts, sc.dh, sc.dd, sc.v_floor, sc.w_floor, sc.vz9,
                     lim.v_max, lim.w_max, lim.rate_max, lim.delta_range[0], lim.delta_range[1], sc.v6_floor), float)


@numba.njit(cache=True)
def _qp_kernel(J, d, wb, dz, kappa, u_prev, u_nom, k, G, h, lb, ub):
    """The rows of the oracle ``build_qp_reference`` (tests/srwmr/srwmr_reference.py) compiled (bitwise the
    same G, h, lb, ub; tested), written
    into the buffers ``G``, ``h``, ``lb``, ``ub``, and where ``u_nom`` lies: 0 the bounds are empty
    (infeasible), 1 inside the set (the QP's own optimum), 2 outside
    (the solver is needed). ``k``: :func:`kernel_consts`."""
    d0, d1, wbl, wbr, dz0, dz1, u0, u2 = d[0], d[1], wb[0], wb[1], dz[0], dz[1], u_prev[0], u_prev[2]
    wb0, half, ts, dh, dd, v_floor, w_floor, vz9 = k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7]
    v_max, w_max, rate_max, lo, hi, v6_floor = k[8], k[9], k[10], k[11], k[12], k[13]
    j00, j10 = J[0, 0], J[1, 0]
    dwb0, dwb1 = j00 - J[2, 0], j10 - J[3, 0]
    k3, k4, k5, k6, k7, k8, k9 = kappa[1], kappa[2], kappa[3], kappa[4], kappa[5], kappa[6], kappa[7]
    big = 1e6
    hl, hr = dz0 * d0, dz1 * d1
    lim6l = k6 * max(abs(u0 - u2 * half), v6_floor) if math.isfinite(k6) else big
    lim6r = k6 * max(abs(u0 + u2 * half), v6_floor) if math.isfinite(k6) else big
    lim7 = k7 * max(abs(u0), v_floor) if math.isfinite(k7) else big
    lim8 = k8 * max(abs(u2), w_floor) if math.isfinite(k8) else big
    lim9 = k9 * vz9 if math.isfinite(k9) else big
    G[:] = 0.0
    G[0, 3], G[1, 4] = -dwb0 * ts / wb0, -dwb1 * ts / wb0  # MC3
    G[2, 3], G[2, 4], G[3, 3], G[3, 4] = dz0 * ts, -dz1 * ts, -dz0 * ts, dz1 * ts  # MC4
    G[4, 3], G[4, 4], G[5, 3], G[5, 4] = dwb0 * ts, -dwb1 * ts, -dwb0 * ts, dwb1 * ts  # MC5
    G[6, 3], G[7, 3], G[8, 4], G[9, 4] = j00, -j00, j10, -j10  # MC6
    G[10, 0], G[11, 0], G[12, 2], G[13, 2] = 1.0, -1.0, 1.0, -1.0  # MC7, MC8
    G[14, 3], G[14, 4], G[15, 3], G[15, 4] = dz0, -dz1, -dz0, dz1  # MC9
    h[0] = (k3 - (wb0 - wbl) / wb0) if math.isfinite(k3) else big
    h[1] = (k3 - (wb0 - wbr) / wb0) if math.isfinite(k3) else big
    h[2] = (k4 * dh - (hl - hr)) if math.isfinite(k4) else big
    h[3] = (k4 * dh + (hl - hr)) if math.isfinite(k4) else big
    h[4] = (k5 * dd - (wbl - wbr)) if math.isfinite(k5) else big
    h[5] = (k5 * dd + (wbl - wbr)) if math.isfinite(k5) else big
    h[6] = h[7] = lim6l
    h[8] = h[9] = lim6r
    h[10], h[11], h[12], h[13] = u0 + lim7, -u0 + lim7, u2 + lim8, -u2 + lim8
    h[14] = h[15] = lim9
    lb[0], lb[1], lb[2] = -v_max, -v_max, -w_max
    ub[0], ub[1], ub[2] = v_max, v_max, w_max
    lb[3], lb[4] = max(-rate_max, (lo - d0) / ts), max(-rate_max, (lo - d1) / ts)
    ub[3], ub[4] = min(rate_max, (hi - d0) / ts), min(rate_max, (hi - d1) / ts)
    where = 1
    for j in range(5):
        if lb[j] > ub[j] + 1e-12:
            return 0
        if u_nom[j] < lb[j] or u_nom[j] > ub[j]:
            where = 2
    for i in range(16):
        gu = 0.0
        for j in range(5):
            gu += G[i, j] * u_nom[j]
        if not gu <= h[i] + 1e-12:
            where = 2
    return where


def limited_share(solves: int, inside: int, changed: int) -> float:
    """Of all control periods (``solves`` solver calls + ``inside`` periods already feasible), the
    share in which the projection changed the command (``changed`` of the calls)."""
    periods = solves + inside
    return changed / periods if periods else 0.0


class SaturatedIK:
    """The per-step projection; keeps solve-time statistics (``times`` in seconds)."""

    def __init__(self, cfg: RobotConfig, lim: IKLimits, sc: mc.Scales, ts: float, solver: str = "daqp"):
        self.cfg, self.lim, self.sc, self.ts, self.solver = cfg, lim, sc, ts, solver
        self.P = np.diag(np.asarray(lim.weights, float))
        self._consts = kernel_consts(cfg, sc, lim, ts)
        self._G, self._h, self._lb, self._ub = np.zeros((N_INEQ, N_U)), np.zeros(N_INEQ), np.zeros(N_U), np.zeros(N_U)
        self.times: list[float] = []
        self.active = 0  # steps where the projection changed the command
        self.inside = 0  # steps whose nominal command was already feasible (no solver call)

    def solve(
        self,
        u_nom: np.ndarray,
        st: IKState,
        kappa: np.ndarray,
        J: np.ndarray | None = None,
        wb: np.ndarray | None = None,
        always: bool = False,
        dz: np.ndarray | None = None,
    ) -> np.ndarray | None:
        """u* or None when infeasible (``J``, ``wb``, ``dz``: the rocker Jacobian, wheelbases and
        hinge rise at ``st.delta`` if already known). A nominal command inside the set is the QP's own optimum
        and is returned without calling the solver (``always``: call it anyway, for timing)."""
        u_nom = np.asarray(u_nom, float)
        if J is None or wb is None or dz is None:
            G, h, lb, ub = build_qp(self.cfg, st, kappa, self.sc, self.lim, self.ts, J, wb, dz)
            if (lb > ub + 1e-12).any():
                return None
            where = 1 if (G @ u_nom <= h + 1e-12).all() and (u_nom >= lb).all() and (u_nom <= ub).all() else 2
        else:
            G, h, lb, ub = self._G, self._h, self._lb, self._ub
            where = _qp_kernel(J, np.asarray(st.delta, float), wb, dz, kappa, np.asarray(st.u_prev, float), u_nom,
                               self._consts, G, h, lb, ub)
            if where == 0:
                return None
            # (the buffers are this call's: the solver reads them now, nothing keeps them)
        if not always and where == 1:
            self.inside += 1
            return u_nom.copy()
        q = -self.P @ u_nom
        t0 = time.perf_counter()
        u = qpsolvers.solve_qp(self.P, q, G, h, lb=lb, ub=ub, solver=self.solver)
        self.times.append(time.perf_counter() - t0)
        if u is None:
            return None
        if np.max(np.abs(u - u_nom)) > 1e-9:
            self.active += 1
        return np.asarray(u, float)

    def timing(self) -> dict[str, float]:
        """Solve statistics: ``qp_n`` solver calls (the nominal command was outside the set),
        ``qp_inside`` periods already inside, ``qp_active_share`` of the calls that changed the
        command, and ``qp_limited_share``: of all periods, those where the projection changed the
        command (the constraint-saturated IK at work)."""
        t = np.asarray(self.times) * 1e6
        limited = limited_share(len(t), self.inside, self.active)
        if not len(t):
            return {"qp_n": 0, "qp_inside": self.inside, "qp_median_us": float("nan"), "qp_p99_us": float("nan"),
                    "qp_limited_share": limited}
        return {
            "qp_n": int(len(t)),
            "qp_inside": self.inside,
            "qp_median_us": float(np.median(t)),
            "qp_p99_us": float(np.percentile(t, 99)),
            "qp_active_share": self.active / len(t),
            "qp_limited_share": limited,
        }
