"""Rigid wheel on deformable soil: Bekker pressure-sinkage, Wong-Reece stress distribution,
Janosi-Hanamoto shear, Ishigami-style lateral shear (docs/soil.md has the equations).

Conventions (all SI):

- Contact angle ``theta`` is measured at the axle from the downward vertical, positive towards
  the direction of travel. The wheel touches soil on ``[theta_r, theta_1]`` with entry angle
  ``theta_1 = arccos(1 - z/r)`` and exit (rear) angle ``theta_r = -c_exit * theta_1``.
- Slip ``s`` (dimensionless), documented range ``(-1, 1]``:
  driving (``v <= r*omega``): ``s = 1 - v/(r*omega)`` in ``[0, 1]`` (1 = spinning in place);
  skid (``v > r*omega``): ``s = r*omega/v - 1`` in ``(-1, 0)`` (-1 = locked wheel, excluded).
  Internally everything uses the velocity ratio ``kappa = v/(r*omega)``: ``1 - s`` when
  driving, ``1/(1 + s)`` when skidding, so the shear displacement is
  ``j(theta) = r[(theta_1 - theta) - kappa (sin theta_1 - sin theta)]`` (Wong-Reece's
  ``(1 - s)`` form for ``s >= 0``).
- Lateral: the slip angle enters through the lateral slip ratio ``q = v_y/(r*omega)`` (=
  ``kappa * tan(beta)``); lateral displacement ``j_y = q r (theta_1 - theta)`` (Ishigami et al.
  2007, eq. for j_y with ``(1 - s) tan beta`` generalised to skid through kappa).
- Outputs per wheel: ``W`` normal (vertical) load the soil carries (N), ``DP`` drawbar pull
  along travel (N; negative = rolling resistance), ``T`` torque the soil exerts against the
  wheel's rotation (N m; the driving torque needed in steady state), ``Fy`` lateral force
  magnitude (N; it opposes the lateral velocity). W and DP act at the axle; T about it.

Functions are pure and vectorised: inputs broadcast against each other.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

N_NODES = 24  # Gauss-Legendre nodes per sub-interval ([theta_r, theta_m] and [theta_m, theta_1])
_GL_X, _GL_W = np.polynomial.legendre.leggauss(N_NODES)
SLIP_MIN = -0.95  # most negative slip the table and the coupling use (kappa = 20)
SLIP_MAX = 1.0


def _check(name: str, value: float, ok: bool, valid: str) -> None:
    if not (ok and np.isfinite(value)):
        raise ValueError(f"{name}={value!r} is invalid; valid range: {valid}")


@dataclass(frozen=True)
class SoilParams:
    """Bekker / Wong-Reece / Janosi-Hanamoto soil parameters.

    Attributes:
        name: label used in reports.
        n: sinkage exponent (-), in (0, 3) (Bekker's closed form needs n < 3).
        k_c: cohesive modulus of deformation (N/m^(n+1)), >= 0.
        k_phi: frictional modulus of deformation (N/m^(n+2)), > 0.
        c: cohesion (Pa), >= 0.
        phi_deg: internal friction angle (deg), in (0, 90).
        K: longitudinal shear deformation modulus (m), > 0.
        K_y: lateral shear deformation modulus (m), > 0; None = same as K.
        a0: theta_m = (a0 + a1*s) theta_1, constant part (-), in [0, 1).
        a1: slip part of the same (-), >= 0 with a0 + a1 <= 1 (theta_m is clipped at 0 in skid).
        c_exit: rear (exit) angle ratio, theta_r = -c_exit * theta_1 (-), in [0, 1]; 0 = the
            classical Wong-Reece no-rebound assumption.
        source: citation / provenance string.
    """

    name: str = "soil"
    n: float = 1.0
    k_c: float = 1.4e3
    k_phi: float = 700e3
    c: float = 500.0
    phi_deg: float = 30.0
    K: float = 0.015
    K_y: float | None = None
    a0: float = 0.4
    a1: float = 0.15
    c_exit: float = 0.0
    source: str = ""

    def __post_init__(self) -> None:
        _check("n", self.n, 0 < self.n < 3, "0 < n < 3")
        _check("k_c", self.k_c, self.k_c >= 0, "k_c >= 0 N/m^(n+1)")
        _check("k_phi", self.k_phi, self.k_phi > 0, "k_phi > 0 N/m^(n+2)")
        _check("c", self.c, self.c >= 0, "c >= 0 Pa")
        _check("phi_deg", self.phi_deg, 0 < self.phi_deg < 90, "0 < phi_deg < 90 deg")
        _check("K", self.K, self.K > 0, "K > 0 m")
        if self.K_y is not None:
            _check("K_y", self.K_y, self.K_y > 0, "K_y > 0 m")
        _check("a0", self.a0, 0 <= self.a0 < 1, "0 <= a0 < 1")
        _check("a1", self.a1, self.a1 >= 0 and self.a0 + self.a1 <= 1, "a1 >= 0 and a0 + a1 <= 1")
        _check("c_exit", self.c_exit, 0 <= self.c_exit <= 1, "0 <= c_exit <= 1")

    @property
    def tan_phi(self) -> float:
        return float(np.tan(np.radians(self.phi_deg)))

    @property
    def Ky(self) -> float:
        return self.K if self.K_y is None else self.K_y


@dataclass(frozen=True)
class WheelParams:
    """A rigid, smooth cylindrical wheel (no grousers).

    Attributes:
        radius: (m), > 0.
        width: contact width b (m), > 0.
        mass: (kg), > 0; used by the MuJoCo testbed.
    """

    radius: float = 0.15
    width: float = 0.12
    mass: float = 2.0

    def __post_init__(self) -> None:
        _check("radius", self.radius, self.radius > 0, "radius > 0 m")
        _check("width", self.width, self.width > 0, "width > 0 m")
        _check("mass", self.mass, self.mass > 0, "mass > 0 kg")


def kappa_from_slip(s):
    """Velocity ratio v/(r*omega) from slip (see module docstring). s in (-1, 1]."""
    s = np.asarray(s, dtype=float)
    if np.any(s > 1) or np.any(s <= -1) or not np.all(np.isfinite(s)):
        raise ValueError(f"slip={s!r} is invalid; valid range: -1 < s <= 1")
    return np.where(s >= 0, 1.0 - s, 1.0 / (1.0 + np.minimum(s, 0.0)))


def slip_from_speeds(v, r_omega, v_eps: float = 1e-3):
    """Slip from hub speed v and rim speed r*omega (both m/s, same sign convention).

    ``s = (r omega - v) / max(|r omega|, |v|, v_eps)``: equals ``1 - v/(r omega)`` when driving
    and ``r omega/v - 1`` when skidding; clipped to [SLIP_MIN, 1].
    """
    v = np.asarray(v, dtype=float)
    rw = np.asarray(r_omega, dtype=float)
    den = np.maximum(np.maximum(np.abs(rw), np.abs(v)), v_eps)
    return np.clip((rw - v) / den, SLIP_MIN, SLIP_MAX)


def entry_angle(z, radius: float):
    """theta_1 = arccos(1 - z/r) (rad) for sinkage z (m), clipped to [0, pi/2]."""
    return np.arccos(np.clip(1.0 - np.asarray(z, dtype=float) / radius, 0.0, 1.0))


def _stresses(theta, th1, thm, thr, s_kappa, q, soil: SoilParams, wheel: WheelParams):
    """Normal, longitudinal shear and lateral shear stress (Pa) at angles theta (..., N)."""
    r, b = wheel.radius, wheel.width
    k = (soil.k_c / b + soil.k_phi) * r**soil.n
    front = theta >= thm
    denom = np.where(thm - thr > 1e-12, thm - thr, 1.0)
    th_eq = np.where(front, theta, th1 - (theta - thr) / denom * (th1 - thm))
    sigma = k * np.maximum(np.cos(th_eq) - np.cos(th1), 0.0) ** soil.n
    j = r * ((th1 - theta) - s_kappa * (np.sin(th1) - np.sin(theta)))
    tau_max = soil.c + sigma * soil.tan_phi
    tau = np.sign(j) * tau_max * (1.0 - np.exp(-np.abs(j) / soil.K))
    jy = q * r * (th1 - theta)
    tau_y = tau_max * (1.0 - np.exp(-np.abs(jy) / soil.Ky))
    return sigma, tau, tau_y


def wheel_forces(z, s, soil: SoilParams, wheel: WheelParams, q=0.0):
    """Integrate the stresses over the contact arc.

    Args:
        z: sinkage (m), >= 0, array-like.
        s: slip (-), in (-1, 1], broadcast with z.
        q: lateral slip ratio v_y/(r omega) (-), >= 0 (magnitude), broadcast.

    Returns:
        dict of arrays (broadcast shape): W (N), DP (N), T (N m), Fy (N, magnitude),
        theta1, theta_m, theta_r (rad).
    """
    z, s, q = np.broadcast_arrays(np.asarray(z, float), np.asarray(s, float), np.abs(np.asarray(q, float)))
    kap = kappa_from_slip(s)
    th1 = entry_angle(z, wheel.radius)
    thm = np.clip(soil.a0 + soil.a1 * s, 0.0, 1.0) * th1
    thr = -soil.c_exit * th1
    ex = (Ellipsis, None)
    # two Gauss-Legendre panels: [thr, thm] and [thm, th1] (kink of sigma at thm)
    h1, m1 = (thm - thr) / 2, (thm + thr) / 2
    h2, m2 = (th1 - thm) / 2, (th1 + thm) / 2
    theta = np.concatenate([m1[ex] + h1[ex] * _GL_X, m2[ex] + h2[ex] * _GL_X], axis=-1)
    wts = np.concatenate([h1[ex] * _GL_W, h2[ex] * _GL_W], axis=-1)
    sig, tau, tau_y = _stresses(theta, th1[ex], thm[ex], thr[ex], kap[ex], q[ex], soil, wheel)
    r, b = wheel.radius, wheel.width
    ct, st = np.cos(theta), np.sin(theta)
    W = r * b * np.sum(wts * (sig * ct + tau * st), axis=-1)
    DP = r * b * np.sum(wts * (tau * ct - sig * st), axis=-1)
    T = r * r * b * np.sum(wts * tau, axis=-1)
    Fy = r * b * np.sum(wts * tau_y, axis=-1)
    return {"W": W, "DP": DP, "T": T, "Fy": Fy, "theta1": th1, "theta_m": thm, "theta_r": thr}


def max_sinkage(wheel: WheelParams) -> float:
    """Largest sinkage the model accepts: half the radius (theta_1 = 60 deg) (m)."""
    return 0.5 * wheel.radius


def solve_sinkage(load, s, soil: SoilParams, wheel: WheelParams, iters: int = 60):
    """Sinkage z (m) with W(z, s) = load, by vectorised bisection on [0, max_sinkage].

    Args:
        load: vertical wheel load (N), > 0, array-like.
        s: slip, broadcast with load.

    Raises:
        ValueError: a load is not positive, or exceeds W at max_sinkage (the wheel would sink
            beyond r/2, outside the model's validity).
    """
    load, s = np.broadcast_arrays(np.asarray(load, float), np.asarray(s, float))
    if np.any(~(load > 0)):
        raise ValueError(f"load={load!r} is invalid; valid range: load > 0 N")
    zmax = max_sinkage(wheel)
    wmax = wheel_forces(np.full(load.shape, zmax), s, soil, wheel)["W"]
    if np.any(load > wmax):
        raise ValueError(f"load={load!r} sinks the wheel beyond {zmax} m (r/2) on {soil.name}; "
                         f"valid range: load <= {np.min(wmax):.4g} N")
    lo, hi = np.zeros(load.shape), np.full(load.shape, zmax)
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        big = wheel_forces(mid, s, soil, wheel)["W"] > load
        hi = np.where(big, mid, hi)
        lo = np.where(big, lo, mid)
    return 0.5 * (lo + hi)


def bekker_sinkage(load, soil: SoilParams, wheel: WheelParams):
    """Bekker's closed-form rigid-wheel sinkage (m) for small sinkage (Wong, Theory of Ground
    Vehicles, ch. 6): z0 = (3W / ((3-n)(k_c + b k_phi) sqrt(D)))^(2/(2n+1)), D = 2r.

    Note the factor b: ``(k_c + b k_phi) = b (k_c/b + k_phi)``. Writing ``(k_c/b + k_phi)``
    without the b (as issue 12 does) is dimensionally wrong and sinks ``b^(-2/(2n+1))`` times
    deeper (4.1x for b = 0.12 m, n = 1).
    """
    n, b, D = soil.n, wheel.width, 2 * wheel.radius
    k = soil.k_c + b * soil.k_phi
    return (3 * np.asarray(load, float) / ((3 - n) * k * np.sqrt(D))) ** (2 / (2 * n + 1))


def steady_state(load, s, soil: SoilParams, wheel: WheelParams, omega: float = 1.0):
    """Analytic steady state of a wheel carrying ``load`` at slip ``s`` and spin ``omega``.

    Returns a dict of arrays: sinkage_m, DP_N, torque_Nm, DP_coeff (DP/W), efficiency
    ((DP v)/(T omega), v = kappa r omega; nan where T <= 0), v_mps.
    """
    z = solve_sinkage(load, s, soil, wheel)
    f = wheel_forces(z, s, soil, wheel)
    v = kappa_from_slip(np.broadcast_to(s, z.shape)) * wheel.radius * omega
    with np.errstate(divide="ignore", invalid="ignore"):
        eff = np.where(f["T"] > 0, f["DP"] * v / (f["T"] * omega), np.nan)
    return {"sinkage_m": z, "DP_N": f["DP"], "torque_Nm": f["T"], "DP_coeff": f["DP"] / np.asarray(load, float),
            "efficiency": eff, "v_mps": v, "W_N": f["W"]}
