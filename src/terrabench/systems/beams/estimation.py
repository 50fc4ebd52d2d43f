"""Environmental force sensing and beam-parameter estimation (paper Secs. II-D, II-E, IV).

The robot senses the *total* beam force at 100 Hz with multiplicative Gaussian noise (eq. 6)
during a window ``T_s`` after first contact, knows its own pose at each sample, and fits the
beam parameters by minimising eq. 7 (sum over samples of the Euclidean norm of the force
residual) with Nelder-Mead from many random starts.

Speed: for a fixed hinge height the modelled force is linear in the stiffness, ``F = k G(h_b)``,
so the per-unit-stiffness force ``G`` is tabulated once per sensing record on a fine grid of
hinge heights and interpolated inside the objective. All random starts run together in a batched
Nelder-Mead (same reflection / expansion / contraction / shrink rules and tolerances as MATLAB's
``fminsearch``), so an estimate takes a fraction of a second.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from terrabench.config import Relation, check_fields, ordered, param, relation

from .model import Beam, ModelConfig, SimLog, SimulatedTimeout, deflection_vec, simulate

#: Names of the fitted parameters per estimation variant (number of unknowns).
VARIANTS = {
    4: ("k1", "k2", "hb1", "hb2"),
    3: ("k1", "k2", "hb"),
    2: ("k1", "k2"),
}


@dataclass(frozen=True)
class SensingConfig:
    """How the force data are collected."""

    sigma: float = 0.20
    """Standard deviation of the multiplicative noise Z in eq. 6 (0.2 = 20 %)."""
    sensing_time: float = 0.30
    """Sensing window T_s after first contact, s."""
    sample_rate: float = 100.0
    """Force-sensor sampling rate, Hz."""
    push_force: float = 1.0
    """Open-loop propulsion F_x after first contact while sensing, N (paper Sec. III-B-i)."""
    x_start: float = -0.08
    """Initial x of the robot centre, m (contact happens near x = -0.062 m)."""
    lookahead: float = 0.3
    """Extra simulated time after the window used only to check that contact goes on, s."""
    max_approach_time: float = 5.0
    """Give up looking for first contact after this long, s."""
    per_axis_noise: bool = True
    """Draw Z independently for each force axis (True) or one Z per sample (False)."""
    drive_speed: float | None = None
    """If set, x is driven at this constant speed, m/s (the experiment's servo carriage) and
    ``push_force`` is ignored."""
    timeout: float = math.inf
    """Simulated-time cap of the approach-and-push run, s; reaching it before the window ends
    raises :class:`~.model.SimulatedTimeout`."""

    def __post_init__(self) -> None:
        if not (np.isfinite(self.sigma) and self.sigma >= 0):
            raise ValueError(f"noise sigma = {self.sigma!r} is invalid; it must be >= 0 (0.2 = 20 %)")
        if not (np.isfinite(self.sensing_time) and self.sensing_time > 0):
            raise ValueError(f"sensing_time = {self.sensing_time!r} s is invalid; it must be > 0")
        if not (self.sample_rate > 0):
            raise ValueError(f"sample_rate = {self.sample_rate!r} Hz is invalid; it must be > 0")


@dataclass(frozen=True)
class EstimatorConfig:
    """The fit of eq. 7.

    Relations: the start ranges are (lower, upper) with lower <= upper; the hinge-height table is
    (min, max, step) with min < max and 0 < step <= max - min.
    """

    relations: ClassVar[tuple[Relation, ...]] = (
        ordered("k_start_range", why="initial guesses are drawn uniformly from it"),
        ordered("hb_start_range_mm", why="initial guesses are drawn uniformly from it"),
        relation(("hb_grid_mm",), lambda g: g[0] < g[1] and 0 < g[2] <= g[1] - g[0],
                 "{0} must be (min, max, step) with min < max and 0 < step <= max - min",
                 "the hinge-height table is min, min + step, ... max"),
    )

    n_unknowns: int = param(3, choices=tuple(VARIANTS), doc="4: (k1, k2, hb1, hb2)")
    """4: (k1, k2, hb1, hb2); 3: (k1, k2, hb1 = hb2); 2: (k1, k2) with hb1 = hb2 = known_hb."""
    n_starts: int = param(100, ge=1, doc="Random initial guesses (paper: 100)")
    """Random initial guesses (paper: 100)."""
    k_start_range: tuple[float, float] = param((0.0, 5.0), length=2, ge=0, unit="N m/rad",
                                               doc="Range of initial stiffness guesses, N m/rad (paper: [0, 5])")
    """Range of initial stiffness guesses, N m/rad (paper: [0, 5])."""
    hb_start_range_mm: tuple[float, float] = param((0.0, 5.0), length=2, unit="mm",
                                                   doc="Range of initial hinge-height guesses, mm (paper: [0, 5])")
    """Range of initial hinge-height guesses, mm (paper: [0, 5])."""
    hb_grid_mm: tuple[float, float, float] = param((-20.0, 40.0, 0.1), length=3, unit="mm",
                                                   doc="(min, max, step) of the hinge-height table, mm")
    """(min, max, step) of the hinge-height table, mm; estimates are confined to [min, max]."""
    known_hb: float = param(0.0, unit="m", doc="Hinge height assumed known in the 2-unknown variant, m")
    """Hinge height assumed known in the 2-unknown variant, m."""
    max_iter_per_dim: int = param(200, ge=1, doc="Iteration cap per unknown (fminsearch default MaxIter = 200 n)")
    """Iteration cap per unknown (fminsearch default MaxIter = 200 n)."""
    xatol: float = param(1e-4, gt=0, doc="Simplex size tolerance (fminsearch TolX)")
    """Simplex size tolerance (fminsearch TolX)."""
    fatol: float = param(1e-4, gt=0, doc="Objective spread tolerance, N (fminsearch TolFun)")
    """Objective spread tolerance, N (fminsearch TolFun)."""

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass
class SensingData:
    """What the robot has when it starts estimating."""

    t: np.ndarray
    """Sample times, s, shape (N,)."""
    q: np.ndarray
    """Robot poses at the samples (x, alpha, beta), shape (N, 3)."""
    force_clean: np.ndarray
    """Noise-free total beam force, N, shape (N, 3)."""
    force: np.ndarray
    """Sensed (noisy) force, N, shape (N, 3)."""
    t_contact: float
    """Time of first contact, s."""
    state_end: tuple[np.ndarray, np.ndarray]
    """Pose and velocity at the end of the window (x, alpha, beta) and their rates."""
    contact_duration: float
    """How long contact lasted within the simulated span, s (lower bound)."""
    log: "SimLog | None" = None
    """The full per-step simulation of the approach and push (None when not kept)."""


def sense(cfg: ModelConfig, sensing: SensingConfig, rng: np.random.Generator,
          clean: "SensingData | None" = None) -> SensingData:
    """Simulate the approach and open-loop push, and sample the force sensor (eq. 6).

    Args:
        cfg: model with the true beams.
        sensing: sensing settings.
        rng: the only source of randomness (noise draws).
        clean: a previous noise-free record of the same (cfg, sensing) to reuse; only the noise
            is redrawn.

    Returns:
        The :class:`SensingData`.

    Raises:
        ValueError: if the robot never touches the beams, or if contact ends before T_s.
    """
    if clean is None:
        clean = sense_clean(cfg, sensing)
    f = clean.force_clean
    shape = f.shape if sensing.per_axis_noise else (f.shape[0], 1)
    z = rng.normal(0.0, sensing.sigma, size=shape) if sensing.sigma > 0 else np.zeros(shape)
    return SensingData(clean.t, clean.q, f, f * (1.0 + z), clean.t_contact, clean.state_end,
                       clean.contact_duration, clean.log)


def sense_clean(cfg: ModelConfig, sensing: SensingConfig) -> SensingData:
    """Noise-free part of :func:`sense` (deterministic in ``cfg`` and ``sensing``)."""
    r = cfg.robot
    t_sample = 1.0 / sensing.sample_rate
    n_samples = int(round(sensing.sensing_time * sensing.sample_rate))
    if n_samples < 1:
        raise ValueError(f"sensing_time = {sensing.sensing_time} s holds no sample at "
                         f"{sensing.sample_rate} Hz; use at least {t_sample} s")
    state = {"contact": False}

    def ctrl(t, q, v, contacts):
        if contacts[0].in_contact or contacts[1].in_contact:
            state["contact"] = True
        return (sensing.push_force if state["contact"] else 0.0, 0.0, 0.0)

    def stop(t, q, v, tc):
        if math.isnan(tc):
            return t >= sensing.max_approach_time
        return t >= tc + sensing.sensing_time + sensing.lookahead - 1e-12

    v_init = r.v0 if sensing.drive_speed is None else sensing.drive_speed
    span = sensing.max_approach_time + sensing.sensing_time + sensing.lookahead + 0.1
    log = simulate(cfg, (sensing.x_start, 0.0, 0.0), (v_init, 0.0, 0.0), min(span, sensing.timeout), ctrl,
                   x_exit=None, stop=stop, fixed_x_speed=sensing.drive_speed)
    if sensing.timeout < span and log.outcome == "timeout" and (
            math.isnan(log.t_contact) or log.t[-1] < log.t_contact + sensing.sensing_time - 1e-9):
        raise SimulatedTimeout(f"sensing reached the simulated-time cap of {sensing.timeout} s "
                               f"before the {sensing.sensing_time} s window ended")
    if math.isnan(log.t_contact):
        raise ValueError(
            "the robot never touched the beams within "
            f"{sensing.max_approach_time} s (start x = {sensing.x_start} m, gap = {cfg.layout.gap} m, "
            f"robot half-width b = {r.b} m): nothing can be estimated; start behind the beams "
            "(x < 0) with a gap narrower than the robot")
    touching = np.abs(log.theta).sum(1) > 0
    last = log.t[np.nonzero(touching)[0][-1]]
    duration = last - log.t_contact
    t_end = log.t_contact + sensing.sensing_time
    # contact may be intermittent (the undamped robot bounces); it has *ended* when the robot
    # does not touch the beams again at or after the end of the window (within the lookahead)
    if log.outcome == "fell" and log.t[-1] < t_end + 1e-9 or last < t_end - 1e-9:
        raise ValueError(
            f"sensing_time = {sensing.sensing_time} s is longer than the contact lasts "
            f"({duration:.3f} s after first contact, outcome {log.outcome!r}); "
            f"use a window <= {duration:.3f} s or a propulsion that keeps the robot on the beams")
    i_end = int(np.searchsorted(log.t, t_end - 1e-9))
    log = SimLog(log.t[:i_end + 1], log.q[:i_end + 1], log.v[:i_end + 1], log.u[:i_end + 1],
                 log.force[:i_end + 1], log.theta[:i_end + 1], log.t_contact, "stopped")
    t_req = log.t_contact + np.arange(1, n_samples + 1) * t_sample
    idx = np.searchsorted(log.t, t_req - 1e-9)
    return SensingData(log.t[idx], log.q[idx], log.force[idx], log.force[idx].copy(), log.t_contact,
                       (log.q[-1], log.v[-1]), float(duration), log)


# --------------------------------------------------------------------------- tabulated model

@dataclass
class ForceTable:
    """Per-unit-parameter beam forces at the sample poses, tabulated over hinge height.

    ``basis[j][name]`` has shape (n_h, N, 3): force on the robot (N) of beam j per unit of the
    named linear parameter (``"k"``: per N m/rad; ``"tau0"``: per N m; ``"const"``: the
    parameter-free beam-weight part).
    """

    h_mm: np.ndarray
    basis: list[dict[str, np.ndarray]]

    def interp(self, j: int, name: str, h_mm: np.ndarray) -> np.ndarray:
        """Linear interpolation in hinge height; ``h_mm`` shape (B,) -> (B, N, 3)."""
        h0, dh = self.h_mm[0], self.h_mm[1] - self.h_mm[0]
        pos = np.clip((np.asarray(h_mm, float) - h0) / dh, 0.0, len(self.h_mm) - 1.000001)
        i0 = pos.astype(int)
        f = (pos - i0)[:, None, None]
        tab = self.basis[j][name]
        return tab[i0] * (1.0 - f) + tab[i0 + 1] * f


def force_table(q: np.ndarray, cfg: ModelConfig, h_mm: np.ndarray, beam_mass: float = 0.0) -> ForceTable:
    """Tabulate the per-unit-parameter forces of both beams at poses ``q`` (N, 3) over ``h_mm``."""
    r, lay = cfg.robot, cfg.layout
    h = np.asarray(h_mm, float)[:, None] * 1e-3
    basis = []
    for j in range(2):
        th, _, n, lever, touch = deflection_vec(q[None, :, 0], q[None, :, 1], q[None, :, 2], h, j, r, lay,
                                                return_contact=True)
        inv = np.where(touch, 1.0 / np.maximum(lever, cfg.min_lever), 0.0)
        dirn = -n  # force on the robot points into it
        weight = -0.5 * (lay.length - h) * beam_mass * cfg.gravity * np.sin(th)
        basis.append({
            "k": (th * inv)[..., None] * dirn,
            "tau0": inv[..., None] * dirn,
            "const": (weight * inv)[..., None] * dirn,
        })
    return ForceTable(np.asarray(h_mm, float), basis)


# --------------------------------------------------------------------------- batched Nelder-Mead

def nelder_mead_batch(fun, x0: np.ndarray, max_iter: int, xatol: float = 1e-4, fatol: float = 1e-4):
    """Run Nelder-Mead from every row of ``x0`` at once.

    Args:
        fun: maps (B, n) points to (B,) objective values.
        x0: starts, shape (B, n).
        max_iter: iteration cap.
        xatol, fatol: stop a run once its simplex spans <= xatol in every coordinate and its
            values span <= fatol (the fminsearch criterion).

    Returns:
        (x_best (B, n), f_best (B,), iterations (B,)).
    """
    x0 = np.asarray(x0, float)
    B, n = x0.shape
    simp = np.repeat(x0[:, None, :], n + 1, axis=1)
    for j in range(n):
        simp[:, j + 1, j] = np.where(x0[:, j] != 0, 1.05 * x0[:, j], 0.00025)
    fs = fun(simp.reshape(-1, n)).reshape(B, n + 1)
    iters = np.zeros(B, int)
    rows = np.arange(B)
    for _ in range(max_iter):
        order = np.argsort(fs, axis=1, kind="stable")
        simp = np.take_along_axis(simp, order[:, :, None], axis=1)
        fs = np.take_along_axis(fs, order, axis=1)
        done = (np.abs(simp[:, 1:] - simp[:, :1]).max(axis=(1, 2)) <= xatol) & \
               (np.abs(fs[:, 1:] - fs[:, :1]).max(axis=1) <= fatol)
        act = rows[~done]
        if act.size == 0:
            break
        iters[act] += 1
        S, F = simp[act], fs[act]
        cen = S[:, :-1].mean(axis=1)
        worst, fw, fb, fsec = S[:, -1], F[:, -1], F[:, 0], F[:, -2]
        xr = 2 * cen - worst
        xe = 3 * cen - 2 * worst
        xoc = 1.5 * cen - 0.5 * worst
        xic = 0.5 * cen + 0.5 * worst
        fr, fe, foc, fic = (fun(v) for v in (xr, xe, xoc, xic))
        newx, newf = worst.copy(), fw.copy()
        shrink = np.zeros(act.size, bool)
        c1 = fr < fb
        use_e = c1 & (fe < fr)
        newx[use_e], newf[use_e] = xe[use_e], fe[use_e]
        use_r = (c1 & ~use_e) | ((fr >= fb) & (fr < fsec))
        newx[use_r], newf[use_r] = xr[use_r], fr[use_r]
        c3 = (fr >= fsec) & (fr < fw)
        ok = c3 & (foc <= fr)
        newx[ok], newf[ok] = xoc[ok], foc[ok]
        shrink |= c3 & ~ok
        c4 = fr >= fw
        ok = c4 & (fic < fw)
        newx[ok], newf[ok] = xic[ok], fic[ok]
        shrink |= c4 & ~ok
        S[:, -1], F[:, -1] = newx, newf
        if shrink.any():
            Ss = S[shrink]
            Ss[:, 1:] = Ss[:, :1] + 0.5 * (Ss[:, 1:] - Ss[:, :1])
            F[shrink, 1:] = fun(Ss[:, 1:].reshape(-1, n)).reshape(-1, n)
            S[shrink] = Ss
        simp[act], fs[act] = S, F
    best = np.argmin(fs, axis=1)
    return simp[rows, best], fs[rows, best], iters


# --------------------------------------------------------------------------- the estimator

@dataclass
class Estimate:
    """Result of one fit."""

    params: dict[str, float]
    """Fitted values: ``k1, k2`` (N m/rad) and ``hb1, hb2`` (m), always all four."""
    cost: float
    """Eq. 7 at the optimum, N."""
    n_samples: int
    """Force samples used."""
    starts_near_best: int
    """How many of the random starts ended within 1e-6 relative of the best cost."""
    extra: dict[str, float] = field(default_factory=dict)


def _full_params(p: np.ndarray, n_unknowns: int, known_hb_mm: float):
    """Map the variant's unknowns (B, n) to (k1, k2, h1_mm, h2_mm) arrays."""
    if n_unknowns == 4:
        return p[:, 0], p[:, 1], p[:, 2], p[:, 3]
    if n_unknowns == 3:
        return p[:, 0], p[:, 1], p[:, 2], p[:, 2]
    h = np.full(p.shape[0], known_hb_mm)
    return p[:, 0], p[:, 1], h, h


def estimate(data: SensingData, cfg: ModelConfig, est: EstimatorConfig, rng: np.random.Generator) -> Estimate:
    """Fit the beam parameters to the sensed forces by minimising eq. 7.

    Args:
        data: sensing record (poses and noisy forces).
        cfg: model geometry (its ``beams`` are *not* used: they are the unknowns).
        est: estimator settings.
        rng: draws the random initial guesses.

    Returns:
        The :class:`Estimate` with the best of ``est.n_starts`` Nelder-Mead runs.
    """
    lo, hi, step = est.hb_grid_mm
    h_mm = np.arange(lo, hi + 0.5 * step, step)
    table = force_table(data.q, cfg, h_mm)
    n = est.n_unknowns
    known = est.known_hb * 1e3
    target = data.force

    def fun(p):
        k1, k2, h1, h2 = _full_params(p, n, known)
        if n == 2:
            g1 = np.broadcast_to(table.interp(0, "k", h1[:1]), (p.shape[0],) + target.shape)
            g2 = np.broadcast_to(table.interp(1, "k", h2[:1]), (p.shape[0],) + target.shape)
        else:
            g1, g2 = table.interp(0, "k", h1), table.interp(1, "k", h2)
        model = k1[:, None, None] * g1 + k2[:, None, None] * g2
        return np.linalg.norm(model - target[None], axis=-1).sum(axis=-1)

    starts = np.empty((est.n_starts, n))
    starts[:, :2] = rng.uniform(*est.k_start_range, size=(est.n_starts, 2))
    if n > 2:
        starts[:, 2:] = rng.uniform(*est.hb_start_range_mm, size=(est.n_starts, n - 2))
    xb, fb, _ = nelder_mead_batch(fun, starts, est.max_iter_per_dim * n, est.xatol, est.fatol)
    i = int(np.argmin(fb))
    k1, k2, h1, h2 = (float(v[0]) for v in _full_params(xb[i:i + 1], n, known))
    h1, h2 = float(np.clip(h1, lo, hi)), float(np.clip(h2, lo, hi))
    near = int(np.sum(fb <= fb[i] * (1 + 1e-6) + 1e-12))
    return Estimate({"k1": k1, "k2": k2, "hb1": h1 * 1e-3, "hb2": h2 * 1e-3}, float(fb[i]),
                    int(target.shape[0]), near)


def relative_errors(est: dict[str, float], truth: tuple[Beam, Beam], h_range: float = 5e-3) -> dict[str, float]:
    """Paper's relative errors: |k^-k|/k and |h^-h| / 5 mm (Sec. III-B-ii)."""
    return {
        "e_k1": abs(est["k1"] - truth[0].k) / truth[0].k,
        "e_k2": abs(est["k2"] - truth[1].k) / truth[1].k,
        "e_hb1": abs(est["hb1"] - truth[0].h_b) / h_range,
        "e_hb2": abs(est["hb2"] - truth[1].h_b) / h_range,
    }


def estimate_preload(data: SensingData, cfg: ModelConfig, h_b: float, beam_mass: float,
                     n_starts: int, rng: np.random.Generator, k_range=(0.0, 5.0), tau_range=(0.0, 0.5),
                     max_iter: int = 400) -> Estimate:
    """Physical-experiment variant (Sec. IV, eq. 12): fit a shared (k, tau0) with h_b and M_B known.

    Returns:
        An :class:`Estimate` whose params hold ``k`` (N m/rad) and ``tau0`` (N m).
    """
    table = force_table(data.q, cfg, np.array([h_b * 1e3, h_b * 1e3 + 1e-3]), beam_mass=beam_mass)
    gk = table.basis[0]["k"][0] + table.basis[1]["k"][0]
    gt = table.basis[0]["tau0"][0] + table.basis[1]["tau0"][0]
    gc = table.basis[0]["const"][0] + table.basis[1]["const"][0]
    target = data.force

    def fun(p):
        model = p[:, 0, None, None] * gk + p[:, 1, None, None] * gt + gc
        return np.linalg.norm(model - target[None], axis=-1).sum(axis=-1)

    starts = np.column_stack([rng.uniform(*k_range, n_starts), rng.uniform(*tau_range, n_starts)])
    xb, fb, _ = nelder_mead_batch(fun, starts, max_iter)
    i = int(np.argmin(fb))
    near = int(np.sum(fb <= fb[i] * (1 + 1e-6) + 1e-12))
    return Estimate({"k": float(xb[i, 0]), "tau0": float(xb[i, 1])}, float(fb[i]), int(target.shape[0]), near)
