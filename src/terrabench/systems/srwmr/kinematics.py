"""HIT-MRII kinematics in the body frame (pure numpy; no simulator).

Body frame: origin at the chassis centre (CoM), x forward, y left, z up. Per side the closing
angle ``delta`` (= -q_rocker, >= 0 lifts the chassis) turns the rear section down by delta and,
through the angle-adjusting gear, the front section down by ``z * delta``; ``phi`` is the
differential joint (both sections of a side turn with it); ``zeta`` the passive bogie angle;
``mu`` the steering angles (c1..c6). Rotations about +y follow MuJoCo:
``(x, z) -> (x cos q + z sin q, -x sin q + z cos q)``.

* :func:`axle_positions` - the six axle centres (the 3-D chain body -> differential -> hinge ->
  bogie -> pillar -> axle).
* :func:`contact_points` - axle minus r along body z (flat ground under a level body).
* :func:`rocker_jacobian` - d(axle)/d(delta) per side (numerical, central difference).
* :func:`wheel_velocities` - horizontal velocity each wheel's contact must have (body frame) for
  a body twist (vx, vy, wz) and the rocker rates: ``v_i = v_b + w_b x c_i + J_i ddelta``.
* :func:`inverse_kinematics` - steering angles and spin rates that roll every grounded wheel
  without slip at those velocities (Ackermann / crab / differential follow from the twist), with
  the offset-wheel term ``-e mu_dot / r`` while steering.
* :func:`forward_kinematics` - the body twist that best explains measured wheel spins and
  steering angles (least squares; the inverse of the above for grounded wheels).
* :func:`lift_height` - height of a lifted wheel as a function of the rocker-angle change
  (the paper's eqs. 8-10, lost; rigid-link four-bar geometry on flat ground with the clutch
  engaged).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from terrabench.systems.srwmr.robot import WHEEL_SIDE, RobotConfig

_SIDE_IDX = np.array([0 if s == "L" else 1 for s in WHEEL_SIDE])
_SIGN = np.array([1.0 if s == "L" else -1.0 for s in WHEEL_SIDE])


def _rot(x, z, q):
    c, s = np.cos(q), np.sin(q)
    return x * c + z * s, -x * s + z * c


def axle_positions(cfg: RobotConfig, delta, zeta=(0.0, 0.0), phi=(0.0, 0.0), mu=None) -> np.ndarray:
    """(6, 3) axle centres in the body frame for per-side ``delta``, ``zeta``, ``phi`` (rad)."""
    delta, zeta, phi = np.asarray(delta, float), np.asarray(zeta, float), np.asarray(phi, float)
    mu = np.zeros(6) if mu is None else np.asarray(mu, float)
    b, z = cfg.rear_len, cfg.z_ratio
    th0 = cfg.rear_angle
    e = cfg.wheel_offset * _SIGN
    lat = cfg.steer_y - cfg.hinge_track / 2
    out = np.empty((6, 3))
    for s in (0, 1):
        yh = (1 if s == 0 else -1) * cfg.hinge_track / 2
        # rear section: q = -delta + phi; pivot then bogie (q + zeta)
        qr = -delta[s] + phi[s]
        px, pz = _rot(-b * math.cos(th0), -b * math.sin(th0), qr)
        qb = qr + zeta[s]
        for wi, xb in ((2 + s, cfg.bogie_front), (4 + s, -cfg.bogie_rear)):
            # pillar top at (xb, 0) in the bogie frame; axle at (0, -Lp) in the pillar frame
            # plus the steering-turned offset (-e sin mu, e cos mu)
            ox, oy = -e[wi] * math.sin(mu[wi]), e[wi] * math.cos(mu[wi])
            tx, tz = _rot(xb + ox, -cfg.pillar_rear, qb)
            out[wi] = (px + tx, yh + (1 if s == 0 else -1) * lat + oy, pz + tz)
        qf = z * delta[s] + phi[s]
        wi = s
        ox, oy = -e[wi] * math.sin(mu[wi]), e[wi] * math.cos(mu[wi])
        fx, fz = _rot(cfg.front_reach + ox, -cfg.front_drop - cfg.pillar_front, qf)
        out[wi] = (fx, yh + (1 if s == 0 else -1) * lat + oy, fz)
    return out


def geometry(cfg: RobotConfig, delta, mu=None) -> tuple[np.ndarray, np.ndarray]:
    """Axle centres (6, 3) and d(axle)/d(delta_side) (6, 3) in closed form, bogies level and the
    differential at zero, with the steering offsets of ``mu`` (None: none): the same numbers as
    :func:`axle_positions` / :func:`rocker_jacobian` (tested), from the one compiled kernel
    (:func:`period_geometry`).

    Rear side: the pivot sits at angle rear_angle (theta_s20) + delta below the hinge, the level bogie carries
    the pillars (``bogie_front`` ahead of the pivot, ``bogie_rear`` behind); front: the section,
    ``front_angle`` below the horizontal at nominal, turned by z delta carries its pillar.
    """
    susp, geom, _, _ = period_geometry(cfg, delta, _NO_MU if mu is None else mu)
    return susp if mu is None else geom


_NO_MU = np.zeros(6)


@numba.njit(cache=True)
def _suspension_kernel(delta, mu, k):
    """The suspension geometry without and with the steering offsets (Python floats' expressions,
    scalar libm sin/cos; the oracle ``tests/srwmr/srwmr_reference.py:geometry_pair_reference`` holds the
    same operations in the same order and is compared bitwise), plus the hinge rise (2,) and
    the front-middle wheelbases (2,) of the offset-free geometry. ``k``: the robot's lengths
    (:attr:`RobotConfig.kernel_lengths`). Returns one (5, 6, 3) array: P0, J0, P, J, then [4, 0, :2] the hinge rise
    and [4, 1, :2] the wheelbases (one array: each array a compiled call returns costs ~0.6 us)."""
    d0, d1 = delta[0], delta[1]
    b, a, bm, z, th0, lpr, lpf, e, yl, bq, tf = k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], k[8], k[9], k[10]
    ax, az = a * math.cos(tf), -a * math.sin(tf) - lpf  # front axle below the steering joint, section frame
    out = np.zeros((5, 6, 3))
    P0, J0, P, J = out[0], out[1], out[2], out[3]
    s0, c0 = math.sin(0.0), math.cos(0.0)
    for s in range(2):
        dl = d0 if s == 0 else d1
        sg = 1.0 if s == 0 else -1.0
        ang = th0 + dl
        ca, sa = math.cos(ang), math.sin(ang)
        px, pz = -b * ca, -b * sa
        for k in range(2):
            wi = 2 + s + 2 * k
            xb = bm if k == 0 else -bq
            m = mu[wi]
            P0[wi, 0] = px + xb - sg * e * s0
            P0[wi, 1] = sg * yl + sg * e * c0
            P0[wi, 2] = pz - lpr
            P[wi, 0] = px + xb - sg * e * math.sin(m)
            P[wi, 1] = sg * yl + sg * e * math.cos(m)
            P[wi, 2] = pz - lpr
            J0[wi, 0] = J[wi, 0] = b * sa
            J0[wi, 2] = J[wi, 2] = -b * ca
        cq, sq = math.cos(z * dl), math.sin(z * dl)
        for k in range(2):
            sm = s0 if k == 0 else math.sin(mu[s])
            cm = c0 if k == 0 else math.cos(mu[s])
            PP = P0 if k == 0 else P
            JJ = J0 if k == 0 else J
            xa = ax - sg * e * sm
            PP[s, 0] = xa * cq + az * sq
            PP[s, 1] = sg * yl + sg * e * cm
            PP[s, 2] = -xa * sq + az * cq
            JJ[s, 0] = z * (-xa * sq + az * cq)
            JJ[s, 2] = z * (-xa * cq - az * sq)
    out[4, 0, 0] = -(J0[0, 2] + J0[2, 2] + J0[4, 2]) / 3
    out[4, 0, 1] = -(J0[1, 2] + J0[3, 2] + J0[5, 2]) / 3
    out[4, 1, 0] = P0[0, 0] - P0[2, 0]
    out[4, 1, 1] = P0[1, 0] - P0[3, 0]
    return out


def period_geometry(cfg: RobotConfig, delta, mu):
    """The suspension geometry of one control period in one compiled call: ``((P0, J0), (P, J),
    dz, wb)``: :func:`geometry` without and with the steering offsets ``mu``, the hinge rise
    :func:`hinge_rise` of ``J0`` and the front-middle wheelbases of ``P0`` (fresh arrays)."""
    g = _suspension_kernel(np.asarray(delta, float), np.asarray(mu, float), cfg.kernel_lengths)
    return (g[0], g[1]), (g[2], g[3]), g[4, 0, :2], g[4, 1, :2]


def geometry_pair(cfg: RobotConfig, delta, mu):
    """``(geometry(cfg, delta), geometry(cfg, delta, mu))`` in one compiled pass: the suspension
    geometry without steering offsets (constraints) and with them (wheel commands). The same
    expressions as :func:`geometry`, so bitwise the same numbers (tested)."""
    susp, geom, _, _ = period_geometry(cfg, delta, mu)
    return susp, geom


def hinge_rise(J: np.ndarray) -> np.ndarray:
    """(2,) rise of each side's hinge per unit closing angle (m/rad): minus the mean vertical
    rate of the side's three axles, from the rocker Jacobian ``J`` (6, 3)."""
    return np.array([-(J[0, 2] + J[2, 2] + J[4, 2]) / 3, -(J[1, 2] + J[3, 2] + J[5, 2]) / 3])


