"""Figures of a HIT-MRII episode as pure functions of arrays (seed 001 sec. 8.4-8.5).

* body slip ``s_b = 1 - v_b / v_cmd`` (the paper's robot slip), time-aggregated as
  ``1 - sum(v) / sum(v_cmd)`` over the instants with a commanded speed;
* wheel slip ``s = (r w - v) / (r w)`` (mean of the wheels in the soil, from the soil model: a lifted
  wheel has none);
* drawbar-pull coefficient ``PC = F_DP / F_N``;
* traction efficiency ``PE = F_DP v / P_drive`` (the paper's eq. 43 form, DP v over T w);
* energy (J) as the integral of the actuators' |tau w|;
* wheel-load figures ``W_diff = W_max - W_min``, ``W_fmr = max(W_max - c, c - W_min)``, c the loads'
  mean or the midrange of W_max and W_min (``scales.w_fmr_centre``);
* constraint ratios: their maxima over the episode.
"""

from __future__ import annotations

import numpy as np

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.constraints import load_figures  # the figures, here and in the reports
from terrabench.systems.srwmr.robot import WHEELS


def body_slip(v, v_cmd, v_min: float = 1e-4) -> float:
    """1 - sum(v)/sum(v_cmd) over the instants with |v_cmd| > v_min (nan if none)."""
    v, vc = np.asarray(v, float), np.asarray(v_cmd, float)
    sel = np.isfinite(vc) & (np.abs(vc) > v_min) & np.isfinite(v)
    if not sel.any():
        return float("nan")
    return float(1.0 - v[sel].sum() / vc[sel].sum())


def along_command(v, v_cmd, v_lat=None, vy_cmd=None):
    """(speed along the commanded direction, commanded speed) per instant: the body velocity
    (forward ``v``, lateral ``v_lat``) projected on the commanded (``v_cmd``, ``vy_cmd``). Rows
    with no lateral command are ``(v sign(v_cmd), |v_cmd|)`` exactly, so a crab (WCM) and a
    forward run share one slip definition."""
    v, vc = np.asarray(v, float), np.asarray(v_cmd, float)
    if v_lat is None or vy_cmd is None:
        return v, vc
    vl, vyc = np.asarray(v_lat, float), np.nan_to_num(np.asarray(vy_cmd, float))
    norm = np.hypot(vc, vyc)
    lateral = vyc != 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        par = np.where(lateral, (v * vc + vl * vyc) / norm, v * np.sign(vc))
    return par, np.where(lateral, norm, np.abs(vc))


def body_slip_series(v, v_cmd, v_min: float = 1e-4):
    """Instantaneous s_b (nan where nothing is commanded)."""
    v, vc = np.asarray(v, float), np.asarray(v_cmd, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(vc) > v_min, 1.0 - v / vc, np.nan)


def windowed_slip(v, v_cmd, n: int, v_min: float = 1e-4) -> np.ndarray:
    """Body slip ``1 - sum(v)/sum(v_cmd)`` over consecutive windows of ``n`` samples (those with
    a commanded speed; windows with fewer than half such samples dropped)."""
    v, vc = np.asarray(v, float), np.asarray(v_cmd, float)
    sel = np.isfinite(vc) & (np.abs(vc) > v_min) & np.isfinite(v)
    m = len(v) // n
    if m == 0:
        return np.array([])
    s = sel[: m * n].reshape(m, n)
    sv = np.where(s, v[: m * n].reshape(m, n), 0.0).sum(1)
    sc = np.where(s, vc[: m * n].reshape(m, n), 0.0).sum(1)
    ok = s.sum(1) >= n / 2
    return 1.0 - sv[ok] / sc[ok]


def drawbar_coefficient(dp, fn) -> float:
    """PC = sum F_DP / sum F_N (nan if no load)."""
    fn = float(np.nansum(fn))
    return float(np.nansum(dp)) / fn if fn > 0 else float("nan")


def traction_efficiency(dp, v, p_drive) -> float:
    """PE = sum(DP v) / sum(P_drive) (nan if no drive power)."""
    dp, v, p = (np.asarray(a, float) for a in (dp, v, p_drive))
    sel = np.isfinite(dp) & np.isfinite(v) & np.isfinite(p)
    den = p[sel].sum()
    return float((dp[sel] * v[sel]).sum() / den) if den > 0 else float("nan")


def energy(power, dt: float) -> float:
    """Integral of power (W) sampled every ``dt`` (s), J."""
    return float(np.nansum(np.asarray(power, float)) * dt)


def path_length(x, y) -> float:
    x, y = np.asarray(x, float), np.asarray(y, float)
    return float(np.sum(np.hypot(np.diff(x), np.diff(y))))


def episode_metrics(log, x_start: float, z_start: float, w_fmr_centre: str = "mean") -> dict[str, float]:
    """The named figures of a finished episode log (columns of :mod:`terrabench.systems.srwmr.task`)."""
    col = log.column
    x, y, z = col("x"), col("y"), col("z")
    names = set(log.columns)
    if {"v_lat", "vy_cmd"} <= names:
        v, vc = along_command(col("v"), col("v_cmd"), col("v_lat"), col("vy_cmd"))
    else:
        v, vc = col("v"), col("v_cmd")
    W = log.block([f"W_{c}" for c in WHEELS])
    wd, wf = load_figures(W, w_fmr_centre)
    moving = np.isfinite(vc) & (np.abs(vc) > 1e-4)
    slip = col("slip")
    out = {
        "distance": path_length(x, y),
        "progress": float(x[-1] - x_start),
        "climb": float(z[-1] - z_start),
        "energy_kJ": log.energy / 1000.0,
        "body_slip": body_slip(v, vc),
        "wheel_slip": float(np.nanmean(slip[moving])) if moving.any() else float("nan"),
        "sinkage": float(np.nanmean(col("sinkage"))),
        "W_mean": float(np.nanmean(W)),
        "W_diff_max": float(np.nanmax(wd)),
        "W_fmr_max": float(np.nanmax(wf)),
        "PC": drawbar_coefficient(col("DP")[moving], W.sum(axis=1)[moving]) if moving.any() else float("nan"),
        "PE": traction_efficiency(col("DP")[moving], v[moving], col("P_drive")[moving])
        if moving.any()
        else float("nan"),
        "mean_power_W": float(np.nanmean(np.diff(log.data[:, -1])) / log.period) if len(log.data) > 1 else float("nan"),
    }
    # spread of the slip over 5 s windows (Task 9's ranges)
    ws = windowed_slip(v, vc, max(1, int(round(5.0 / log.period))))
    out["slip_p10"] = float(np.percentile(ws, 10)) if len(ws) else float("nan")
    out["slip_p90"] = float(np.percentile(ws, 90)) if len(ws) else float("nan")
    for n in mc.NAMES:
        e = col(f"eta_{n}")
        out[f"max_eta_{n}"] = float(np.nanmax(e)) if np.isfinite(e).any() else float("nan")
    # per plan step (T8 stages): slip, time, energy
    step = col("step")
    en = log.data[:, -1]
    for k in np.unique(step[np.isfinite(step)]).astype(int)[:8]:
        sel = step == k
        out[f"step{k}_slip"] = body_slip(v[sel], vc[sel])
        idx = np.flatnonzero(sel)
        out[f"step{k}_time"] = float(len(idx) * log.period)
        out[f"step{k}_energy_kJ"] = float(en[idx[-1]] - en[idx[0]]) / 1000.0 if len(idx) > 1 else 0.0
    return out
