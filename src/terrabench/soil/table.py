"""Precomputed (sinkage, slip, lateral ratio) tables of the wheel-soil forces for the simulation loop.

One :class:`SoilTable` per (soil, wheel). Uniform grids: sinkage ``z`` in ``[0, r]``, slip ``s``
in ``[-1, 1]``, and ``p = C / (1 + C)`` in ``[0, 1]`` for the lateral ratio ``C = |v_y| /
max(r omega, v_x)`` (so a wheel dragged sideways, C -> inf, is the last node). The combined shear
couples all four outputs (W, DP, T, Fy) to C, so each is tabulated on the full 3-D grid and looked
up trilinearly by a compiled kernel (:func:`lookup_one`, also used inside the MuJoCo coupling).
Outside the grid: ``z <= 0`` gives zero force; ``z > r`` extrapolates W linearly with the last
cell's slope (an overloaded wheel is still pushed up) and holds DP, T, Fy.

Accuracy against :func:`terrabench.soil.terramechanics.wheel_forces` with the default grid is
checked in tests/soil/test_soil_table.py.
"""

from __future__ import annotations

import functools

import numba
import numpy as np

from terrabench.soil.terramechanics import (
    _GL_W,
    _GL_X,
    SLIP_MAX,
    SLIP_MIN,
    SoilParams,
    WheelParams,
    _many,
    max_sinkage,
    pack,
)


@numba.njit(cache=True, inline="always")
def lookup_one(z, s, C, tab, dwdz, tp):
    """(W, DP, T, Fy) at one state. ``tp = [z_max, 1/dz, 1/ds, 1/dp]``; tab (nz, ns, np, 4)."""
    nz, ns, npp = tab.shape[0], tab.shape[1], tab.shape[2]
    if z <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    zc = min(z, tp[0])
    fz = zc * tp[1]
    i = min(int(fz), nz - 2)
    tz = fz - i
    sc = min(max(s, SLIP_MIN), SLIP_MAX)
    fs = (sc - SLIP_MIN) * tp[2]
    j = min(int(fs), ns - 2)
    ts = fs - j
    p = C / (1.0 + C) if C < 1e12 else 1.0
    fp = p * tp[3]
    k = min(int(fp), npp - 2)
    tq = fp - k
    out0 = 0.0
    out1 = 0.0
    out2 = 0.0
    out3 = 0.0
    for di in range(2):
        wi = tz if di else 1.0 - tz
        for dj in range(2):
            wj = ts if dj else 1.0 - ts
            for dk in range(2):
                wk = tq if dk else 1.0 - tq
                w = wi * wj * wk
                row = tab[i + di, j + dj, k + dk]
                out0 += w * row[0]
                out1 += w * row[1]
                out2 += w * row[2]
                out3 += w * row[3]
    if z > tp[0]:
        slope = ((1 - ts) * ((1 - tq) * dwdz[j, k] + tq * dwdz[j, k + 1])
                 + ts * ((1 - tq) * dwdz[j + 1, k] + tq * dwdz[j + 1, k + 1]))
        out0 += slope * (z - tp[0])
    return out0, out1, out2, out3


@numba.njit(cache=True)
def _lookup_many(z, s, C, tab, dwdz, tp, out):
    for n in range(z.shape[0]):
        W, DP, T, Fy = lookup_one(z[n], s[n], C[n], tab, dwdz, tp)
        out[n, 0] = W
        out[n, 1] = DP
        out[n, 2] = T
        out[n, 3] = Fy


class SoilTable:
    """Force tables of one wheel on one soil.

    Args:
        soil, wheel: the pair.
        nz: sinkage nodes on [0, r] (>= 2).  ns: slip nodes on [-1, 1] (>= 2).
        nq: nodes of p = C/(1 + C) on [0, 1] (>= 2).

    Attributes:
        data: (nz, ns, nq, 4) array: W (N), DP (N), T (N m), Fy (N).
    """

    def __init__(self, soil: SoilParams, wheel: WheelParams, nz: int = 65, ns: int = 81, nq: int = 41):
        for name, v in (("nz", nz), ("ns", ns), ("nq", nq)):
            if int(v) < 2:
                raise ValueError(f"{name}={v!r} is invalid; valid range: integer >= 2")
        self.soil, self.wheel = soil, wheel
        self.nz, self.ns, self.nq = int(nz), int(ns), int(nq)
        self.z_max = max_sinkage(wheel)
        self.z = np.linspace(0.0, self.z_max, nz)
        self.s = np.linspace(SLIP_MIN, SLIP_MAX, ns)
        self.p = np.linspace(0.0, 1.0, nq)
        with np.errstate(divide="ignore"):
            self.q = np.where(self.p < 1, self.p / np.maximum(1 - self.p, 1e-300), np.inf)
        Z, S, Q = np.meshgrid(self.z, self.s, np.minimum(self.q, 1e9), indexing="ij")
        out = np.empty((Z.size, 4))
        _many(Z.ravel(), S.ravel(), Q.ravel(), pack(soil, wheel), _GL_X, _GL_W, out)
        self.data = np.ascontiguousarray(out.reshape(nz, ns, nq, 4))
        dz = self.z[1]
        self.dWdz_end = np.ascontiguousarray((self.data[-1, :, :, 0] - self.data[-2, :, :, 0]) / dz)
        self.params = np.array([self.z_max, 1.0 / dz, 1.0 / (self.s[1] - self.s[0]), 1.0 / self.p[1]])

    def lookup(self, z, s, q=None):
        """Interpolated forces for N wheels.

        Args:
            z: sinkage (m), (N,).  s: slip (-), (N,).  q: lateral ratio C (-), (N,) or None (= 0).

        Returns:
            W, DP, T, Fy: arrays (N,).
        """
        z = np.ascontiguousarray(np.atleast_1d(np.asarray(z, float)))
        s = np.ascontiguousarray(np.broadcast_to(np.asarray(s, float), z.shape))
        if q is None:
            C = np.zeros_like(z)
        else:
            C = np.ascontiguousarray(np.abs(np.broadcast_to(np.asarray(q, float), z.shape)))
        out = np.empty((z.size, 4))
        _lookup_many(z, s, C, self.data, self.dWdz_end, self.params, out)
        return out[:, 0], out[:, 1], out[:, 2], out[:, 3]

    def static_sinkage(self, load: float) -> float:
        """Sinkage (m) where the table's W(z, s=0, C=0) equals ``load`` (N)."""
        j = int(np.argmin(np.abs(self.s)))
        w = self.data[:, j, 0, 0]
        if load > w[-1]:
            return float(self.z_max + (load - w[-1]) / self.dWdz_end[j, 0])
        return float(np.interp(load, w, self.z))


@functools.lru_cache(maxsize=16)
def cached_table(soil, wheel) -> SoilTable:
    """The look-up table of a (soil, wheel) pair, built once per process (both are frozen)."""
    return SoilTable(soil, wheel)
