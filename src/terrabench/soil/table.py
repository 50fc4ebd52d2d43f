"""Precomputed (sinkage, slip) tables of the wheel-soil forces for the simulation loop.

One :class:`SoilTable` per (soil, wheel). Uniform grids: sinkage ``z`` in ``[0, r/2]``, slip
``s`` in ``[SLIP_MIN, 1]``, lateral slip ratio ``q`` in ``[0, q_max]``. Lookups are bilinear in
(z, s) (and linear in q for the lateral force), for N wheels at once with a handful of numpy
operations. Outside the grid: ``z <= 0`` gives zero force; ``z > r/2`` extrapolates W linearly
with the last cell's slope (so an overloaded wheel is still pushed up) and holds DP, T, Fy;
s and q are clamped (the forces saturate there anyway).

Accuracy against :func:`terrabench.soil.terramechanics.wheel_forces` with the default grid
(tests/soil/test_soil_table.py): |dW|, |dDP|, |dT/r|, |dFy| <= 1 % of the load at operating
points (load 30-300 N).
"""

from __future__ import annotations

import numpy as np

from terrabench.soil.terramechanics import SLIP_MAX, SLIP_MIN, SoilParams, WheelParams, max_sinkage, wheel_forces


class SoilTable:
    """Force tables of one wheel on one soil.

    Args:
        soil, wheel: the pair.
        nz: sinkage nodes on [0, r/2].  ns: slip nodes on [SLIP_MIN, 1].
        nq: lateral-slip nodes on [0, q_max].  q_max: (-).

    Attributes:
        data: (nz, ns, 3 + nq) array: W (N), DP (N), T (N m), then Fy (N) at each q node.
    """

    def __init__(self, soil: SoilParams, wheel: WheelParams, nz: int = 64, ns: int = 59,
                 nq: int = 21, q_max: float = 1.0):
        self.soil, self.wheel = soil, wheel
        self.nz, self.ns, self.nq = nz, ns, nq
        self.z_max = max_sinkage(wheel)
        self.z = np.linspace(0.0, self.z_max, nz)
        self.s = np.linspace(SLIP_MIN, SLIP_MAX, ns)
        self.q = np.linspace(0.0, q_max, nq)
        self.dz, self.ds, self.dq = self.z[1], self.s[1] - self.s[0], self.q[1]
        Z, S, Q = np.meshgrid(self.z, self.s, self.q, indexing="ij")
        f = wheel_forces(Z, S, soil, wheel, q=Q)
        data = np.empty((nz, ns, 3 + nq))
        data[..., 0] = f["W"][..., 0]
        data[..., 1] = f["DP"][..., 0]
        data[..., 2] = f["T"][..., 0]
        data[..., 3:] = f["Fy"]
        self.data = data
        self.dWdz_end = (data[-1, :, 0] - data[-2, :, 0]) / self.dz  # (ns,) extrapolation slope
        self._flat = data.reshape(nz * ns, 3 + nq)
        self._offsets = np.array([0, 1, ns, ns + 1])
        self._arange = np.arange(64)

    def lookup(self, z, s, q=None):
        """Interpolated forces for N wheels.

        Args:
            z: sinkage (m), shape (N,).  s: slip (-), (N,).  q: |v_y/(r omega)| (-), (N,) or None.

        Returns:
            W, DP, T, Fy: arrays (N,) (Fy is zeros when q is None).
        """
        z = np.asarray(z, float)
        fz = np.clip(z, 0.0, self.z_max) * (1.0 / self.dz)
        i = np.minimum(fz.astype(np.intp), self.nz - 2)
        tz = fz - i
        fs = (np.clip(s, SLIP_MIN, SLIP_MAX) - SLIP_MIN) * (1.0 / self.ds)
        j = np.minimum(fs.astype(np.intp), self.ns - 2)
        ts = fs - j
        # one gather of the 4 corner rows: (N, 4, 3 + nq)
        corners = self._flat[(i * self.ns + j)[:, None] + self._offsets]
        wts = np.stack(((1 - tz) * (1 - ts), (1 - tz) * ts, tz * (1 - ts), tz * ts), axis=1)
        row = np.einsum("nk,nkc->nc", wts, corners)
        on = z > 0
        over = np.maximum(z - self.z_max, 0.0)
        slope = (1 - ts) * self.dWdz_end[j] + ts * self.dWdz_end[j + 1]
        row[~on] = 0.0
        W = row[:, 0] + np.where(on, slope * over, 0.0)
        if q is None:
            return W, row[:, 1], row[:, 2], np.zeros_like(W)
        fq = np.minimum(np.abs(q), self.q[-1]) * (1.0 / self.dq)
        k = np.minimum(fq.astype(np.intp), self.nq - 2)
        tq = fq - k
        n = self._arange[: len(z)] if len(z) <= len(self._arange) else np.arange(len(z))
        Fy = (1 - tq) * row[n, 3 + k] + tq * row[n, 4 + k]
        return W, row[:, 1], row[:, 2], Fy

    def static_sinkage(self, load: float) -> float:
        """Sinkage (m) where the table's W(z, s=0) equals ``load`` (N)."""
        j = int(np.argmin(np.abs(self.s)))
        w = self.data[:, j, 0]
        if load > w[-1]:
            return float(self.z_max + (load - w[-1]) / self.dWdz_end[j])
        return float(np.interp(load, w, self.z))