def contact_points(cfg: RobotConfig, delta, zeta=(0.0, 0.0), phi=(0.0, 0.0), mu=None) -> np.ndarray:
    """(6, 3) wheel-ground contact points in the body frame (axle - r z_b)."""
    p = axle_positions(cfg, delta, zeta, phi, mu)
    p[:, 2] -= cfg.wheel_radius
    return p


def level_zeta(cfg: RobotConfig, delta) -> np.ndarray:
    """Bogie angles that keep the middle and rear axles level (flat ground) for ``delta``."""
    return np.asarray(delta, float).copy()  # the bogie turns back by what the rear section turned


def rocker_jacobian(cfg: RobotConfig, delta, phi=(0.0, 0.0), mu=None, h: float = 1e-5) -> np.ndarray:
    """(6, 3) d(axle)/d(delta_side) of each wheel for its own side, the bogie kept level."""
    delta = np.asarray(delta, float)
    J = np.empty((6, 3))
    for s in (0, 1):
        dp, dm = delta.copy(), delta.copy()
        dp[s] += h
        dm[s] -= h
        pp = axle_positions(cfg, dp, level_zeta(cfg, dp), phi, mu)
        pm = axle_positions(cfg, dm, level_zeta(cfg, dm), phi, mu)
        sel = _SIDE_IDX == s
        J[sel] = ((pp - pm) / (2 * h))[sel]
    return J


