"""Minimal-cost motion planning on the energy landscape (paper Sec. II-H).

A directed graph joins every landscape node to its six neighbours (+-dx, +-dalpha, +-dbeta);
an edge costs the rise in potential energy (zero for a fall). Dijkstra (scipy's C
implementation) finds the cheapest path from the state after the sensory delay to the level pose
past the beams; the path gets 0.02 s per vertex and is fitted by one fifth-order polynomial per
coordinate. The shared ``terrabench.planning`` package had no landscape planner when this was
written, so it lives here.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from terrabench.config import param

from .landscape import Landscape


@dataclass(frozen=True)
class PlannerConfig:
    """Graph search and trajectory fit."""

    edge_epsilon: float = param(1e-7, gt=0,
                                doc="cost added to every edge, J (keeps zero-cost edges in the graph)")
    """Cost added to every edge, J: keeps zero-cost (falling) edges in the sparse graph and
    prefers the shortest of equally cheap paths; 300 edges add 0.03 mJ."""
    vertex_time: float = param(0.02, gt=0, unit="s", doc="Time between consecutive path vertices, s (paper)")
    """Time between consecutive path vertices, s (paper)."""
    poly_order: int = param(5, ge=1, doc="Order of the per-coordinate polynomial fit (paper: fifth)")
    """Order of the per-coordinate polynomial fit (paper: fifth)."""
    forbid_contact: bool = param(False, doc="Remove edges into poses touching a beam (the obstacle-avoidance baseline)")
    """Remove edges into poses touching a beam (the obstacle-avoidance baseline)."""
    target_x: float | None = param(None, unit="m", doc="x of the target level pose, m (None: the grid's last x)")
    """x of the target level pose, m (None: the grid's last x)."""


@lru_cache(maxsize=2)
def _edges(shape: tuple[int, int, int]) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols) of all six-neighbour edges of a grid, int32."""
    idx = np.arange(np.prod(shape), dtype=np.int64).reshape(shape)
    rows, cols = [], []
    for ax in range(3):
        a = [slice(None)] * 3
        b = [slice(None)] * 3
        a[ax], b[ax] = slice(0, -1), slice(1, None)
        i, j = idx[tuple(a)].ravel(), idx[tuple(b)].ravel()
        rows += [i, j]
        cols += [j, i]
    return np.concatenate(rows).astype(np.int32), np.concatenate(cols).astype(np.int32)


@dataclass
class Plan:
    """A planned path and its smooth trajectory."""

    path: np.ndarray
    """Path vertices (x, alpha, beta) in (m, rad, rad), shape (P, 3)."""
    cost: float
    """Sum of edge costs along the path (energy rises), J, epsilon included."""
    rise: float
    """Sum of the energy rises alone, J."""
    barrier: float
    """Highest energy along the path minus the start energy, J."""
    coeffs: np.ndarray
    """Polynomial coefficients per coordinate (highest power first), shape (3, order+1)."""
    duration: float
    """Time span of the path, s."""
    mode: str
    """"roll" if the path's largest |roll| exceeds its largest |pitch|, else "pitch"."""

    def desired(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Desired pose, velocity and acceleration at time ``t`` since the plan started.

        Past the end the final fitted pose is held with zero rates.
        """
        tc = min(max(t, 0.0), self.duration)
        q = np.array([np.polyval(c, tc) for c in self.coeffs])
        if t > self.duration or t < 0:
            return q, np.zeros(3), np.zeros(3)
        d1 = np.array([np.polyval(np.polyder(c), tc) for c in self.coeffs])
        d2 = np.array([np.polyval(np.polyder(c, 2), tc) for c in self.coeffs])
        return q, d1, d2


def plan_path(ls: Landscape, q_start, cfg: PlannerConfig = PlannerConfig()) -> Plan:
    """Dijkstra from the node nearest ``q_start`` to the level pose at the far end of the grid.

    Args:
        ls: the landscape (energies in J).
        q_start: start pose (x, alpha, beta), snapped to the nearest grid node.
        cfg: planner settings.

    Returns:
        The :class:`Plan`.

    Raises:
        ValueError: if no path exists (e.g. the start touches a beam in avoidance mode).
    """
    shape = ls.energy.shape
    rows, cols = _edges(shape)
    e = ls.energy.ravel()
    w = np.maximum(e[cols] - e[rows], 0.0) + cfg.edge_epsilon
    if cfg.forbid_contact:
        ok = ~ls.contact_mask().ravel()[cols]
        rows_, cols_, w = rows[ok], cols[ok], w[ok]
    else:
        rows_, cols_ = rows, cols
    n = e.size
    graph = csr_matrix((w, (rows_, cols_)), shape=(n, n))
    src = np.ravel_multi_index(ls.index(q_start), shape)
    xs = ls.grid.xs
    if cfg.target_x is None:
        tx = xs.size - 1
    else:
        tx = int(np.clip(np.rint((cfg.target_x - xs[0]) / ls.grid.dx), 0, xs.size - 1))
    mid = ls.grid.angles.size // 2
    dst = np.ravel_multi_index((tx, mid, mid), shape)
    dist, pred = dijkstra(graph, directed=True, indices=src, return_predecessors=True)
    if not np.isfinite(dist[dst]):
        raise ValueError(f"no path from pose {tuple(np.round(q_start, 4))} to the level pose at x = {xs[tx]:.3f} m "
                         "(start in contact while contact is forbidden?)")
    nodes = [dst]
    while nodes[-1] != src:
        nodes.append(pred[nodes[-1]])
    nodes = np.array(nodes[::-1])
    ix, ia, ib = np.unravel_index(nodes, shape)
    ang = ls.grid.angles
    path = np.column_stack([xs[ix], ang[ia], ang[ib]])
    ep = e[nodes]
    rise = float(np.maximum(np.diff(ep), 0).sum())
    t = cfg.vertex_time * np.arange(len(nodes))
    duration = float(t[-1]) if len(t) > 1 else cfg.vertex_time
    order = min(cfg.poly_order, max(len(nodes) - 1, 1))
    if len(nodes) > 1:
        coeffs = np.array([np.polyfit(t, path[:, j], order) for j in range(3)])
    else:
        coeffs = np.array([[path[0, j]] for j in range(3)])
    if coeffs.shape[1] < cfg.poly_order + 1:
        coeffs = np.pad(coeffs, ((0, 0), (cfg.poly_order + 1 - coeffs.shape[1], 0)))
    mode = "roll" if np.abs(path[:, 1]).max() > np.abs(path[:, 2]).max() else "pitch"
    return Plan(path, float(dist[dst]), rise, float(ep.max() - ep[0]), coeffs, duration, mode)
