"""Rigid wheel on deformable soil: Bekker or Reece pressure-sinkage with a slip-dependent
sinkage exponent, Wong-Reece stress distribution with an exit angle, Janosi-Hanamoto shear from
the combined (longitudinal + lateral) shear displacement capped by Mohr-Coulomb, and sidewall
bulldozing (docs/soil.md has the equations and docs/assumptions-soil.md the sources).

Conventions (all SI):

- Contact angle ``theta`` is measured at the axle from the downward vertical, positive towards
  the direction of travel. The wheel touches soil on ``[theta_r, theta_1]`` with entry angle
  ``theta_1 = arccos(1 - z/r)`` (sinkage z up to r) and exit angle
  ``theta_r = -(c_exit + c_exit1 s) theta_1``.
- Slip ``s`` in ``[-1, 1]``: driving (``v_x <= r omega``) ``s = 1 - v_x/(r omega)`` (1 =
  spinning in place); skid (``v_x > r omega``) ``s = r omega / v_x - 1`` (-1 = locked wheel).
- Time base: a soil element's contact time is measured with the faster of rim and hub,
  ``u = max(r omega, v_x)``. With ``A = r omega / u`` and ``B = v_x / u`` (A = 1, B = 1 - s
  driving; A = 1 + s, B = 1 in skid) the shear displacements are
  ``j_x = r [A (theta_1 - theta) - B (sin theta_1 - sin theta)]`` (Wong & Reece 1967 for driving;
  their towed/braked form for skid, finite for the locked wheel) and
  ``j_y = C r (theta_1 - theta)`` with the lateral ratio ``C = |v_y| / u`` (Ishigami et al.
  2007: ``(1 - s) tan(beta)`` when driving).
- Outputs per wheel: ``W`` vertical load the soil carries (N), ``DP`` drawbar pull along the
  heading (N; negative = resistance), ``T`` torque the soil exerts against the wheel's rotation
  (N m), ``Fy`` lateral force magnitude (N, opposing v_y; shear + bulldozing).

The integral is one compiled kernel (numba, cached on disk) used by everything: the direct
functions here, the look-up tables and the validation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from terrabench.config import ConfigError, check_fields, param

N_NODES = 24  # Gauss-Legendre nodes per sub-interval ([theta_r, theta_m] and [theta_m, theta_1])
_GL_X, _GL_W = np.polynomial.legendre.leggauss(N_NODES)
SLIP_MIN = -1.0  # locked wheel: finite with the braked-wheel displacement, no clip needed
SLIP_MAX = 1.0
FORMS = ("bekker", "reece")


@dataclass(frozen=True)
class SoilParams:
    """Soil parameters (Bekker or Reece pressure-sinkage, Wong-Reece, Janosi-Hanamoto)."""

    name: str = param("soil", doc="label used in reports")
    n: float = param(1.0, gt=0, lt=3, doc="sinkage exponent at zero slip")
    k_c: float = param(1.4e3, ge=0, unit="Bekker N/m^(n+1), Reece -", doc="cohesive modulus")
    k_phi: float = param(700e3, gt=0, unit="Bekker N/m^(n+2), Reece -", doc="frictional modulus")
    c: float = param(500.0, ge=0, unit="Pa", doc="cohesion")
    phi_deg: float = param(30.0, gt=0, lt=90, unit="deg", doc="internal friction angle")
    K: float = param(0.015, gt=0, unit="m", doc="longitudinal shear deformation modulus")
    K_y: float | None = param(None, gt=0, unit="m", doc="lateral shear deformation modulus (null = K)")
    a0: float = param(0.4, ge=0, lt=1, doc="theta_m = (a0 + a1 s) theta_1: constant part")
    a1: float = param(0.15, ge=-1, le=1, doc="slip part of theta_m when driving (0 <= a0 + a1 <= 1)")
    c_exit: float = param(0.0, ge=0, le=1,
                          doc="exit angle ratio at zero slip, theta_r = -(c_exit + c_exit1 s) theta_1 (0 = the "
                              "classical no-rebound assumption)")
    source: str = param("", doc="citation / provenance string")
    form: str = param("bekker", choices=FORMS,
                      doc="pressure-sinkage form: bekker, sigma = (k_c/b + k_phi) z^n (k_c in N/m^(n+1), k_phi in "
                          "N/m^(n+2)); reece, sigma = (c k_c + gamma b k_phi) (z/b)^n (k_c, k_phi dimensionless, "
                          "Reece 1965)")
    n1: float = param(0.0, ge=-1, le=2,
                      doc="slip-sinkage coefficient when driving, n(s) = n + n1 s for s >= 0 (Ding et al. 2011); n + "
                          "n1 > 0")
    n2: float = param(0.0, ge=-1, le=2,
                      doc="slip-sinkage coefficient in skid, n(s) = n + n2 |s| for s < 0 (robomechanics "
                          "3d-terramechanics); n + n2 > 0. With lateral motion the exponent is n + n1 s_drive + n2 "
                          "s_slide: s_drive = max(r omega - v_x, 0) / u (the rim outrunning the hub along the "
                          "heading), s_slide = |(max(v_x - r omega, 0), v_y)| / u (the soil sliding past a rim that "
                          "does not carry it), u = max(r omega, |v|); with v_y = 0 this is n(s) of n1 and n2")
    gamma: float = param(15.0e3, gt=0, unit="N/m^3", doc="soil specific weight (Reece form and bulldozing)")
    a1_skid: float | None = param(None, ge=-1, le=1,
                                  doc="slip part of theta_m in skid, theta_m = (a0 + a1_skid s) theta_1 for s < 0 "
                                      "(null = a1); theta_m is clipped to [theta_r, theta_1]")
    c_exit1: float = param(0.0, ge=-1, le=1, doc="slip part of the exit ratio c_exit; the ratio is clipped to [0, 1]")
    bulldoze: float = param(1.0, ge=0, le=10,
                            doc="factor on the sidewall bulldozing force (Ishigami 2007 with Hegedus' passive "
                                "pressure; 0 = off)")
    plough: float = param(1.0, ge=0, le=10,
                          doc="factor on the front-face ploughing resistance of a braked wheel (the same passive "
                              "pressure over the rut depth, mobilised by the skid -s; 0 = off)")

    def __post_init__(self) -> None:
        check_fields(self)  # the declared ranges; then the checks across fields
        for key, v in (("n1", self.n1), ("n2", self.n2)):
            if not self.n + v > 0:
                raise ConfigError(key, v, f"a number in [-1, 2] with n + {key} > 0 (n = {self.n})")
        if not 0 <= self.a0 + self.a1 <= 1:
            raise ConfigError("a1", self.a1, f"a number in [-1, 1] with 0 <= a0 + a1 <= 1 (a0 = {self.a0})")

    @property
    def tan_phi(self) -> float:
        return float(np.tan(np.radians(self.phi_deg)))

    @property
    def Ky(self) -> float:
        return self.K if self.K_y is None else self.K_y

    def exponent(self, s):
        """Sinkage exponent n(s) at slip s (-)."""
        s = np.asarray(s, float)
        return np.where(s >= 0, self.n + self.n1 * s, self.n - self.n2 * s)

    def modulus(self, width: float) -> tuple[float, float]:
        """(k, L) with ``sigma = k (z/L)^n`` for a wheel of this width (Pa, m)."""
        if self.form == "bekker":
            return self.k_c / width + self.k_phi, 1.0
        return self.c * self.k_c + self.gamma * width * self.k_phi, width

    def to_reece(self, width: float) -> "SoilParams":
        """The Reece-form soil with the same pressure at slip 0 for this width (exact at n(0)).

        ``k_c' = k_c b^(n-1) / c`` (needs c > 0), ``k_phi' = k_phi b^(n-1) / gamma``."""
        if self.form == "reece":
            return self
        if self.c <= 0 and self.k_c > 0:
            raise ValueError(f"c={self.c!r} is invalid for the Reece form with k_c={self.k_c}; valid range: c > 0 Pa")
        f = width ** (self.n - 1)
        from dataclasses import replace

        return replace(self, form="reece", k_c=self.k_c * f / self.c if self.c > 0 else 0.0,
                       k_phi=self.k_phi * f / self.gamma)

    def to_bekker(self, width: float) -> "SoilParams":
        """The Bekker-form soil with the same pressure at slip 0 for this width:
        ``k_c = c k_c' b^(1-n)``, ``k_phi = gamma k_phi' b^(1-n)``."""
        if self.form == "bekker":
            return self
        from dataclasses import replace

        f = width ** (1 - self.n)
        return replace(self, form="bekker", k_c=self.c * self.k_c * f, k_phi=self.gamma * self.k_phi * f)


@dataclass(frozen=True)
class WheelParams:
    """A rigid, smooth cylindrical wheel (no grousers)."""

    radius: float = param(0.15, gt=0, le=2.0, unit="m",
                          doc="wheel radius; <= 2 m: Bekker-Wong pressure-sinkage was measured with "
                              "plates and wheels well under a metre, beyond that it is extrapolation")
    width: float = param(0.12, gt=0, unit="m", doc="contact width b")
    mass: float = param(2.0, gt=0, unit="kg", doc="wheel mass (used by the MuJoCo testbed)")

    def __post_init__(self) -> None:
        check_fields(self)


# ---------------------------------------------------------------------------------------------
# the compiled kernel

_P_LEN = 20


def pack(soil: SoilParams, wheel: WheelParams) -> np.ndarray:
    """The soil-wheel pair as the float array the kernel reads."""
    k, L = soil.modulus(wheel.width)
    phi = math.radians(soil.phi_deg)
    xc = math.pi / 4 - phi / 2  # Hegedus' failure-plane angle
    d1 = 1 / math.tan(xc) + math.tan(xc + phi)
    d2 = 1 / math.tan(xc) + (1 / math.tan(xc)) ** 2 / (1 / math.tan(phi))
    a1s = soil.a1 if soil.a1_skid is None else soil.a1_skid
    return np.array([wheel.radius, wheel.width, k, L, soil.n, soil.n1, soil.n2, soil.c, soil.tan_phi,
                     soil.K, soil.Ky, soil.a0, soil.a1, a1s, soil.c_exit, soil.c_exit1, soil.gamma,
                     soil.bulldoze * d1, d2, soil.plough * d1])


@numba.njit(cache=True, fastmath=False)
def _angles(z, s, P):
    r = P[0]
    cz = 1.0 - z / r
    if cz < 0.0:
        cz = 0.0
    elif cz > 1.0:
        cz = 1.0
    th1 = math.acos(cz)
    cr = P[14] + P[15] * s
    cr = min(max(cr, 0.0), 1.0)
    thr = -cr * th1
    am = P[11] + (P[12] if s >= 0 else P[13]) * s
    thm = am * th1
    thm = min(max(thm, thr), th1)
    return th1, thm, thr


@numba.njit(cache=True)
def _slip_total(s, C):
    """Slip of the rim speed against the hub's total speed (longitudinal and lateral)."""
    if C <= 0.0:
        return s
    A = 1.0 if s >= 0 else 1.0 + s
    B = 1.0 - s if s >= 0 else 1.0
    vh = math.sqrt(B * B + C * C)
    return (A - vh) / max(A, vh)