def chassis_clearance(cfg: RobotConfig, delta) -> float:
    """Ground clearance (m) on flat ground for symmetric ``delta`` (mean of the sides), the
    chassis level: the hinge height above the mean contact height minus the box half height."""
    c = contact_points(cfg, delta, level_zeta(cfg, delta))
    return float(-c[:, 2].mean() - cfg.box_bottom)


#: bisection bracket (rad) of :func:`delta_for_clearance`: the closing angles of 58 to 529 mm on the
#: fitted linkage, around every clearance a task asks (150-550 mm tested [S]). Not read from
#: ``robot.rocker_range``: the joint's opening stop moved to 0.65 rad, and a wider bracket moves the
#: solved angle of the default 250 mm by one ulp, i.e. every stored trial's bits.
CLEARANCE_BRACKET = (-0.5, 1.2)


def delta_for_clearance(cfg: RobotConfig, clearance: float) -> float:
    """The symmetric closing angle giving ``clearance`` (m) (bisection on :data:`CLEARANCE_BRACKET`)."""
    lo, hi = CLEARANCE_BRACKET
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if chassis_clearance(cfg, [mid, mid]) < clearance:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def clearance_reach(cfg: RobotConfig, delta_range) -> tuple[float, float]:
    """Smallest and largest clearance (m) a posture can be solved for (:func:`delta_for_clearance`)
    with closing angles inside ``delta_range`` (the IK's) and :data:`CLEARANCE_BRACKET`."""
    lo = max(delta_range[0], CLEARANCE_BRACKET[0])
    hi = min(delta_range[1], CLEARANCE_BRACKET[1])
    return chassis_clearance(cfg, [lo, lo]), chassis_clearance(cfg, [hi, hi])


def clearance_range(cfg: RobotConfig) -> tuple[float, float]:
    """Smallest and largest clearance (m) the rocker range reaches."""
    lo, hi = cfg.rocker_range
    return chassis_clearance(cfg, [-hi, -hi]), chassis_clearance(cfg, [-lo, -lo])


