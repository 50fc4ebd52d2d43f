"""Motion constraints MC#1-MC#11 of the HIT-MRII (seed 001 secs. 3-6) as pure functions.

Each constraint is a measure ``m_i`` normalised by its scale ``m_i,max`` to a ratio
``eta_i = m_i / m_i,max``; motion is within the safety margin while ``eta_i <= kappa_i`` (the
paper's eq. 35), with one threshold vector ``kappa`` per mode (:data:`THRESHOLDS`): looser for
the wheel-only modes WRM/WCM, tighter posture limits for the reconfiguring modes (sec. 6). The
paper's threshold table is lost: the scales and kappa values here are reconstructions
(docs/assumptions-srwmr.md), except MC#10 (W_diff <= 1100 N SWLM / 1300 N DWLM) and MC#11
(W_fmr <= 700 N) which the paper states.

MC#1 is a precondition (which wheels may be lifted); MC#2/#3 feasibility (MC#2 logged, MC#3 kept
by the QP); MC#3-#9 enter the constraint-saturated IK (:mod:`terrabench.systems.srwmr.ik`)
linearised one control step ahead; the supervisor halts on MC#4/#5 (posture) and MC#10/#11 (loads).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from terrabench.config import check_fields, param
from terrabench.systems.srwmr.robot import WHEELS

#: MC#1: the lift sets the paper allows (single wheels, symmetric pairs, asymmetric pairs)
ALLOWED_LIFTS = (
    ("c1",),
    ("c2",),
    ("c3",),
    ("c4",),
    ("c5",),
    ("c6",),
    ("c1", "c2"),
    ("c3", "c4"),
    ("c5", "c6"),
    ("c1", "c4"),
    ("c2", "c3"),
    ("c3", "c6"),
    ("c4", "c5"),
)
INF = math.inf


@dataclass(frozen=True)
class MotionConstraint:
    """One motion constraint MC#k as one definition the IK and the supervisor both read.

    ``measures``: the quantity, as the paper states it; ``scale``: the :class:`Scales` field its
    ratio is normalised by (None: by the robot's own nominal value, MC#3's front-middle wheelbase
    :attr:`~terrabench.systems.srwmr.robot.RobotConfig.wheelbase_fm`); ``ratio``: its slot in the
    ratio vector (and in each mode's kappa of :data:`THRESHOLDS`); ``qp_rows``: the rows
    ``[start, stop)`` of the saturated IK's ``G u <= h`` that keep it one step ahead (None: not in
    the QP); ``halts``: the supervisor halts when the measured ratio reaches kappa;
    ``with_clutch``: its QP rows are kept in the lifting modes (False: the symmetric-lift rows a
    clutched side does not follow). The rows are built by
    :func:`~terrabench.systems.srwmr.ik.build_qp` and the ratios by :func:`period_ratios`
    (compiled, one kernel each); tests/srwmr/test_constraints_ik_metrics.py checks that a command
    on a term's QP boundary gives exactly its kappa as ratio.
    """

    name: str
    measures: str
    scale: str | None
    ratio: int
    qp_rows: tuple[int, int] | None
    halts: bool
    with_clutch: bool = True

    def kappa(self, mode: str) -> float:
        return float(thresholds(mode)[self.ratio])


#: MC#2-MC#11, in the order of the ratio vector (MC#1 is the lift precondition, :func:`mc1_check`)
CONSTRAINTS = (
    MotionConstraint("MC2", "commanded rim speeds against those the suspension motion requires", "v2", 0,
                     None, False),
    MotionConstraint("MC3", "front-middle wheelbase reduction", None, 1, (0, 2), False),
    MotionConstraint("MC4", "left-right hinge-height asymmetry (roll)", "dh", 2, (2, 4), True, False),
    MotionConstraint("MC5", "left-right wheelbase asymmetry (yaw deflection)", "dd", 3, (4, 6), True, False),
    MotionConstraint("MC6", "rocker-induced front-wheel speed against the side's speed", "v6_floor", 4, (6, 10),
                     False),
    MotionConstraint("MC7", "change of the forward speed per step", "v_floor", 5, (10, 12), False),
    MotionConstraint("MC8", "change of the yaw rate per step", "w_floor", 6, (12, 14), False),
    MotionConstraint("MC9", "left-right vertical speed difference (roll rate)", "vz9", 7, (14, 16), False, False),
    MotionConstraint("MC10", "W_diff, the spread of the wheel loads", "w_diff", 8, None, True),
    MotionConstraint("MC11", "W_fmr, W_max's or W_min's distance from the average load", "w_fmr", 9, None, True),
)
NAMES = tuple(c.name for c in CONSTRAINTS)
#: the ratios the supervisor halts on (the stability margins of sec. 7.1, posture and loads):
#: "feasibility prerequisites ... not considered as stability-margin indicators" [S] are not
MONITORED = np.array([c.halts for c in CONSTRAINTS])


def mc1_check(lifted) -> None:
    """ValueError naming the allowed lift sets unless ``lifted`` obeys MC#1 (at most two wheels,
    never front and rear together, at most one per side)."""
    key = tuple(sorted(lifted))
    bad = [w for w in key if w not in WHEELS]
    if bad:
        raise ValueError(f"lift {'+'.join(key)} names unknown wheel(s) {bad}; valid wheels: {', '.join(WHEELS)}")
    if key and key not in ALLOWED_LIFTS:
        allowed = ", ".join("+".join(a) for a in ALLOWED_LIFTS)
        raise ValueError(
            f"lift {'+'.join(key)} violates MC#1 (at most two wheels, not front and rear together, "
            f"one per side); allowed lifts: {allowed}"
        )


#: the loads W_fmr can be measured about (``Scales.w_fmr_centre``)
FMR_CENTRES = ("mean", "midrange")


@dataclass(frozen=True)
class Scales:
    """Normalising scales m_i,max of the ratios [R] (docs/assumptions-srwmr.md)."""

    v2: float = param(0.01, gt=0.0, le=1.0, unit="m/s", doc="MC#2 wheel-suspension speed mismatch scale")
    dh: float = param(0.10, gt=0.0, le=1.0, unit="m", doc="MC#4 left-right hinge-height asymmetry scale")
    dd: float = param(0.10, gt=0.0, le=1.0, unit="m", doc="MC#5 left-right wheelbase asymmetry scale")
    v6_floor: float = param(0.008, gt=0.0, le=0.5, unit="m/s",
                            doc="MC#6 side-speed floor: standing still, the rocker-induced front-wheel speed may "
                                "reach kappa x this (0.9 x 8 = 7.2 mm/s) [R: the paper's standstill motions ran "
                                "their front wheel at 7 mm/s (Task 6's lift) and 4.9-7.2 mm/s (Task 3) within "
                                "MC#6, docs/assumptions-srwmr.md]")
    v_floor: float = param(0.005, gt=0.0, le=0.5, unit="m/s", doc="MC#7 speed floor under the ratio")
    w_floor: float = param(0.005, gt=0.0, le=0.5, unit="rad/s", doc="MC#8 yaw-rate floor")
    vz9: float = param(0.01, gt=0.0, le=1.0, unit="m/s", doc="MC#9 left-right vertical speed difference scale")
    w_diff: float = param(1300.0, gt=0.0, le=1e4, unit="N", doc="MC#10 W_diff scale [S 1100 SWLM / 1300 DWLM]")
    w_fmr: float = param(700.0, gt=0.0, le=1e4, unit="N", doc="MC#11 W_fmr scale [S 700]")
    w_fmr_centre: str = param("mean", choices=FMR_CENTRES,
                              doc="the load W_fmr measures W_max and W_min from (its equation is lost: 'the maximum "
                                  "difference between the highest wheel load, Wmax, the lowest wheel load, Wmin, and "
                                  "their average load' [S]): mean = the six wheels' mean load; midrange = the average "
                                  "of W_max and W_min, so W_fmr = W_diff / 2 (docs/assumptions-srwmr.md, 'W_fmr')")

    def __post_init__(self) -> None:
        check_fields(self)


#: kappa per mode, in the order of NAMES (MC2 ... MC11); inf = not enforced in this mode. MC7 in the
#: wheel-only modes ramps the speed over ~5 s (0.01 of max(|v|, 5 mm/s) per 10 ms step): the paper's
#: speed transitions took "approximately 4 s" (Task 8).
THRESHOLDS: dict[str, tuple[float, ...]] = {
    # MC3's eta is normalised by the nominal front-middle wheelbase (948 mm on the fitted linkage);
    # each kappa keeps the least wheelbase the earlier calibration allowed on the 775 mm one:
    # WRM/WCM 310 mm (0.67), RCLM 372 mm (0.61), RCM 426 mm (0.55)
    #        MC2  MC3   MC4  MC5  MC6  MC7  MC8  MC9  MC10  MC11
    "WRM": (INF, 0.67, 1.0, 1.0, INF, 0.01, 0.6, 1.0, 1.0, 1.0),
    "WCM": (INF, 0.67, 1.0, 1.0, INF, 0.01, 0.6, 1.0, 1.0, 1.0),
    # RCLM MC3 0.61: Task 10 raises the chassis to 550 mm, which the fitted linkage cannot reach (534
    # mm at most); its highest T10 height, 480 mm, shortens the wheelbase to 432 mm (eta 0.54)
    "RCLM": (1.0, 0.61, 0.5, 0.5, 0.9, 0.3, 0.5, 0.6, 1.0, 1.0),
    "RCM": (1.0, 0.55, 0.5, 0.5, INF, 0.3, 0.5, 0.6, 1.0, 1.0),
    # SWLM / DWLM: MC10 W_diff <= 1100 N / 1300 N [S Tasks 6, 7], MC11 W_fmr <= 700 N [S]; MC5 not
    # monitored (lifting one side's wheel changes that side's wheelbase by design); MC4 is measured
    # from the IMU roll in these modes (control.py); MC3 0.66 admits the front CoM shift's posture
    # (500 mm: the front and middle tyres 35 mm apart on the fitted linkage, eta 0.65)
    "SWLM": (1.0, 0.66, 0.5, INF, 0.9, 0.3, 0.5, 0.6, 1100 / 1300, 1.0),
    "DWLM": (1.0, 0.66, 0.5, INF, 0.9, 0.3, 0.5, 0.6, 1300 / 1300, 1.0),
}
MODES = tuple(THRESHOLDS)
#: modes whose QP drops the symmetric-lift posture rows MC#4, MC#5, MC#9: with a clutch engaged the
#: rocker rate of a side lifts a wheel instead of its hinge, which those linearised rows do not model
LIFTING_MODES = ("SWLM", "DWLM")


def thresholds(mode: str) -> np.ndarray:
    try:
        return np.array(THRESHOLDS[mode], float)
    except KeyError:
        raise ValueError(f"mode={mode!r} is unknown; valid: {', '.join(MODES)}") from None


def qp_thresholds(mode: str) -> np.ndarray:
    """The kappa vector the saturated IK enforces in ``mode`` (:data:`LIFTING_MODES` without the
    rows of the terms kept only without a clutch: MC#4, MC#5, MC#9)."""
    k = thresholds(mode)
    if mode in LIFTING_MODES:
        k[[c.ratio for c in CONSTRAINTS if not c.with_clutch]] = INF
    return k


# ---------------------------------------------------------------------------- ratios
def eta_roll(h: np.ndarray, sc: Scales) -> float:
    """MC#4: |h_L - h_R| / dh (hinge-height asymmetry of the sides)."""
    return abs(float(h[0] - h[1])) / sc.dh


def eta_yaw(wb: np.ndarray, sc: Scales) -> float:
    """MC#5: |wb_L - wb_R| / dd (left-right deflection asymmetry)."""
    return abs(float(wb[0] - wb[1])) / sc.dd


def eta_rocker_vs_side(dx_front: np.ndarray, v_side: np.ndarray, sc: Scales) -> float:
    """MC#6: the rocker-induced front-wheel speed over the side's commanded speed (max of sides)."""
    return float(np.max(np.abs(dx_front) / np.maximum(np.abs(v_side), sc.v6_floor)))


def eta_change(new: float, old: float, floor: float) -> float:
    """MC#7 / MC#8: |new - old| / max(|old|, floor)."""
    return abs(new - old) / max(abs(old), floor)


def eta_roll_rate(vz: np.ndarray, sc: Scales) -> float:
    """MC#9: |vz_L - vz_R| / vz9 (vertical speed difference of the sides)."""
    return abs(float(vz[0] - vz[1])) / sc.vz9


def w_diff(loads) -> float:
    """W_diff = W_max - W_min of one instant's loads (N): :func:`load_figures`."""
    return float(load_figures(loads)[0])


def load_figures(loads, centre: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """W_diff = W_max - W_min and W_fmr = max(W_max - c, c - W_min) (N) over the last axis of
    ``loads`` (one instant's six loads, or a (n, 6) series), c the loads' mean (``centre`` "mean")
    or the average of W_max and W_min ("midrange": W_fmr = W_diff / 2). The compiled
    :func:`period_ratios` computes the same per period."""
    if centre not in FMR_CENTRES:
        raise ValueError(f"centre={centre!r} is unknown; valid: {', '.join(FMR_CENTRES)}")
    w = np.asarray(loads, float)
    hi, lo = w.max(axis=-1), w.min(axis=-1)
    m = w.mean(axis=-1) if centre == "mean" else 0.5 * (hi + lo)
    return hi - lo, np.maximum(hi - m, m - lo)


def w_fmr(loads, centre: str = "mean") -> float:
    """W_fmr of one instant's loads (N): :func:`load_figures`."""
    return float(load_figures(loads, centre)[1])


def load_ratios(loads, sc: Scales) -> tuple[float, float]:
    """(MC#10, MC#11) ratios."""
    wd, wf = load_figures(loads, sc.w_fmr_centre)
    return float(wd) / sc.w_diff, float(wf) / sc.w_fmr


def mc2_ratio(v_cmd: np.ndarray, v_kin: np.ndarray, sc: Scales) -> float:
    """MC#2: largest mismatch between the commanded rim speeds and the speeds the suspension
    motion requires (m/s), over v2 (a feasibility check of the command, logged)."""
    return float(np.max(np.abs(np.asarray(v_cmd) - np.asarray(v_kin)))) / sc.v2


@numba.njit(cache=True)
def _ratios_kernel(mc2_on, rim_cmd, mu, u_prev, J, ddelta, dz, wb, delta, u, load, k):
    """The ratios of :data:`NAMES` of one control period, compiled: the expressions of
    :func:`mc2_ratio`, :func:`eta_roll`, :func:`eta_yaw`, :func:`eta_change`,
    :func:`load_ratios` ... in the same order on scalars (bitwise the oracle
    ``period_ratios_reference`` in tests/srwmr/srwmr_reference.py; tested)."""
    fl, half, v2, dh, dd, v_floor, w_floor, vz9, w_diff_scale, w_fmr_scale = (
        k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], k[8], k[9])
    r = np.zeros(10)
    u0, u2, u3, u4 = u[0], u[2], u[3], u[4]
    if mc2_on:
        m = 0.0
        for i in range(6):
            v_kin = u_prev[0] + J[i, 0] * ddelta[i % 2]
            m = max(m, abs(rim_cmd[i] * math.cos(mu[i]) - v_kin))
        r[0] = m / v2
    wbl, wbr = wb[0], wb[1]
    r[1] = max((fl - wbl) / fl, (fl - wbr) / fl)
    r[2] = abs(dz[0] * delta[0] - dz[1] * delta[1]) / dh
    r[3] = abs(wbl - wbr) / dd
    if u3 != 0.0 or u4 != 0.0:
        v6_floor = k[10]
        r[4] = max(abs(J[0, 0] * u3) / max(abs(u0 - u2 * half), v6_floor),
                   abs(J[1, 0] * u4) / max(abs(u0 + u2 * half), v6_floor))
    r[5] = abs(u0 - u_prev[0]) / max(abs(u_prev[0]), v_floor)
    r[6] = abs(u2 - u_prev[2]) / max(abs(u_prev[2]), w_floor)
    r[7] = abs(dz[0] * u3 - dz[1] * u4) / vz9
    lo = hi = load[0]
    total = 0.0
    for i in range(6):
        lo, hi = min(lo, load[i]), max(hi, load[i])
        total += load[i]
    mean = total / 6  # numpy's order for 6 values (one after the other from 0)
    if k[11] != 0.0:  # W_fmr about the midrange of W_max and W_min (Scales.w_fmr_centre)
        mean = 0.5 * (hi + lo)
    r[8] = (hi - lo) / w_diff_scale
    r[9] = max(hi - mean, mean - lo) / w_fmr_scale
    return r


def period_ratios(cfg, sc: Scales, u, u_prev, J, dz, wb, delta, ddelta, mu, load, rim_cmd=None,
                  k: np.ndarray | None = None) -> np.ndarray:
    """(10,) ratios of :data:`NAMES` this period (the controller's ``_ratios``), compiled.

    ``u``, ``u_prev`` (5,) this and the last executed command; ``J``, ``dz``, ``wb`` the rocker
    Jacobian (6, 3), hinge rise (2,) and front-middle wheelbases (2,) at ``delta``; ``ddelta``,
    ``mu``, ``load`` measured; ``rim_cmd`` (6,) the last commanded rim speeds (None: no MC#2).
    MC#2 is evaluated while the suspension moves (a rate above 1e-4 rad/s). ``k``: :func:`ratio_consts`
    (None: built here)."""
    mc2_on = rim_cmd is not None and (abs(float(ddelta[0])) > 1e-4 or abs(float(ddelta[1])) > 1e-4)
    rim = _NO_RIM if rim_cmd is None else np.asarray(rim_cmd, float)
    if k is None:
        k = ratio_consts(cfg, sc)
    return _ratios_kernel(mc2_on, rim, mu, np.asarray(u_prev, float), J, ddelta, dz, wb, delta,
                          np.asarray(u, float), load, k)


def ratio_consts(cfg, sc: Scales) -> np.ndarray:
    """The scalars :func:`period_ratios` reads, in the kernel's order (a controller builds them
    once and passes them as ``k``)."""
    return np.array((cfg.wheelbase_fm, cfg.track / 2, sc.v2, sc.dh, sc.dd, sc.v_floor, sc.w_floor, sc.vz9,
                     sc.w_diff, sc.w_fmr, sc.v6_floor, 1.0 if sc.w_fmr_centre == "midrange" else 0.0))


_NO_RIM = np.zeros(6)


@numba.njit(cache=True)
def _halting_kernel(ratios, kappa, monitored):
    n = ratios.shape[0]
    over = np.zeros(n)
    hit = False
    for i in range(n):
        if monitored[i]:
            over[i] = ratios[i] / kappa[i]
            hit = hit or over[i] >= 1.0
    if not hit:
        return -1
    best = 0
    for i in range(n):  # numpy's argmax: the first NaN, else the first maximum
        if math.isnan(over[i]):
            return i
        if over[i] > over[best]:
            best = i
    return best


def halting_ratio(ratios: np.ndarray, kappa: np.ndarray, monitored: np.ndarray) -> int:
    """Index of the monitored ratio the supervisor halts on (the largest ``ratio / kappa`` when
    one reaches 1), -1 when none does: ``np.argmax(np.where(monitored, ratios / kappa, 0))`` if
    any is >= 1, compiled (tested against that expression)."""
    return int(_halting_kernel(ratios, kappa, monitored))