@numba.njit(cache=True)
def _slip_total_many(s, C, out):
    for i in range(s.shape[0]):
        out[i] = _slip_total(s[i], C[i])


def slip_total(s, q):
    """Slip of the rim against the hub's total speed, ``(r omega - |v|) / max(r omega, |v|)``,
    from the longitudinal slip s and the lateral ratio q = C (equals s at C = 0). The slip-dependent
    terms (sinkage exponent, stress and exit angles) use it: the CMU data define slip this way."""
    s, q = np.broadcast_arrays(np.asarray(s, float), np.abs(np.asarray(q, float)))
    out = np.empty(s.size)
    _slip_total_many(np.ascontiguousarray(s.ravel()), np.ascontiguousarray(np.minimum(q.ravel(), 1e9)), out)
    return out.reshape(s.shape)


@numba.njit(cache=True, fastmath=False)
def _point(z, s, C, P, gx, gw):
    """W, DP, T, Fy of one wheel state (z m, s -, C -)."""
    r, b, k, L = P[0], P[1], P[2], P[3]
    if z <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    A = 1.0 if s >= 0 else 1.0 + s
    B = 1.0 - s if s >= 0 else 1.0
    se = _slip_total(s, C)
    # exponent from the two ways a wheel excavates: the rim outrunning the hub along the heading
    # (driving part) and the soil sliding past a rim that does not carry it (skid and sideways)
    vh = max(A, math.sqrt(B * B + C * C))
    s_drive = max(A - B, 0.0) / vh
    s_slide = math.sqrt(max(B - A, 0.0) ** 2 + C * C) / vh
    n = P[4] + P[5] * s_drive + P[6] * s_slide
    c, tphi, K, Ky, gam, bd1, d2 = P[7], P[8], P[9], P[10], P[16], P[17], P[18]
    th1, thm, thr = _angles(z, se, P)
    c1, s1 = math.cos(th1), math.sin(th1)
    W = 0.0
    DP = 0.0
    T = 0.0
    Fy = 0.0
    Fb = 0.0
    ng = gx.shape[0]
    for panel in range(2):
        lo, hi = (thr, thm) if panel == 0 else (thm, th1)
        h = 0.5 * (hi - lo)
        m = 0.5 * (hi + lo)
        if h <= 0.0:
            continue
        for i in range(ng):
            th = m + h * gx[i]
            w = h * gw[i]
            if panel == 0 and thm - thr > 1e-12:
                teq = th1 - (th - thr) / (thm - thr) * (th1 - thm)
            else:
                teq = th
            ct, st = math.cos(th), math.sin(th)
            depth = r * (math.cos(teq) - c1)
            sig = k * (depth / L) ** n if depth > 0.0 else 0.0
            tmax = c + sig * tphi
            jx = r * (A * (th1 - th) - B * (s1 - st))
            jy = C * r * (th1 - th)
            jm = math.sqrt(jx * jx + jy * jy)
            tx = 0.0
            ty = 0.0
            if jm > 0.0:
                jn = math.sqrt((jx / K) ** 2 + (jy / Ky) ** 2)
                tau = tmax * (1.0 - math.exp(-jn))
                tx = tau * jx / jm
                ty = tau * jy / jm
            W += w * (sig * ct + tx * st)
            DP += w * (tx * ct - sig * st)
            T += w * tx
            Fy += w * ty
            if bd1 > 0.0:
                hg = r * (ct - c1)  # geometric depth of the rim below the surface at theta
                if hg > 0.0:
                    Fb += w * bd1 * (c * hg + 0.5 * d2 * gam * hg * hg) * r * ct
    Fy = r * b * Fy
    if bd1 > 0.0 and C > 0.0:
        Fy += Fb * (1.0 - math.exp(-C * r * (th1 - thr) / Ky))
    DP = r * b * DP
    pl1 = P[19]
    if pl1 > 0.0 and s < 0.0:
        # a braked wheel ploughs: passive pressure on the front face over the rut depth z,
        # mobilised by the part of the travel the rim does not carry under the wheel (-s)
        DP -= -s * b * pl1 * (c * z + 0.5 * d2 * gam * z * z)
    return r * b * W, DP, r * r * b * T, Fy