def middle_ahead_of_com(cfg: RobotConfig, clearance: float) -> float:
    """x (m) of the middle axle ahead of the body's CoM at ``clearance`` on level flat ground: a
    front wheel can leave the ground when it is > 0 (the CoM behind the middle support), a rear one
    when it is < 0 (the legged modes' CoM shift, docs/srwmr.md "The CoM window")."""
    d = delta_for_clearance(cfg, clearance)
    return float(axle_positions(cfg, [d, d], level_zeta(cfg, [d, d]))[2, 0]) - cfg.com_x


def wheelbase_front_middle(cfg: RobotConfig, delta) -> np.ndarray:
    """(2,) horizontal front-to-middle axle distance per side (m) (the wheelbase d_wl/2)."""
    p = axle_positions(cfg, delta, level_zeta(cfg, delta))
    return np.array([p[0, 0] - p[2, 0], p[1, 0] - p[3, 0]])


def wheel_velocities(cfg: RobotConfig, u, delta, mu=None, geom=None) -> np.ndarray:
    """(6, 2) horizontal contact velocities (body frame) required by ``u = (vx, vy, wz,
    ddelta_L, ddelta_R)`` so that no wheel slips: v_b + w x c_i + J_i ddelta. ``geom``: a
    precomputed :func:`geometry` (axles, J) at ``delta`` and ``mu``."""
    u = np.asarray(u, float)
    if geom is None:
        c = contact_points(cfg, delta, level_zeta(cfg, delta), mu=mu)
        J = rocker_jacobian(cfg, delta, mu=mu)
    else:
        c, J = geom  # axle x, y equal the contact point's (the contact is straight below)
    rate = u[3:5][_SIDE_IDX]
    v = np.empty((6, 2))
    v[:, 0] = u[0] - u[2] * c[:, 1] + J[:, 0] * rate
    v[:, 1] = u[1] + u[2] * c[:, 0]
    return v


def wheel_velocity_matrix(cfg: RobotConfig, delta, mu=None) -> np.ndarray:
    """(12, 5) linear map ``u -> vec(wheel_velocities)`` (rows x0, y0, x1, y1, ...)."""
    c = contact_points(cfg, delta, level_zeta(cfg, delta), mu=mu)
    J = rocker_jacobian(cfg, delta, mu=mu)
    M = np.zeros((12, 5))
    M[0::2, 0] = 1.0
    M[0::2, 2] = -c[:, 1]
    M[1::2, 1] = 1.0
    M[1::2, 2] = c[:, 0]
    for i in range(6):
        M[2 * i, 3 + _SIDE_IDX[i]] = J[i, 0]
    return M


#: a steering angle may pass +-90 deg by this much before it is folded to the other side (rad)
STEER_HYSTERESIS = math.radians(10.0)


def steer_and_spin(v: np.ndarray, r: float, mu_prev=None, v_min: float = 1e-6):
    """Steering angle (within +-(90 deg + :data:`STEER_HYSTERESIS`)) and spin (rad/s) rolling each
    wheel at ``v`` (6, 2).

    A wheel with no required velocity keeps ``mu_prev``. Each heading has two representations,
    the angle with the spin forwards and the angle turned by 180 deg with the spin reversed; the
    one within +-90 deg is taken unless the other is nearer ``mu_prev`` and within the
    hysteresis: crabbing sideways at +-90 deg, a wheel whose required heading wobbles across
    90 deg (a yaw correction's cross speed changing sign), or a crab to the right entered at
    +90 deg, keeps its side instead of swinging the steering by 180 deg.
    """
    mu_prev = np.zeros(len(v)) if mu_prev is None else np.asarray(mu_prev, float)
    speed = np.hypot(v[:, 0], v[:, 1])
    ang = np.arctan2(v[:, 1], v[:, 0])
    if np.abs(ang).max() < math.pi / 2 - STEER_HYSTERESIS:
        # no heading near +-90 deg: nothing folds and no other representation is admissible
        still = speed < v_min
        return np.where(still, mu_prev, ang), np.where(still, 0.0, speed / r)
    flip = np.abs(ang) > math.pi / 2 + 1e-9
    alt = ang - np.sign(ang) * math.pi  # the opposite heading, rolled backwards
    base = np.where(flip, alt, ang)
    other = np.where(flip, ang, alt)
    # the other representation when it is nearer the present angle and within the hysteresis
    swap = (np.abs(other) <= math.pi / 2 + STEER_HYSTERESIS) & (np.abs(other - mu_prev) < np.abs(base - mu_prev))
    flip ^= swap
    ang = np.where(swap, other, base)
    spin = np.where(flip, -speed, speed) / r
    still = speed < v_min
    return np.where(still, mu_prev, ang), np.where(still, 0.0, spin)


