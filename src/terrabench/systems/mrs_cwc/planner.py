"""Our A* waypoint planner for the MRS-CWC map-based methods.

The paper says its A* cost "trades forward slope against tipping risk" but did not release
it. Ours, per move of length ``ds`` from cell a to cell b on a grid of spacing 0.1475 m (the
released waypoints' grid):

    cost = ds * (1 + w_climb * max(0, tan theta_f)^2 + w_descent * max(0, -tan theta_f)^2
                   + w_tip * tan(theta_lat)^2)

with theta_f the slope along the move and theta_lat the cross slope (the height gradient
perpendicular to the move, at the move's midpoint). Moves steeper than ``max_slope_deg``
along, or ``max_cross_deg`` across, pay ``steep_penalty`` per metre on top. Every term is >= 0, so cost >= ds and the
Euclidean heuristic is admissible.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from terrabench.config import param
from terrabench.planning.astar import MOVE_LENGTH, MOVES, astar, simplify
from terrabench.terrain import sine_sum


@dataclass(frozen=True)
class PlannerConfig:
    """Cost terms of our A* (see module docstring)."""

    cell: float = param(0.1475, gt=0, unit="m",
                        doc="planning grid spacing; 0.1475 = 14.75 m / 100, like the released waypoints")
    w_climb: float = param(4.0, ge=0, doc="weight of squared uphill slope")
    w_descent: float = param(1.0, ge=0, doc="weight of squared downhill slope")
    w_tip: float = param(6.0, ge=0, doc="weight of squared cross slope (tipping risk of a 0.12 m track)")
    max_slope_deg: float = param(50.0, gt=0, le=90, unit="deg", doc="steepest allowed slope along a move")
    max_cross_deg: float = param(45.0, gt=0, le=90, unit="deg", doc="steepest allowed cross slope")
    steep_penalty: float = param(50.0, ge=0, doc="extra cost per metre of a move beyond either limit")
    simplify_tolerance: float = param(0.3, ge=0, unit="m", doc="Douglas-Peucker tolerance of the waypoint list")
    max_spacing: float = param(2.5, gt=0, unit="m", doc="longest allowed distance between consecutive waypoints")


def height_map(terrain, cell: float):
    """Heights on a regular planning grid covering the terrain: (x (ni,), y (nj,), h (ni, nj))."""
    p = terrain.params
    vx, vy = sine_sum.vertex_xy(p)
    interp = RegularGridInterpolator((vx, vy[::-1]), sine_sum.heights(p)[:, ::-1])
    x = np.arange(vx[0], vx[-1] + 1e-9, cell).clip(vx[0], vx[-1])
    y = np.arange(vy[-1], vy[0] + 1e-9, cell).clip(vy[-1], vy[0])
    X, Y = np.meshgrid(x, y, indexing="ij")
    return x, y, interp(np.stack([X, Y], axis=-1))


def edge_costs(h: np.ndarray, cell: float, cfg: PlannerConfig) -> np.ndarray:
    """Per-direction move costs, shape (8, ni, nj); inf where forbidden or off-grid."""
    gx, gy = np.gradient(h, cell)
    ni, nj = h.shape
    out = np.full((8, ni, nj), np.inf)
    tmax_f = math.tan(math.radians(cfg.max_slope_deg))
    tmax_c = math.tan(math.radians(cfg.max_cross_deg))
    for k, ((di, dj), length) in enumerate(zip(MOVES, MOVE_LENGTH)):
        ds = length * cell
        src = (slice(max(0, -di), ni - max(0, di)), slice(max(0, -dj), nj - max(0, dj)))
        dst = (slice(max(0, di), ni - max(0, -di)), slice(max(0, dj), nj - max(0, -dj)))
        tan_f = (h[dst] - h[src]) / ds
        ux, uy = di / length, dj / length
        mgx = 0.5 * (gx[src] + gx[dst])
        mgy = 0.5 * (gy[src] + gy[dst])
        tan_c = -uy * mgx + ux * mgy
        c = ds * (1 + cfg.w_climb * np.maximum(tan_f, 0) ** 2 + cfg.w_descent * np.minimum(tan_f, 0) ** 2
                  + cfg.w_tip * tan_c**2)
        # too steep: not forbidden (a map may offer no fully safe route) but priced far above
        c[(np.abs(tan_f) > tmax_f) | (np.abs(tan_c) > tmax_c)] += ds * cfg.steep_penalty
        out[k][src] = c
    return out


def plan_path(terrain, start_xy, goal_xy, cfg: PlannerConfig = PlannerConfig()) -> np.ndarray:
    """The cheapest path as world XY points, shape (n, 2), from start to goal (m)."""
    x, y, h = height_map(terrain, cfg.cell)
    costs = edge_costs(h, cfg.cell, cfg)
    cell_of = lambda p: (int(round((p[0] - x[0]) / cfg.cell)), int(round((p[1] - y[0]) / cfg.cell)))  # noqa: E731
    cells = astar(costs, cell_of(start_xy), cell_of(goal_xy), min_cost_per_cell=cfg.cell)
    return np.array([(x[i], y[j]) for i, j in cells])


def waypoints_from_path(path: np.ndarray, goal_xy, cfg: PlannerConfig) -> np.ndarray:
    """Simplify a dense path into waypoints no farther apart than ``max_spacing``; end at the goal."""
    pts = simplify(path, cfg.simplify_tolerance)
    out = [pts[0]]
    for p in pts[1:]:
        gap = np.hypot(*(p - out[-1]))
        steps = int(math.ceil(gap / cfg.max_spacing))
        for s in range(1, steps + 1):
            out.append(out[-1] + (p - out[-1]) * (1 / (steps - s + 1)))
    out.append(np.asarray(goal_xy, float))
    return np.array(out)


def plan_waypoints(terrain, cfg) -> np.ndarray:
    """Waypoints for a trial config (``cfg`` is an :class:`MRSConfig`)."""
    pc = cfg.planner
    path = plan_path(terrain, cfg.protocol.start_xy, cfg.protocol.target_xy, pc)
    return waypoints_from_path(path, cfg.protocol.target_xy, pc)