@numba.njit(cache=True)
def _many(z, s, C, P, gx, gw, out):
    for i in range(z.shape[0]):
        W, DP, T, Fy = _point(z[i], s[i], C[i], P, gx, gw)
        out[i, 0] = W
        out[i, 1] = DP
        out[i, 2] = T
        out[i, 3] = Fy


@numba.njit(cache=True)
def _sinkage(load, s, C, P, gx, gw, zmax, iters, out):
    for i in range(load.shape[0]):
        lo, hi = 0.0, zmax
        for _ in range(iters):
            mid = 0.5 * (lo + hi)
            if _point(mid, s[i], C[i], P, gx, gw)[0] > load[i]:
                hi = mid
            else:
                lo = mid
        out[i] = 0.5 * (lo + hi)


# ---------------------------------------------------------------------------------------------
# the public, vectorised functions


def kappa_from_slip(s):
    """Velocity ratio v/(r*omega) from slip (see module docstring), s in [-1, 1] (inf locked)."""
    s = np.asarray(s, dtype=float)
    if np.any(s > 1) or np.any(s < -1) or not np.all(np.isfinite(s)):
        raise ValueError(f"slip={s!r} is invalid; valid range: -1 <= s <= 1")
    with np.errstate(divide="ignore"):
        return np.where(s >= 0, 1.0 - s, 1.0 / (1.0 + np.minimum(s, 0.0)))


