"""The constraint-saturated IK at work: a per-period trace of the QP (issue 27, piece 5).

Kept only by plans whose steps ask for it (``Step.trace``, the instances of group ``ik``,
:mod:`~terrabench.systems.srwmr.ik_cases`), so every other trial is untouched. Each control
period that passes through the IK the controller hands over the nominal command, the executed
one, the measured ratios and the QP's rows ``G u <= h`` of that period (for a ``-noqp`` twin,
whose command bypasses the projection, the rows and the solution of a shadow QP that is not
executed). From them:

* **changed**: the periods in which the projection changes the nominal command (the share is
  the controller's ``qp_limited_share``; in a bypassed twin the share it *would* change);
* **which rows**: per constraint (MC3 ... MC9, and the speed/rate/closing-angle ``bounds``), the
  changed periods in which its rows are active at the executed command (``qp_active_rows``) and
  the periods in which the nominal command violates them (``qp_violated_rows``);
* **one step ahead**: per constraint the ratio the rows predict for a command,
  ``kappa + (G_i u - h_i) / n_i`` (the max over its rows, ``n_i`` the row's normaliser): for
  MC3-#5 the posture ratio after one period, for MC6-#9 the command ratio itself; so the trace
  shows the nominal's ratio above kappa and the executed one at it;
* a thinned series (every ``every`` periods) of t, mode, both commands, the measured and the
  predicted ratios, and the runs of changed periods with their active rows (for the report's
  shading, :mod:`~terrabench.systems.srwmr.report_qp`).
"""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.srwmr import constraints as mc

#: the constraints with QP rows, in row order, then the command bounds
QP_NAMES = tuple(c.name for c in mc.CONSTRAINTS if c.qp_rows is not None) + ("bounds",)
_QP = [c for c in mc.CONSTRAINTS if c.qp_rows is not None]
#: row -> index in QP_NAMES
ROW_OF = np.concatenate([np.full(c.qp_rows[1] - c.qp_rows[0], i) for i, c in enumerate(_QP)])
#: the ratio-vector slots of QP_NAMES[:-1]
RATIO_SLOTS = np.array([c.ratio for c in _QP])
#: most runs of changed periods kept in the info (the counts are always complete)
MAX_RUNS = 4000


def _sig(x, n: int = 6):
    """Round floats to ``n`` significant digits for a compact info (nan -> None)."""
    if isinstance(x, (list, tuple, np.ndarray)):
        return [_sig(v, n) for v in x]
    x = float(x)
    if not math.isfinite(x):
        return None
    return float(f"{x:.{n}g}")


def row_norms(u_prev: np.ndarray, sc: mc.Scales, half_track: float) -> np.ndarray:
    """(16,) the normaliser of each QP row (:func:`~terrabench.systems.srwmr.ik._qp_kernel`):
    ``kappa + (G_i u - h_i) / n_i`` is the row's ratio one period ahead under ``u``."""
    u0, u2 = float(u_prev[0]), float(u_prev[2])
    nl, nr = max(abs(u0 - u2 * half_track), sc.v6_floor), max(abs(u0 + u2 * half_track), sc.v6_floor)
    return np.array([1.0, 1.0, sc.dh, sc.dh, sc.dd, sc.dd, nl, nl, nr, nr,
                     max(abs(u0), sc.v_floor), max(abs(u0), sc.v_floor),
                     max(abs(u2), sc.w_floor), max(abs(u2), sc.w_floor), sc.vz9, sc.vz9])


def predicted(G, h, u, kappa_qp, norms) -> np.ndarray:
    """(7,) per QP constraint the ratio its rows predict under ``u`` (nan where not enforced)."""
    k_row = np.asarray(kappa_qp, float)[RATIO_SLOTS][ROW_OF]
    with np.errstate(invalid="ignore"):
        r = np.where(np.isfinite(k_row), k_row + (G @ u - h) / norms, np.nan)
    out = np.full(len(_QP), np.nan)
    for i in range(len(_QP)):
        v = r[ROW_OF == i]
        if np.isfinite(v).any():
            out[i] = np.nanmax(v)
    return out


def row_sets(G, h, lb, ub, u, u_nom, kappa_qp) -> tuple[int, int]:
    """(active, violated) as bit masks over :data:`QP_NAMES`: the constraints whose rows are
    active (within a tolerance) at ``u``, and those whose rows ``u_nom`` violates."""
    k_row = np.asarray(kappa_qp, float)[RATIO_SLOTS][ROW_OF]
    on = np.isfinite(k_row)
    tol = 1e-9 + 1e-7 * np.abs(h)
    gu, gn = G @ u, G @ u_nom
    act, vio = 0, 0
    for i in range(len(_QP)):
        sel = (ROW_OF == i) & on
        if (gu[sel] >= h[sel] - tol[sel]).any():
            act |= 1 << i
        if (gn[sel] > h[sel] + 1e-12).any():
            vio |= 1 << i
    b = len(_QP)
    if ((u <= lb + 1e-9) | (u >= ub - 1e-9)).any():
        act |= 1 << b
    if ((u_nom < lb - 1e-12) | (u_nom > ub + 1e-12)).any():
        vio |= 1 << b
    return act, vio