def differential_kinematics(cfg: RobotConfig, u, geom) -> tuple[np.ndarray, np.ndarray]:
    """Differential steering (the paper's 3-D differential-drive model, Task 15): every steering
    angle at 0 and each wheel's spin rolling out the forward component of its required contact
    velocity ``vx - wz y_i + J_i,x ddelta`` (the lateral component, ``wz x_i``, is left to skid).
    ``geom``: :func:`geometry` at the current closing angles, no steering offsets."""
    u = np.asarray(u, float)
    P, J = geom
    vx = u[0] - u[2] * P[:, 1] + J[:, 0] * u[3:5][_SIDE_IDX]
    return np.zeros(6), vx / cfg.wheel_radius


@numba.njit(cache=True)
def _contact_velocity_kernel(u, c, J):
    """:func:`wheel_velocities` on scalars (compiled; the same expressions in the same order,
    bitwise): the required contact velocity components vx (6,), vy (6,)."""
    v = np.empty((2, 6))
    for i in range(6):
        rate = u[3] if i % 2 == 0 else u[4]
        v[0, i] = u[0] - u[2] * c[i, 1] + J[i, 0] * rate
        v[1, i] = u[1] + u[2] * c[i, 0]
    return v


@numba.njit(cache=True)
def _steer_fold_kernel(ang, speed, mu_prev, r, v_min, hyst):
    """:func:`steer_and_spin` per wheel from the headings and speeds (compiled, bitwise): the
    representation within +-90 deg unless the other one is nearer ``mu_prev`` and within the
    hysteresis (a wheel already far from +-90 deg takes the first branch of the reference:
    its other representation is never admissible)."""
    out = np.empty((2, 6))
    mu, spin = out[0], out[1]
    half_pi = math.pi / 2
    for i in range(6):
        a = ang[i]
        if speed[i] < v_min:
            mu[i], spin[i] = mu_prev[i], 0.0
            continue
        flip = abs(a) > half_pi + 1e-9
        sgn = 1.0 if a > 0 else (-1.0 if a < 0 else 0.0)
        alt = a - sgn * math.pi
        base = alt if flip else a
        other = a if flip else alt
        if abs(other) <= half_pi + hyst and abs(other - mu_prev[i]) < abs(base - mu_prev[i]):
            flip = not flip
            base = other
        mu[i] = base
        spin[i] = (-speed[i] if flip else speed[i]) / r
    return out


@numba.njit(cache=True)
def _steering_wait_kernel(mu, mu_meas, u, tol):
    m = 0.0
    for i in range(mu.shape[0]):
        e = abs(mu[i] - mu_meas[i])
        if math.isnan(e):
            return False  # numpy's max of an array with a NaN is NaN, and NaN > tol is False
        m = max(m, e)
    return m > tol and (abs(u[0]) > 0.0 or abs(u[1]) > 0.0 or abs(u[2]) > 0.0)


def steering_wait(mu, mu_meas, u, tol: float = 0.15) -> bool:
    """Whether the wheels wait for their steering: a steering angle is more than ``tol`` (rad)
    from its target ``mu`` while the body moves (``u[:3]`` not zero); compiled
    ``np.abs(mu - mu_meas).max() > tol and (np.abs(u[:3]) > 0).any()`` (tested against it)."""
    return bool(_steering_wait_kernel(np.asarray(mu, float), np.asarray(mu_meas, float), np.asarray(u, float), tol))


def inverse_kinematics(cfg: RobotConfig, u, delta, mu_prev=None, mu_rate=None, lifted=(), geom=None):
    """Steering angles (6,) and spin rates (6,) (rad/s) for ``u``; lifted wheels get 0 spin.

    ``mu_rate`` (6,) adds the offset-wheel term: turning the steering axis by mu_dot moves the
    contact point backwards along the heading by e mu_dot, rolled out by -e mu_dot / r.
    With ``geom`` (the controller's per-period geometry) the compiled kernels compute it
    (bitwise :func:`inverse_kinematics_reference`, the numpy form; tested).
    """
    if geom is None or mu_rate is not None:
        return inverse_kinematics_reference(cfg, u, delta, mu_prev, mu_rate, lifted, geom)
    mu_prev = np.zeros(6) if mu_prev is None else np.asarray(mu_prev, float)
    vx, vy = _contact_velocity_kernel(np.asarray(u, float), geom[0], geom[1])
    # numpy's array hypot / arctan2 (SIMD kernels): libm's differ in the last bits
    mu, spin = _steer_fold_kernel(np.arctan2(vy, vx), np.hypot(vx, vy), mu_prev, cfg.wheel_radius, 1e-6,
                                  STEER_HYSTERESIS)
    spin = spin.copy()  # its own buffer (callers change it in place)
    for i in lifted:
        spin[i] = 0.0
    return mu, spin