def slip_from_speeds(v, r_omega, v_eps: float = 1e-3):
    """Slip from hub speed v and rim speed r*omega (both m/s, same sign convention).

    ``s = (r omega - v) / max(|r omega|, |v|, v_eps)``: equals ``1 - v/(r omega)`` when driving
    and ``r omega/v - 1`` when skidding; clipped to [-1, 1].
    """
    v = np.asarray(v, dtype=float)
    rw = np.asarray(r_omega, dtype=float)
    den = np.maximum(np.maximum(np.abs(rw), np.abs(v)), v_eps)
    return np.clip((rw - v) / den, SLIP_MIN, SLIP_MAX)


def entry_angle(z, radius: float):
    """theta_1 = arccos(1 - z/r) (rad) for sinkage z (m), clipped to [0, pi/2]."""
    return np.arccos(np.clip(1.0 - np.asarray(z, dtype=float) / radius, 0.0, 1.0))


def _check_slip(s: np.ndarray) -> None:
    if np.any(s > 1) or np.any(s < -1) or not np.all(np.isfinite(s)):
        raise ValueError(f"slip={s!r} is invalid; valid range: -1 <= s <= 1")


def wheel_forces(z, s, soil: SoilParams, wheel: WheelParams, q=0.0):
    """Integrate the stresses over the contact arc.

    Args:
        z: sinkage (m), >= 0, array-like.
        s: slip (-), in [-1, 1], broadcast with z.
        q: lateral ratio C = |v_y| / max(r omega, v_x) (-), >= 0 (inf: pure sideways drag).

    Returns:
        dict of arrays (broadcast shape): W (N), DP (N), T (N m), Fy (N, magnitude),
        theta1, theta_m, theta_r (rad).
    """
    z, s, q = np.broadcast_arrays(np.asarray(z, float), np.asarray(s, float), np.abs(np.asarray(q, float)))
    _check_slip(s)
    P = pack(soil, wheel)
    out = np.empty((z.size, 4))
    zf, sf = np.ascontiguousarray(z.ravel()), np.ascontiguousarray(s.ravel())
    _many(zf, sf, np.ascontiguousarray(np.minimum(q.ravel(), 1e9)), P, _GL_X, _GL_W, out)
    th1 = entry_angle(z, wheel.radius)
    se = slip_total(s, q)
    cr = np.clip(soil.c_exit + soil.c_exit1 * se, 0.0, 1.0)
    thr = -cr * th1
    a1s = soil.a1 if soil.a1_skid is None else soil.a1_skid
    thm = np.clip((soil.a0 + np.where(se >= 0, soil.a1, a1s) * se) * th1, thr, th1)
    sh = z.shape
    return {"W": out[:, 0].reshape(sh), "DP": out[:, 1].reshape(sh), "T": out[:, 2].reshape(sh),
            "Fy": out[:, 3].reshape(sh), "theta1": th1, "theta_m": thm, "theta_r": thr}


