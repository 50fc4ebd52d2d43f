"""A* on an 8-connected grid with precomputed per-direction edge costs.

The caller supplies, for each of the 8 moves, an array of the cost of leaving every cell in
that direction (``inf`` = forbidden). The heuristic is the Euclidean distance in cells times
a lower bound on the cost per cell, so the search is admissible and returns an optimal path.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

#: The 8 moves (di, dj) and their lengths in cells.
MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1))
MOVE_LENGTH = tuple(math.hypot(di, dj) for di, dj in MOVES)


def astar(
    edge_cost: np.ndarray,
    start: tuple[int, int],
    goal: tuple[int, int],
    min_cost_per_cell: float,
) -> list[tuple[int, int]]:
    """Cheapest 8-connected path from ``start`` to ``goal``.

    Args:
        edge_cost: shape (8, ni, nj); ``edge_cost[k, i, j]`` is the cost of the move
            ``MOVES[k]`` out of cell (i, j); must be >= ``min_cost_per_cell * MOVE_LENGTH[k]``.
        start, goal: cell indices.
        min_cost_per_cell: lower bound of cost per cell of travel (for the heuristic).

    Returns:
        The cells from start to goal inclusive. Raises ValueError if the goal is unreachable.
    """
    _, ni, nj = edge_cost.shape
    for name, c in (("start", start), ("goal", goal)):
        if not (0 <= c[0] < ni and 0 <= c[1] < nj):
            raise ValueError(f"{name} cell {c} is outside the {ni} x {nj} grid")
    gi, gj = goal
    h = lambda i, j: min_cost_per_cell * math.hypot(i - gi, j - gj)  # noqa: E731
    best = np.full((ni, nj), np.inf)
    parent = np.full((ni, nj, 2), -1, dtype=np.int64)
    best[start] = 0.0
    heap = [(h(*start), 0.0, start)]
    cost = edge_cost.tolist()  # python floats: much faster to index in the loop
    while heap:
        _, g, (i, j) = heapq.heappop(heap)
        if (i, j) == goal:
            break
        if g > best[i, j]:
            continue
        for k, (di, dj) in enumerate(MOVES):
            a, b = i + di, j + dj
            if 0 <= a < ni and 0 <= b < nj:
                ng = g + cost[k][i][j]
                if ng < best[a, b]:
                    best[a, b] = ng
                    parent[a, b] = (i, j)
                    heapq.heappush(heap, (ng + h(a, b), ng, (a, b)))
    if not math.isfinite(best[goal]):
        raise ValueError(f"goal {goal} is unreachable from {start} under the given costs")
    path = [goal]
    while path[-1] != start:
        path.append(tuple(int(v) for v in parent[path[-1]]))
    return path[::-1]


def simplify(points: np.ndarray, tolerance: float) -> np.ndarray:
    """Douglas-Peucker simplification of a polyline (n, 2): keep points farther than ``tolerance``."""
    pts = np.asarray(points, float)
    if len(pts) < 3:
        return pts
    keep = np.zeros(len(pts), bool)
    keep[[0, -1]] = True
    stack = [(0, len(pts) - 1)]
    while stack:
        a, b = stack.pop()
        if b <= a + 1:
            continue
        seg = pts[b] - pts[a]
        rel = pts[a + 1 : b] - pts[a]
        norm = np.hypot(*seg)
        if norm == 0:
            d = np.hypot(rel[:, 0], rel[:, 1])
        else:
            d = np.abs(seg[0] * rel[:, 1] - seg[1] * rel[:, 0]) / norm
        k = int(np.argmax(d))
        if d[k] > tolerance:
            keep[a + 1 + k] = True
            stack += [(a, a + 1 + k), (a + 1 + k, b)]
    return pts[keep]


def polyline_deviation(a: np.ndarray, b: np.ndarray, samples: int = 400) -> float:
    """Mean distance from points sampled evenly along polyline ``a`` to polyline ``b`` (m)."""
    return float(np.mean(_points_to_polyline(resample(a, samples), np.asarray(b, float))))


def resample(poly: np.ndarray, n: int) -> np.ndarray:
    poly = np.asarray(poly, float)
    seg = np.hypot(*np.diff(poly, axis=0).T)
    s = np.concatenate([[0], np.cumsum(seg)])
    if s[-1] == 0:
        return np.repeat(poly[:1], n, axis=0)
    t = np.linspace(0, s[-1], n)
    return np.column_stack([np.interp(t, s, poly[:, 0]), np.interp(t, s, poly[:, 1])])


def _points_to_polyline(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance from each point, shape (n, 2), to the polyline ``poly`` (m, 2): shape (n,) (m)."""
    if len(poly) == 1:
        return np.hypot(*(pts - poly[0]).T)
    a, ab = poly[:-1], np.diff(poly, axis=0)
    l2 = (ab**2).sum(axis=1)
    rel = pts[:, None, :] - a[None]  # (n, segments, 2): all pairs at once, no Python loop
    t = np.clip((rel * ab).sum(axis=-1) / np.where(l2 == 0, 1, l2), 0, 1)
    off = rel - t[..., None] * ab
    return np.hypot(off[..., 0], off[..., 1]).min(axis=1)
