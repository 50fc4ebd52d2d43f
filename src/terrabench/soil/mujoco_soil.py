"""Terramechanics forces on MuJoCo wheels through ``data.xfrc_applied``.

Usage (the hallway's episode loop calls ``before_substep`` before every ``mj_step``)::

    soil = SoilWheels(model, data, ["wheel_fl", ...], WHEEL, MARS_SOFT, ground=flat_ground())
    for _ in range(n):
        soil.before_substep(model, data)
        mujoco.mj_step(model, data)

Per wheel and per call (all wheels vectorised):

1. Ground under the wheel centre from ``ground(x, y) -> (z, normal)`` (flat plane or a MuJoCo
   heightfield, bilinear in ``model.hfield_data``).
2. Sinkage ``z = r - (z_c - z_ground) n_z`` (distance of the centre above the local ground
   plane, measured along its normal, subtracted from r).
3. Heading frame: axle ``a`` = the wheel body's y axis, forward ``f = a x n``, lateral
   ``l = n x f``. Hub velocity ``v`` from ``data.cvel``; spin ``omega = w . a``.
4. Slip ``s = (r omega - v_x) / max(|r omega|, |v_x|, v_eps)`` in the travel direction
   (mirrored when the wheel runs backwards); lateral slip ratio ``q = |v_y| / max(|r omega|,
   v_eps)``.
5. Forces from the :class:`~terrabench.soil.table.SoilTable`: normal ``W(z, s) - c_d v_n``
   (>= 0; ``c_d`` damps the sinkage rate so a wheel settles instead of bouncing), drawbar pull
   ``DP`` along f and resisting torque ``T`` about a, both scaled by
   ``g = min(1, max(|r omega|, |v_x|)/v_eps)`` so a wheel at rest feels no rolling resistance
   (no creeping at rest), lateral ``Fy`` against ``v_y``. W and DP act at the axle (the
   Wong-Reece resultants are axle forces; T is the moment of the shear stresses about it), Fy
   at the rim bottom. Everything is written as force + moment about the body's CoM.

The rigid contact of the soil wheels is switched off (their geoms' contype and conaffinity
set to 0 in ``model``) unless ``disable_contact=False``.

Ground truth (sinkage, slip) is kept in :attr:`SoilWheels.truth` for metrics and tests only;
controllers must use :mod:`terrabench.soil.estimation` (encoder + body-velocity estimate).
"""

from __future__ import annotations

from typing import Callable, Sequence

import mujoco
import numpy as np

from terrabench.soil.table import SoilTable
from terrabench.soil.terramechanics import SLIP_MAX, SLIP_MIN, SoilParams, WheelParams

Ground = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def flat_ground(height: float = 0.0) -> Ground:
    """A horizontal plane at ``height`` (m): ``ground(x, y) -> (z (N,), normal (N, 3))``."""

    def ground(x, y):
        x = np.asarray(x, float)
        n = np.zeros((x.size, 3))
        n[:, 2] = 1.0
        return np.full(x.size, height), n

    return ground