def inverse_kinematics_reference(cfg: RobotConfig, u, delta, mu_prev=None, mu_rate=None, lifted=(), geom=None):
    """:func:`inverse_kinematics` with numpy arrays (:func:`wheel_velocities`,
    :func:`steer_and_spin`)."""
    v = wheel_velocities(cfg, u, delta, mu=mu_prev, geom=geom)
    mu, spin = steer_and_spin(v, cfg.wheel_radius, mu_prev)
    if mu_rate is not None:
        spin = spin - cfg.wheel_offset * np.asarray(mu_rate, float) / cfg.wheel_radius
    for i in lifted:
        spin[i] = 0.0
    return mu, spin


def forward_kinematics(cfg: RobotConfig, spin, mu, delta, ddelta=(0.0, 0.0), grounded=None, mu_geom=None) -> np.ndarray:
    """Body twist (vx, vy, wz) explaining wheel spins (rad/s) and steering angles (rad) of the
    grounded wheels, rolling without slip, given the rocker rates (least squares). ``mu_geom``:
    the steering angles that place the offset contact points (default ``mu``)."""
    spin, mu = np.asarray(spin, float), np.asarray(mu, float)
    g = np.ones(6, bool) if grounded is None else np.asarray(grounded, bool)
    M = wheel_velocity_matrix(cfg, delta, mu=mu if mu_geom is None else mu_geom)
    rim = cfg.wheel_radius * spin
    rhs = np.empty(12)
    rhs[0::2] = rim * np.cos(mu)
    rhs[1::2] = rim * np.sin(mu)
    rhs -= M[:, 3:] @ np.asarray(ddelta, float)
    rows = np.repeat(g, 2)
    sol, *_ = np.linalg.lstsq(M[rows, :3], rhs[rows], rcond=None)
    return sol


def _side_profile(cfg: RobotConfig, delta: float, zeta: float):
    """Side-plane (x, z) of the three axles of one side (hinge at the origin), sections turned."""
    p = axle_positions(cfg, [delta, delta], [zeta, zeta])
    return p[[0, 2, 4]][:, [0, 2]]


def lift_height(cfg: RobotConfig, which: str, d_delta: float, delta0: float = 0.0) -> float:
    """Height (m) a ``front``/``middle``/``rear`` wheel rises off flat ground when the closing
    angle changes by ``d_delta`` from ``delta0`` with the clutch engaged (bogie locked level at
    the start) and the other two wheels of the side kept on the ground (the hinge and the side
    move as a rigid four-bar: the two grounded axles stay at axle height).

    Lifting the front wheel needs the hinge to open (d_delta < 0), the rear one to close
    (d_delta > 0), as the paper's SWLM does (theta_s2 reduced for front/middle, increased for rear).
    """
    idx = {"front": 0, "middle": 1, "rear": 2}
    if which not in idx:
        raise ValueError(f"which={which!r} is unknown; valid: front, middle, rear")
    zeta0 = float(level_zeta(cfg, [delta0, delta0])[0])
    ground = [i for i in range(3) if i != idx[which]]

    def above(delta: float) -> float:
        # with the clutch engaged the bogie keeps its angle relative to the rear section
        pts = _side_profile(cfg, delta, zeta0)
        a, b = pts[ground[0]], pts[ground[1]]
        # rigid motion (rotation in the side plane) putting both grounded axles at one height
        ang = math.atan2(b[1] - a[1], b[0] - a[0])
        ang0 = 0.0 if b[0] > a[0] else math.pi
        rot = ang0 - ang
        c, s = math.cos(rot), math.sin(rot)
        rel = pts - a
        zs = rel[:, 0] * s + rel[:, 1] * c
        return float(zs[idx[which]] - zs[ground[0]])

    # the rise from the start: away from the fully open hinge the three axles of the start posture
    # are not level (the wheel stands 11 mm over the other two at the 500 mm clearance's closing
    # angle), and that standing offset is no lift (it had tripled the lever, so the legged lifts ran
    # at a third of their 7 mm/s)
    return above(delta0 + d_delta) - above(delta0)