def max_sinkage(wheel: WheelParams) -> float:
    """Largest sinkage the model accepts: the wheel radius (theta_1 = 90 deg) (m)."""
    return wheel.radius


def solve_sinkage(load, s, soil: SoilParams, wheel: WheelParams, q=0.0, iters: int = 50):
    """Sinkage z (m) with W(z, s, q) = load, by bisection on [0, r] (compiled).

    Args:
        load: vertical wheel load (N), > 0, array-like.
        s: slip, broadcast with load.  q: lateral ratio (see :func:`wheel_forces`).

    Raises:
        ValueError: a load is not positive, or exceeds W at z = r (the wheel would sink past
            its axle, outside the model).
    """
    load, s, q = np.broadcast_arrays(np.asarray(load, float), np.asarray(s, float), np.abs(np.asarray(q, float)))
    if np.any(~(load > 0)):
        raise ValueError(f"load={load!r} is invalid; valid range: load > 0 N")
    _check_slip(s)
    zmax = max_sinkage(wheel)
    wmax = wheel_forces(np.full(load.shape, zmax), s, soil, wheel, q)["W"]
    if np.any(load > wmax):
        raise ValueError(f"load={load!r} sinks the wheel beyond its radius {zmax} m on {soil.name}; "
                         f"valid range: load <= {np.min(wmax):.4g} N")
    P = pack(soil, wheel)
    out = np.empty(load.size)
    _sinkage(np.ascontiguousarray(load.ravel()), np.ascontiguousarray(s.ravel()),
             np.ascontiguousarray(np.minimum(q.ravel(), 1e9)), P, _GL_X, _GL_W, zmax, iters, out)
    return out.reshape(load.shape)