class QPTrace:
    """What :class:`~terrabench.systems.srwmr.control.RoverController` records per period when a
    plan step has ``trace`` (see the module docstring); :meth:`info` is merged into its info."""

    def __init__(self, sc: mc.Scales, half_track: float, every: int = 10, bypassed: bool = False):
        self.sc, self.half, self.every, self.bypassed = sc, half_track, every, bypassed
        self.n = 0
        self.changed = 0
        self.active = np.zeros(len(QP_NAMES), int)
        self.violated = np.zeros(len(QP_NAMES), int)
        self.exceed_meas = np.zeros(len(_QP), int)  # periods the measured ratio is above kappa (+1e-3)
        self.max_meas = np.full(len(_QP), -np.inf)
        self.max_pred_nom = np.full(len(_QP), -np.inf)
        self.max_pred_exec = np.full(len(_QP), -np.inf)
        self.kappa: dict[str, list] = {}
        self.rows: list[list] = []
        self.runs: list[list] = []  # [t0, t1, active mask, violated mask] of consecutive changed periods
        self._win_changed = False
        self._last_changed = False

    def record(self, t, mode: str, mode_code: int, u_nom, u_qp, u, u_prev, ratios, kappa, kappa_qp,
               G, h, lb, ub) -> None:
        """One period: ``u_qp`` the projection (executed unless bypassed), ``u`` the executed command."""
        u_nom, u_qp, u = (np.asarray(a, float) for a in (u_nom, u_qp, u))
        norms = row_norms(u_prev, self.sc, self.half)
        changed = bool(np.max(np.abs(u_qp - u_nom)) > 1e-9)
        act, vio = row_sets(G, h, lb, ub, u_qp, u_nom, kappa_qp)
        p_nom, p_exec = predicted(G, h, u_nom, kappa_qp, norms), predicted(G, h, u, kappa_qp, norms)
        meas = np.asarray(ratios, float)[RATIO_SLOTS]
        k = np.asarray(kappa, float)[RATIO_SLOTS]
        self.kappa.setdefault(mode, _sig(k))
        self.n += 1
        if changed:
            self.changed += 1
            for i in range(len(QP_NAMES)):
                self.active[i] += (act >> i) & 1
        for i in range(len(QP_NAMES)):
            self.violated[i] += (vio >> i) & 1
        with np.errstate(invalid="ignore"):
            self.exceed_meas += np.isfinite(k) & (meas > k + 1e-3)
        self.max_meas = np.fmax(self.max_meas, meas)
        self.max_pred_nom = np.fmax(self.max_pred_nom, p_nom)
        self.max_pred_exec = np.fmax(self.max_pred_exec, p_exec)
        if changed:
            if self._last_changed and self.runs and self.runs[-1][2] == act:
                self.runs[-1][1] = float(t)
            elif len(self.runs) < MAX_RUNS:
                self.runs.append([float(t), float(t), act, vio])
        self._last_changed = changed
        self._win_changed = self._win_changed or changed
        if (self.n - 1) % self.every == 0:
            self.rows.append([_sig(t, 7), mode_code, int(self._win_changed), act if changed else 0]
                             + _sig(u_nom) + _sig(u) + _sig(meas) + _sig(p_nom) + _sig(p_exec))
            self._win_changed = False

    def info(self) -> dict:
        names = QP_NAMES
        qn = names[:-1]

        def per(a, names_=names):
            return {n: int(v) for n, v in zip(names_, a)}

        def fin(a):
            return {n: _sig(v) for n, v in zip(qn, a)}

        return {
            "qp_trace": {
                "bypassed": self.bypassed,
                "periods": self.n,
                "changed": self.changed,
                "changed_share": self.changed / self.n if self.n else 0.0,
                "names": list(names),
                "active_rows": per(self.active),
                "violated_rows": per(self.violated),
                "measured_above_kappa": per(self.exceed_meas, qn),
                "max_measured": fin(self.max_meas),
                "max_predicted_nominal": fin(self.max_pred_nom),
                "max_predicted_executed": fin(self.max_pred_exec),
                "kappa": self.kappa,
                "every": self.every,
                "columns": ["t", "mode", "changed", "active"] + [f"u_nom{i}" for i in range(5)]
                + [f"u{i}" for i in range(5)] + [f"eta_{n}" for n in qn] + [f"pred_nom_{n}" for n in qn]
                + [f"pred_exec_{n}" for n in qn],
                "rows": self.rows,
                "runs": self.runs,
            }
        }
