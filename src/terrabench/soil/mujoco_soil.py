"""Terramechanics forces on MuJoCo wheels through ``data.xfrc_applied``.

Usage (the hallway's episode loop calls ``before_substep`` before every ``mj_step``)::

    soil = SoilWheels(model, data, ["wheel_fl", ...], WHEEL, MARS_SOFT, ground=flat_ground())
    for _ in range(n):
        soil.before_substep(model, data)
        mujoco.mj_step(model, data)

Per wheel and per call (all wheels vectorised):

1. Ground under the wheel centre from ``ground(x, y) -> (z, normal)`` (flat plane or a MuJoCo
   heightfield, bilinear in ``model.hfield_data``), lowered by the deepest initial rut there
   (``ruts``, none by default: a buried start, the wheel settled in its own rut).
2. Sinkage ``z = r - (z_c - z_ground) n_z`` (distance of the centre above the local ground
   plane, measured along its normal, subtracted from r).
3. Heading frame: axle ``a`` = the wheel body's y axis, forward ``f = a x n``, lateral
   ``l = n x f``. Hub velocity ``v`` from ``data.cvel``; spin ``omega = w . a``.
4. Slip ``s = (r omega - v_x) / max(|r omega|, |v_x|, v_eps)`` in the travel direction
   (mirrored when the wheel runs backwards), in [-1, 1] (-1: locked); lateral ratio
   ``C = |v_y| / max(|r omega|, |v_x|, v_eps)``.
5. Forces from the :class:`~terrabench.soil.table.SoilTable`: normal ``W(z, s, C) - c_d v_n``
   (>= 0; ``c_d`` damps the sinkage rate so a wheel settles instead of bouncing), drawbar pull
   ``DP`` along f and resisting torque ``T`` about a, both scaled by
   ``g = min(1, max(|r omega|, |v_x|)/v_eps)`` so a wheel at rest feels no rolling resistance
   (no creeping at rest), lateral ``Fy`` against ``v_y``. W and DP act at the axle (the
   Wong-Reece resultants are axle forces; T is the moment of the shear stresses about it), Fy
   at the rim bottom. Everything is written as force + moment about the body's CoM. With
   ``rut_behind=True`` a negative DP is dropped while the rim turns along the travel direction and
   the hub does not advance (its rut lies behind it; off by default, docs/soil.md "Limitations").
6. Static footing (``footing=True``, the default): the steady-state DP, T and Fy are weighted by
   ``g = min(|r omega| / v_eps, 1)`` (they need soil flowing under a turning rim) and the rest of
   the tangential reaction, ``1 - g``, is the footing of the contact patch: a per-wheel state
   ``m`` (mobilised fraction of the footing strength along f and l) obeying Dahl's law in the
   patch's slip displacement, whose monotonic loading curve is Janosi-Hanamoto's
   ``1 - exp(-j/K)``, renewed as the rim rolls one contact length; strength = the model's own
   sliding forces at the current sinkage (locked-wheel drawbar resistance along f, sideways
   drag along l); critical damping on its initial stiffness, clipped to the remaining strength.
   A braked wheel under a push below the strength moves ``-K ln(1 - F/F_max)`` and holds; a
   larger push slides at the strength. The look-up's slip fades with the speed below v_eps
   (a creeping wheel carries its load as at slip 0). docs/soil.md, "Static footing".

The rigid contact of the soil wheels is switched off (their geoms' contype and conaffinity
set to 0 in ``model``) unless ``disable_contact=False``.

Steps 1-5 for all wheels run in one compiled kernel (numba, cached on disk; heightfield and
flat ground inside it, any other ``ground`` callable evaluated in Python first), so soil forces
every physics step (``every=1``, the default) cost a few microseconds.

Ground truth (sinkage, slip) is kept in :attr:`SoilWheels.truth` for metrics and tests only;
controllers must use :mod:`terrabench.soil.estimation` (encoder + body-velocity estimate).
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import mujoco
import numba
import numpy as np

from terrabench.soil.table import SoilTable, lookup_one
from terrabench.soil.terramechanics import SoilParams, WheelParams

Ground = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]

_FLAT, _HFIELD, _CALLBACK = 0, 1, 2


class flat_ground:  # noqa: N801 - kept a function-like name: ``flat_ground(h)`` is the public API
    """A horizontal plane at ``height`` (m): ``ground(x, y) -> (z (N,), normal (N, 3))``."""

    kind = _FLAT

    def __init__(self, height: float = 0.0):
        self.height = float(height)
        self.h = np.zeros((2, 2))
        self.params = np.array([0.0, 0.0, self.height, 1.0, 1.0, 1.0, 1.0, 2.0, 2.0])

    def __call__(self, x, y):
        x = np.asarray(x, float)
        n = np.zeros((x.size, 3))
        n[:, 2] = 1.0
        return np.full(x.size, self.height), n


class hfield_ground:  # noqa: N801
    """Height and normal of a MuJoCo heightfield geom (axis-aligned, unrotated), bilinear.

    MuJoCo stores ``nrow x ncol`` values in [0, 1], rows along +y, columns along +x, over
    ``[-size_x, size_x] x [-size_y, size_y]`` around the geom, scaled by ``size_z``. Points
    outside the field are clamped to its edge.
    """

    kind = _HFIELD

    def __init__(self, model: mujoco.MjModel, geom: str | int):
        gid = geom if isinstance(geom, int) else mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
        if gid < 0 or model.geom_type[gid] != mujoco.mjtGeom.mjGEOM_HFIELD:
            raise ValueError(f"geom={geom!r} is not a heightfield geom of this model")
        hid = model.geom_dataid[gid]
        nrow, ncol = int(model.hfield_nrow[hid]), int(model.hfield_ncol[hid])
        sx, sy, sz, _ = model.hfield_size[hid]
        adr = model.hfield_adr[hid]
        self.h = np.ascontiguousarray(model.hfield_data[adr: adr + nrow * ncol].reshape(nrow, ncol) * sz, dtype=float)
        pos = model.geom_pos[gid]
        self.params = np.array([pos[0], pos[1], pos[2], sx, sy, 2 * sx / (ncol - 1), 2 * sy / (nrow - 1),
                                float(nrow), float(ncol)])

    def __call__(self, x, y):
        x = np.atleast_1d(np.asarray(x, float))
        y = np.atleast_1d(np.asarray(y, float))
        z = np.empty(x.size)
        n = np.empty((x.size, 3))
        for i in range(x.size):
            z[i], n[i, 0], n[i, 1], n[i, 2] = _hfield_at(x[i], y[i], self.h, self.params)
        return z, n


@numba.njit(cache=True, inline="always")
def _hfield_at(x, y, h, gp):
    nrow, ncol = int(gp[7]), int(gp[8])
    u = min(max((x - gp[0] + gp[3]) / gp[5], 0.0), ncol - 1 - 1e-9)
    w = min(max((y - gp[1] + gp[4]) / gp[6], 0.0), nrow - 1 - 1e-9)
    c, r = int(u), int(w)
    tu, tw = u - c, w - r
    h00, h01, h10, h11 = h[r, c], h[r, c + 1], h[r + 1, c], h[r + 1, c + 1]
    z = (1 - tw) * ((1 - tu) * h00 + tu * h01) + tw * ((1 - tu) * h10 + tu * h11)
    dzdx = ((1 - tw) * (h01 - h00) + tw * (h11 - h10)) / gp[5]
    dzdy = ((1 - tu) * (h10 - h00) + tu * (h11 - h01)) / gp[6]
    nn = math.sqrt(dzdx * dzdx + dzdy * dzdy + 1.0)
    return z + gp[2], -dzdx / nn, -dzdy / nn, 1.0 / nn


@numba.njit(cache=True, inline="always")
def _footing(i, sink, rw, vf, vl, g, r, foot, caps, tp, fp):
    """Advance wheel i's footing state over one step and return its force along f and along l,
    weighted by ``1 - g`` (docs/soil.md, "Static footing").

    State ``m = foot[i]``: the mobilised fraction of the footing's shear strength along f and l
    (|m| <= 1). Dahl's law in the patch displacement, whose monotonic loading curve is
    Janosi-Hanamoto's ``1 - exp(-j/K)``, plus renewal of the soil under the patch as the rim
    rolls one contact length: ``dm/dt = u - (|u| + |r omega| / L_c) m``, ``u = (v_sx/K, v_sy/K_y)``,
    integrated exactly over the step for constant velocities. ``foot[i, 2]``: the side of the
    wheel's own rut (+1: the wheel last rolled along +f with its rim faster than v_eps, so the rut lies behind;
    0: none, fresh soil on both sides); pushed into its rut the footing keeps only its shear part."""
    dt, K, Ky, cex, ct = fp[1], fp[2], fp[3], fp[4], fp[5]
    if sink <= 0.0:
        foot[i, 0] = 0.0
        foot[i, 1] = 0.0
        foot[i, 2] = 0.0  # lifted: it lands on fresh soil
        return 0.0, 0.0, 0.0
    if abs(rw) > fp[6] and rw * vf > 0.0:  # rolling: the rut forms behind the travel
        foot[i, 2] = 1.0 if vf > 0.0 else -1.0
    vsx = vf - rw  # the contact patch against the soil (the rim bottom's velocity)
    ux, uy = vsx / K, vl / Ky
    un = math.sqrt(ux * ux + uy * uy)
    cz = min(max(1.0 - sink / r, 0.0), 1.0)
    lc = max(r * math.acos(cz) * (1.0 + cex), 1e-6)  # contact length, entry to exit
    a = un + abs(rw) / lc
    mx, my = foot[i, 0], foot[i, 1]
    if a * dt < 1e-12:
        mx += ux * dt
        my += uy * dt
    else:
        e = math.exp(-a * dt)
        mx = ux / a + (mx - ux / a) * e
        my = uy / a + (my - uy / a) * e
    foot[i, 0] = mx
    foot[i, 1] = my
    # strength of the footing at this sinkage: the model's own sliding forces (the locked wheel's
    # drawbar resistance along f, the sideways-dragged wheel's lateral force), linear in z
    zc = min(sink, tp[0]) * tp[1]
    k = min(int(zc), caps.shape[0] - 2)
    t = zc - k
    capx = (1.0 - t) * caps[k, 0] + t * caps[k + 1, 0]
    capy = (1.0 - t) * caps[k, 1] + t * caps[k + 1, 1]
    phs = (1.0 - t) * caps[k, 2] + t * caps[k + 1, 2]
    if mx * foot[i, 2] < 0.0:
        # pushed back into its own rut: no fresh soil to compact or plough, the shear part only
        capx = phs * capx
        phs = 1.0
    # damping of the elastic footing, clipped so that the reaction stays within the strength
    # (gone once the soil yields, |m| -> 1: a sliding wheel meets the strength itself)
    rem = max(1.0 - math.sqrt(mx * mx + my * my), 0.0)
    dx = min(max(ct * vsx, -rem * capx), rem * capx)
    dy = min(max(ct * vl, -rem * capy), rem * capy)
    ffx = -(1.0 - g) * (mx * capx + dx)
    ffy = -(1.0 - g) * (my * capy + dy)
    return ffx, ffy, phs


@numba.njit(cache=True, inline="always")
def _rut_at(px, py, ruts, r):
    """Depth (m) of the deepest initial rut under (px, py) and its slope (d depth / dx, d depth / dy).

    Rut k (``ruts[k] = (x, y, f_x, f_y, depth, half width, tan wall)``): the soil surface lowered by
    ``depth - rise(u) - side(l)`` where positive, u along the rut's heading f, l across it. Along f the
    floor is the wheel's own imprint (a circle of the wheel radius r) out to where its slope reaches
    the wall's, then straight walls at that slope; across, flat over the half width, then the wall's
    slope (docs/assumptions-srwmr.md, "T4 buried start")."""
    best, gx, gy = 0.0, 0.0, 0.0
    for k in range(ruts.shape[0]):
        dx, dy = px - ruts[k, 0], py - ruts[k, 1]
        fx, fy, tw = ruts[k, 2], ruts[k, 3], ruts[k, 6]
        u = dx * fx + dy * fy
        lat = -dx * fy + dy * fx
        a = r * tw / math.sqrt(1.0 + tw * tw)  # r sin(wall angle): the imprint meets the wall
        au = abs(u)
        su = 1.0 if u >= 0.0 else -1.0
        if au <= a:
            q = math.sqrt(r * r - u * u)
            rise, drise = r - q, u / q
        else:
            rise = r - r / math.sqrt(1.0 + tw * tw) + (au - a) * tw
            drise = su * tw
        al = abs(lat) - ruts[k, 5]
        side, dside = 0.0, 0.0
        if al > 0.0:
            side = al * tw
            dside = tw if lat >= 0.0 else -tw
        dep = ruts[k, 4] - rise - side
        if dep > best:
            best = dep
            # d depth / d(x, y) = -(d rise / du) (du/dx, du/dy) - (d side / dl) (dl/dx, dl/dy)
            gx = -drise * fx + dside * fy
            gy = -drise * fy - dside * fx
    return best, gx, gy


@numba.njit(cache=True)
def _soil_kernel(bodies, roots, xpos, xmat, cvel, scom, xipos, xfrc, gmode, gh, gp, zg_in, n_in,
                 tab, dwdz, tp, r, damping, v_eps, truth, foot, caps, fp, ruts):
    for i in range(bodies.shape[0]):
        b = bodies[i]
        px, py, pz = xpos[b, 0], xpos[b, 1], xpos[b, 2]
        ax, ay, az = xmat[b, 1], xmat[b, 4], xmat[b, 7]
        wx, wy, wz = cvel[b, 0], cvel[b, 1], cvel[b, 2]
        rx, ry, rz = px - scom[roots[i], 0], py - scom[roots[i], 1], pz - scom[roots[i], 2]
        vx_ = cvel[b, 3] + wy * rz - wz * ry
        vy_ = cvel[b, 4] + wz * rx - wx * rz
        vz_ = cvel[b, 5] + wx * ry - wy * rx
        if gmode == 0:
            zg, nx, ny, nz = gp[2], 0.0, 0.0, 1.0
        elif gmode == 1:
            zg, nx, ny, nz = _hfield_at(px, py, gh, gp)
        else:
            zg, nx, ny, nz = zg_in[i], n_in[i, 0], n_in[i, 1], n_in[i, 2]
        rut = 0.0
        if ruts.shape[0] > 0:
            rut, gx, gy = _rut_at(px, py, ruts, r)
            if rut > 0.0:
                # the surface zg - rut: its slope is the ground's (-n_x/n_z, -n_y/n_z) less the rut's
                hx = -nx / nz - gx
                hy = -ny / nz - gy
                hn = math.sqrt(hx * hx + hy * hy + 1.0)
                nx, ny, nz = -hx / hn, -hy / hn, 1.0 / hn
                zg = zg - rut
        # heading f = a x n, lateral l = n x f
        fx, fy, fz = ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx
        fn = math.sqrt(fx * fx + fy * fy + fz * fz)
        if fn < 1e-12:
            fn = 1e-12
        fx, fy, fz = fx / fn, fy / fn, fz / fn
        lx, ly, lz = ny * fz - nz * fy, nz * fx - nx * fz, nx * fy - ny * fx
        sink = r - (pz - zg) * nz
        vf = vx_ * fx + vy_ * fy + vz_ * fz
        vl = vx_ * lx + vy_ * ly + vz_ * lz
        vn = vx_ * nx + vy_ * ny + vz_ * nz
        rw = r * (wx * ax + wy * ay + wz * az)
        d = 1.0 if rw + vf >= 0 else -1.0
        big = max(abs(rw), abs(vf))
        den = max(big, v_eps)
        s = min(max(d * (rw - vf) / den, -1.0), 1.0)
        C = abs(vl) / den
        fade = min(big / v_eps, 1.0)
        st = s
        if fp[0] > 0.0:
            # below v_eps the slip of a creeping wheel is not a steady state: the look-up's slip (the
            # stress angles and exponent behind the load it carries) fades with the speed
            st = s * fade
        W, DP, T, Fy = lookup_one(sink, st, C, tab, dwdz, tp)
        if fp[7] > 0.0 and DP < 0.0 and d * vf <= 0.0:
            # the rim turns along d but the hub does not advance: the compaction resistance of the
            # steady state needs a soil face ahead, and this wheel's rut lies behind it
            DP = 0.0
        Fn = W - damping * vn
        if Fn < 0.0 or sink <= 0.0:
            Fn = 0.0
        dpf = d * DP * fade
        tf = d * T * fade
        fyv = -Fy if vl > 0 else (Fy if vl < 0 else 0.0)
        ffx = 0.0  # footing force along f: its shear share at the rim bottom, the rest at the axle
        ffy = 0.0  # along l, at the rim bottom (as Fy)
        phs = 0.0
        if fp[0] > 0.0:
            # the steady-state forces need soil flowing under a turning rim: weight min(|r omega| / v_eps, 1);
            # the rest of the reaction is the footing of the patch (Dahl / Janosi-Hanamoto state)
            g = min(abs(rw) / v_eps, 1.0)
            ffx, ffy, phs = _footing(i, sink, rw, vf, vl, g, r, foot, caps, tp, fp)
            dpf = d * DP * g
            tf = d * T * g
            fyv = fyv * g + ffy
        fax = dpf + (1.0 - phs) * ffx  # along f at the axle
        frx = phs * ffx  # along f at the rim bottom
        Fax, Fay, Faz = Fn * nx + fax * fx, Fn * ny + fax * fy, Fn * nz + fax * fz
        Flx, Fly, Flz = fyv * lx + frx * fx, fyv * ly + frx * fy, fyv * lz + frx * fz
        arx, ary, arz = px - xipos[b, 0], py - xipos[b, 1], pz - xipos[b, 2]
        brx, bry, brz = arx - r * nx, ary - r * ny, arz - r * nz
        xfrc[b, 0] = Fax + Flx
        xfrc[b, 1] = Fay + Fly
        xfrc[b, 2] = Faz + Flz
        xfrc[b, 3] = -tf * ax + (ary * Faz - arz * Fay) + (bry * Flz - brz * Fly)
        xfrc[b, 4] = -tf * ay + (arz * Fax - arx * Faz) + (brz * Flx - brx * Flz)
        xfrc[b, 5] = -tf * az + (arx * Fay - ary * Fax) + (brx * Fly - bry * Flx)
        truth[0, i] = sink + rut if rut > 0.0 else sink  # below the undisturbed surface
        truth[1, i] = s
        truth[2, i] = C
        truth[3, i] = W
        truth[4, i] = dpf + ffx
        truth[5, i] = tf + r * frx
        truth[6, i] = Fy
        truth[7, i] = Fn
        truth[8, i] = foot[i, 0]
        truth[9, i] = foot[i, 1]
        truth[10, i] = rut


_TRUTH = ("sinkage", "slip", "lateral_slip", "W", "DP", "T", "Fy", "Fn", "foot_x", "foot_y", "rut")


def _body_ids(model: mujoco.MjModel, wheels: Sequence[str | int]) -> np.ndarray:
    ids = []
    for w in wheels:
        if isinstance(w, (int, np.integer)):
            ids.append(int(w))
            continue
        b = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, w)
        if b < 0:
            g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, w)
            if g < 0:
                raise ValueError(f"wheel={w!r} is neither a body nor a geom of this model")
            b = int(model.geom_bodyid[g])
        ids.append(b)
    if not ids or min(ids) <= 0 or max(ids) >= model.nbody:
        raise ValueError(f"wheels={list(wheels)!r} must name 1..{model.nbody - 1} bodies (not the world)")
    return np.asarray(ids, dtype=np.intp)


def disable_rigid_contact(model: mujoco.MjModel, body_ids) -> None:
    """Switch off collisions of every geom of the given bodies (contype = conaffinity = 0)."""
    for b in np.atleast_1d(body_ids):
        sel = model.geom_bodyid == b
        model.geom_contype[sel] = 0
        model.geom_conaffinity[sel] = 0


class SoilWheels:
    """Wheel-soil forces for a set of wheel bodies (one soil, one wheel geometry).

    Args:
        model, data: the MuJoCo pair (model is modified: wheel contacts off).
        wheels: wheel body names/ids, or geom names (their bodies are used). Each body's local
            y axis must be the axle and its origin the wheel centre.
        wheel: wheel geometry (radius, width).
        soil: soil parameters, or a prebuilt :class:`SoilTable` for (soil, wheel).
        ground: ``ground(x, y) -> (z, normal)``; default a flat plane at z = 0.
            :class:`flat_ground` and :class:`hfield_ground` are evaluated inside the kernel.
        damping: sinkage-rate damping c_d (N s/m) per wheel; None = ``damping_ratio`` times
            critical for the nominal load on the soil's stiffness dW/dz at static sinkage.
        damping_ratio: (-), used when damping is None.
        nominal_load: wheel load (N) for the default damping; None = total model mass x g /
            number of wheels.
        every: compute forces every k-th call and hold them in between (1 = each call, default).
        v_eps: speed scale (m/s) regularising slip and fading rolling resistance at rest.
        disable_contact: switch off the wheels' rigid contacts.
        footing: static footing (default on): below ``v_eps`` the tangential soil reaction is the
            elastic-plastic footing of the contact patch (Janosi-Hanamoto in the accumulated patch
            displacement, capped by the soil's sliding strength, renewed as the rim rolls) instead
            of the faded steady-state forces alone; above ``v_eps`` the forces are the steady-state
            ones (docs/soil.md, "Static footing"). False: the faded steady-state forces only.
        refresh: recompute kinematics and velocities (mj_kinematics, mj_comPos, mj_comVel)
            for the current state before each force evaluation. Without it the forces use
            ``xpos``/``cvel`` that ``mj_step`` left behind, which are one step old (mj_step
            integrates after its forward pass); with a 1 ms step the difference is below the
            tests' tolerances and refresh costs extra time per call.
        ruts: initial rut depth (m) under each wheel (one number for all, or one per wheel; None or
            0: none, the default): the soil surface is lowered under each wheel's hub as placed when
            the hook is built (``data``'s current pose), so a wheel settled ``rut`` below its
            static sinkage starts that much deeper in the soil (docs/assumptions-srwmr.md, "T4
            buried start"). The floor is the wheel's imprint, the walls stand at the soil's friction angle (a loose
            soil's angle of repose), across the axle the floor is ``rut_width`` wide. Every wheel
            feels every rut (a wheel that drives into another's rut drops into it); ruts do not
            change with time. ``truth["sinkage"]`` is then measured from the undisturbed surface
            (the force model's sinkage into the rut floor plus the rut under the hub) and
            ``truth["rut"]`` is the rut's depth under the hub.
        rut_width: width (m) of a rut's flat floor across the axle; None = the wheel width.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, wheels: Sequence[str | int],
                 wheel: WheelParams, soil: SoilParams | SoilTable, ground: Ground | None = None, *,
                 damping: float | None = None, damping_ratio: float = 1.0,
                 nominal_load: float | None = None, every: int = 1, v_eps: float = 0.02,
                 disable_contact: bool = True, refresh: bool = False, footing: bool = True,
                 ruts: float | Sequence[float] | None = None, rut_width: float | None = None,
                 rut_behind: bool = False):
        if int(every) != every or every < 1:
            raise ValueError(f"every={every!r} is invalid; valid range: integer >= 1")
        if not v_eps > 0:
            raise ValueError(f"v_eps={v_eps!r} is invalid; valid range: v_eps > 0 m/s")
        self.table = soil if isinstance(soil, SoilTable) else SoilTable(soil, wheel)
        if self.table.wheel != wheel:
            raise ValueError("the SoilTable was built for a different wheel")
        self.wheel, self.soil = wheel, self.table.soil
        self.ground = ground or flat_ground()
        self.bodies = _body_ids(model, wheels)
        self.roots = np.ascontiguousarray(model.body_rootid[self.bodies], dtype=np.intp)
        self.n = len(self.bodies)
        self.every, self.v_eps = int(every), float(v_eps)
        g = float(np.linalg.norm(model.opt.gravity)) or 9.81
        if nominal_load is None:
            nominal_load = float(np.sum(model.body_mass)) * g / self.n
        self.nominal_load = nominal_load
        if damping is None:
            z0 = self.table.static_sinkage(nominal_load)
            dz = self.table.static_sinkage(nominal_load * 1.01) - z0
            k = 0.01 * nominal_load / dz if dz > 0 else nominal_load / max(z0, 1e-3)  # dW/dz (N/m)
            damping = 2.0 * damping_ratio * np.sqrt(k * nominal_load / g)
        if not damping >= 0:
            raise ValueError(f"damping={damping!r} is invalid; valid range: damping >= 0 N s/m")
        self.damping = float(damping)
        self.footing = bool(footing)
        #: footing state per wheel: mobilised fraction of the footing strength along f and l
        self.foot = np.zeros((self.n, 3))
        t = self.table
        j0 = int(np.argmin(np.abs(t.s)))
        # footing strength against z: the locked wheel's drawbar resistance (shear, compaction, front
        # ploughing) and the lateral force of a wheel dragged sideways (shear, sidewall bulldozing)
        capx = np.maximum(-t.data[:, 0, 0, 1], 0.0)
        # the shear stresses' share of it, which acts at the rim (its moment: the locked wheel's torque);
        # the normal stresses' share (compaction, ploughing) acts through the axle
        shear = np.divide(np.abs(t.data[:, 0, 0, 2]) / wheel.radius, capx, out=np.zeros_like(capx), where=capx > 0)
        self._caps = np.ascontiguousarray(np.stack([capx, np.maximum(t.data[:, j0, -1, 3], 0.0),
                                                    np.clip(shear, 0.0, 1.0)], axis=1))
        z0 = t.static_sinkage(nominal_load)
        k_t = float(np.interp(z0, t.z, self._caps[:, 0])) / self.soil.K  # initial footing stiffness (N/m)
        self.footing_damping = 2.0 * damping_ratio * np.sqrt(max(k_t, 0.0) * nominal_load / g)
        #: a driven wheel whose hub does not advance has its rut behind it: no soil face ahead pushes
        #: the hub back (the steady state's negative drawbar pull is dropped there); off by default
        #: until the stored results are re-made with it (docs/soil.md, "Limitations")
        self.rut_behind = bool(rut_behind)
        self._fp = np.array([1.0 if self.footing else 0.0, float(model.opt.timestep) * self.every, self.soil.K,
                             self.soil.Ky, self.soil.c_exit, self.footing_damping, self.v_eps,
                             1.0 if self.rut_behind else 0.0])
        if disable_contact:
            disable_rigid_contact(model, self.bodies)
        self.refresh = bool(refresh)
        kind = getattr(self.ground, "kind", _CALLBACK)
        self._gmode = kind if kind in (_FLAT, _HFIELD) else _CALLBACK
        self._gh = np.ascontiguousarray(getattr(self.ground, "h", np.zeros((2, 2))), dtype=float)
        self._gp = np.ascontiguousarray(getattr(self.ground, "params", np.zeros(9)), dtype=float)
        self._zg = np.zeros(self.n)
        self._nrm = np.zeros((self.n, 3))
        self._truth = np.zeros((len(_TRUTH), self.n))
        #: ground truth per wheel (views of one array, updated in place at each evaluation)
        self.truth: dict[str, np.ndarray] = {k: self._truth[i] for i, k in enumerate(_TRUTH)}
        mujoco.mj_forward(model, data)  # valid xpos/xmat/cvel for the first call
        #: initial ruts, one row per rut: (x, y, heading x, heading y, depth, floor half width, tan wall)
        self.ruts = self._place_ruts(data, ruts, rut_width)
        self._bind(data)
        self._calls = 0

    def _place_ruts(self, data: mujoco.MjData, ruts, rut_width) -> np.ndarray:
        """The rut rows under the wheels' hubs as they stand in ``data`` (an empty (0, 7) array: none)."""
        if ruts is None:
            return np.zeros((0, 7))
        depth = np.broadcast_to(np.asarray(ruts, float), (self.n,))
        if not np.all(np.isfinite(depth)) or np.any(depth < 0) or np.any(depth > self.wheel.radius):
            raise ValueError(f"ruts={ruts!r} is invalid; valid range: 0 <= depth <= the wheel radius "
                             f"{self.wheel.radius} m, one number or one per wheel ({self.n})")
        half = 0.5 * (self.wheel.width if rut_width is None else float(rut_width))
        if not half >= 0:
            raise ValueError(f"rut_width={rut_width!r} is invalid; valid range: >= 0 m")
        tw = self.soil.tan_phi
        rows = []
        for i, b in enumerate(self.bodies):
            if depth[i] <= 0.0:
                continue
            ax, ay = data.xmat[b, 1], data.xmat[b, 4]  # the axle's horizontal part; heading = axle x up
            fx, fy = ay, -ax
            fn = math.hypot(fx, fy)
            if fn < 1e-9:
                raise ValueError(f"ruts: wheel {i} has a vertical axle; a rut needs a heading")
            rows.append((data.xpos[b, 0], data.xpos[b, 1], fx / fn, fy / fn, depth[i], half, tw))
        return np.ascontiguousarray(np.array(rows, float).reshape(-1, 7))

    def _bind(self, data: mujoco.MjData) -> None:
        # MjData's arrays are views of buffers that live as long as data: fetch them once
        self._data = data
        self._views = (data.xpos, data.xmat, data.cvel, data.subtree_com, data.xipos, data.xfrc_applied)

    def before_substep(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Compute (every ``every``-th call) and write the soil wrench of each wheel."""
        if self._calls % self.every == 0:
            if self.refresh:
                mujoco.mj_kinematics(model, data)
                mujoco.mj_comPos(model, data)
                mujoco.mj_comVel(model, data)
            self._step(data)
        self._calls += 1

    def _step(self, data: mujoco.MjData) -> None:
        if data is not self._data:
            self._bind(data)
        xpos, xmat, cvel, scom, xipos, xfrc = self._views
        if self._gmode == _CALLBACK:
            p = xpos[self.bodies]
            zg, nrm = self.ground(p[:, 0], p[:, 1])
            self._zg[:] = zg
            self._nrm[:] = nrm
        t = self.table
        _soil_kernel(self.bodies, self.roots, xpos, xmat, cvel, scom, xipos, xfrc, self._gmode, self._gh, self._gp,
                     self._zg, self._nrm, t.data, t.dWdz_end, t.params, self.wheel.radius, self.damping, self.v_eps,
                     self._truth, self.foot, self._caps, self._fp, self.ruts)

    @property
    def wrench(self) -> np.ndarray:
        """The soil wrench (force, moment about the CoM) of each wheel as last written, (N, 6)."""
        return self._views[5][self.bodies].copy()