def bekker_sinkage(load, soil: SoilParams, wheel: WheelParams):
    """Bekker's closed-form rigid-wheel sinkage (m) for small sinkage (Wong, Theory of Ground
    Vehicles, ch. 6): z0 = (3W / ((3-n)(k_c + b k_phi) sqrt(D)))^(2/(2n+1)), D = 2r
    (Bekker form at slip 0; a Reece soil is converted first)."""
    sp = soil.to_bekker(wheel.width)
    n, b, D = sp.n, wheel.width, 2 * wheel.radius
    k = sp.k_c + b * sp.k_phi
    return (3 * np.asarray(load, float) / ((3 - n) * k * np.sqrt(D))) ** (2 / (2 * n + 1))


def steady_state(load, s, soil: SoilParams, wheel: WheelParams, omega: float = 1.0, q=0.0):
    """Analytic steady state of a wheel carrying ``load`` at slip ``s``; ``omega`` (rad/s) sets
    the speed scale: driving, the wheel spins at omega and moves at ``v = (1 - s) r omega``; in
    skid it moves at ``v = r omega`` and spins at ``(1 + s) omega`` (0 when locked).

    Returns a dict of arrays: sinkage_m, DP_N, torque_Nm, DP_coeff (DP/W), efficiency
    ((DP v)/(T omega_wheel); nan where T <= 0), v_mps, omega_rps, Fy_N, W_N.
    """
    z = solve_sinkage(load, s, soil, wheel, q)
    f = wheel_forces(z, s, soil, wheel, q)
    sb = np.broadcast_to(np.asarray(s, float), z.shape)
    v = np.where(sb >= 0, 1.0 - sb, 1.0) * wheel.radius * omega
    w = np.where(sb >= 0, 1.0, 1.0 + sb) * omega
    with np.errstate(divide="ignore", invalid="ignore"):
        eff = np.where(f["T"] > 0, f["DP"] * v / (f["T"] * w), np.nan)
    return {"sinkage_m": z, "DP_N": f["DP"], "torque_Nm": f["T"], "DP_coeff": f["DP"] / np.asarray(load, float),
            "efficiency": eff, "v_mps": v, "omega_rps": w, "W_N": f["W"], "Fy_N": f["Fy"]}