def hfield_ground(model: mujoco.MjModel, geom: str | int) -> Ground:
    """Height and normal of a MuJoCo heightfield geom (axis-aligned, unrotated), bilinear.

    MuJoCo stores ``nrow x ncol`` values in [0, 1], rows along +y, columns along +x, over
    ``[-size_x, size_x] x [-size_y, size_y]`` around the geom, scaled by ``size_z``. Points
    outside the field are clamped to its edge.
    """
    gid = geom if isinstance(geom, int) else mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    if gid < 0 or model.geom_type[gid] != mujoco.mjtGeom.mjGEOM_HFIELD:
        raise ValueError(f"geom={geom!r} is not a heightfield geom of this model")
    hid = model.geom_dataid[gid]
    nrow, ncol = model.hfield_nrow[hid], model.hfield_ncol[hid]
    sx, sy, sz, _ = model.hfield_size[hid]
    adr = model.hfield_adr[hid]
    h = model.hfield_data[adr: adr + nrow * ncol].reshape(nrow, ncol) * sz
    pos = model.geom_pos[gid].copy()
    dx, dy = 2 * sx / (ncol - 1), 2 * sy / (nrow - 1)

    def ground(x, y):
        u = np.clip((np.asarray(x, float) - pos[0] + sx) / dx, 0, ncol - 1 - 1e-9)
        w = np.clip((np.asarray(y, float) - pos[1] + sy) / dy, 0, nrow - 1 - 1e-9)
        c, r = u.astype(np.intp), w.astype(np.intp)
        tu, tw = u - c, w - r
        h00, h01, h10, h11 = h[r, c], h[r, c + 1], h[r + 1, c], h[r + 1, c + 1]
        z = (1 - tw) * ((1 - tu) * h00 + tu * h01) + tw * ((1 - tu) * h10 + tu * h11)
        dzdx = ((1 - tw) * (h01 - h00) + tw * (h11 - h10)) / dx
        dzdy = ((1 - tu) * (h10 - h00) + tu * (h11 - h01)) / dy
        n = np.stack([-dzdx, -dzdy, np.ones_like(z)], axis=-1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        return z + pos[2], n

    return ground


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
        damping: sinkage-rate damping c_d (N s/m) per wheel; None = ``damping_ratio`` times
            critical for the nominal load on the soil's stiffness dW/dz at static sinkage.
        damping_ratio: (-), used when damping is None.
        nominal_load: wheel load (N) for the default damping; None = total model mass x g /
            number of wheels.
        every: compute forces every k-th call and hold them in between (speed; 1 = each call).
        v_eps: speed scale (m/s) regularising slip and fading rolling resistance at rest.
        disable_contact: switch off the wheels' rigid contacts.
        refresh: recompute kinematics and velocities (mj_kinematics, mj_comPos, mj_comVel)
            for the current state before each force evaluation. Without it the forces use
            ``xpos``/``cvel`` that ``mj_step`` left behind, which are one step old (mj_step
            integrates after its forward pass); with a 1 ms step the difference is below the
            tests' tolerances and refresh costs extra time per call.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, wheels: Sequence[str | int],
                 wheel: WheelParams, soil: SoilParams | SoilTable, ground: Ground | None = None, *,
                 damping: float | None = None, damping_ratio: float = 1.0,
                 nominal_load: float | None = None, every: int = 1, v_eps: float = 0.02,
                 disable_contact: bool = True, refresh: bool = False):
        if every < 1:
            raise ValueError(f"every={every!r} is invalid; valid range: integer >= 1")
        if v_eps <= 0:
            raise ValueError(f"v_eps={v_eps!r} is invalid; valid range: v_eps > 0 m/s")
        self.table = soil if isinstance(soil, SoilTable) else SoilTable(soil, wheel)
        if self.table.wheel != wheel:
            raise ValueError("the SoilTable was built for a different wheel")
        self.wheel, self.soil = wheel, self.table.soil
        self.ground = ground or flat_ground()
        self.bodies = _body_ids(model, wheels)
        self.roots = model.body_rootid[self.bodies]
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
        if damping < 0:
            raise ValueError(f"damping={damping!r} is invalid; valid range: damping >= 0 N s/m")
        self.damping = float(damping)
        if disable_contact:
            disable_rigid_contact(model, self.bodies)
        self.refresh = bool(refresh)
        self._model = model
        mujoco.mj_forward(model, data)  # valid xpos/xmat/cvel for the first call
        self._calls = 0
        self._wrench = np.zeros((self.n, 6))
        self.truth: dict[str, np.ndarray] = {k: np.zeros(self.n) for k in
                                             ("sinkage", "slip", "lateral_slip", "W", "DP", "T", "Fy", "Fn")}

    def before_substep(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Compute (every ``every``-th call) and write the soil wrench of each wheel."""
        if self._calls % self.every == 0:
            if self.refresh:
                mujoco.mj_kinematics(model, data)
                mujoco.mj_comPos(model, data)
                mujoco.mj_comVel(model, data)
            self._wrench = self._compute(data)
            data.xfrc_applied[self.bodies] = self._wrench
        self._calls += 1

    def _compute(self, data: mujoco.MjData) -> np.ndarray:
        # np.cross costs ~15 us per call on small arrays: cross products are written out.
        r = self.wheel.radius
        b = self.bodies
        p = data.xpos[b]
        a = data.xmat[b][:, 1::3]  # body y axis (axle) in world: column 1 of each xmat
        cvel = data.cvel[b]
        w, lin = cvel[:, :3], cvel[:, 3:]
        rel = p - data.subtree_com[self.roots]
        v = lin + _cross(w, rel)
        zg, nrm = self.ground(p[:, 0], p[:, 1])
        f = _cross(a, nrm)
        f /= np.sqrt((f * f).sum(1))[:, None]
        lat = _cross(nrm, f)
        sink = r - (p[:, 2] - zg) * nrm[:, 2]
        vx = (v * f).sum(1)
        vy = (v * lat).sum(1)
        vn = (v * nrm).sum(1)
        rw = r * (w * a).sum(1)
        d = np.where(rw + vx >= 0, 1.0, -1.0)
        big = np.maximum(np.abs(rw), np.abs(vx))
        s = np.clip(d * (rw - vx) / np.maximum(big, self.v_eps), SLIP_MIN, SLIP_MAX)
        q = np.abs(vy) / np.maximum(np.abs(rw), self.v_eps)
        W, DP, T, Fy = self.table.lookup(sink, s, q)
        fade = np.minimum(big * (1.0 / self.v_eps), 1.0)
        Fn = np.maximum(W - self.damping * vn, 0.0) * (sink > 0)
        dpf = d * DP * fade
        tf = d * T * fade
        fy = -np.sign(vy) * Fy
        F_axle = Fn[:, None] * nrm + dpf[:, None] * f
        F_lat = fy[:, None] * lat
        arm = p - data.xipos[b]
        wrench = np.empty((self.n, 6))
        wrench[:, :3] = F_axle + F_lat
        wrench[:, 3:] = -tf[:, None] * a + _cross(arm, F_axle) + _cross(arm - r * nrm, F_lat)
        t = self.truth
        t["sinkage"], t["slip"], t["lateral_slip"] = sink, s, q
        t["W"], t["DP"], t["T"], t["Fy"], t["Fn"] = W, dpf, tf, Fy, Fn
        return wrench


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (N, 3) arrays."""
    out = np.empty_like(u)
    out[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    out[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    out[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return out
