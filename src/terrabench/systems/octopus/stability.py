"""Static stability margin: distance from the COG's ground projection to the support polygon.

Evaluation-only ground truth (the task computes it from MuJoCo contacts); controllers never see it.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True)
def _hull(xs, ys, out):  # pragma: no cover
    """Andrew's monotone chain over the n points (xs, ys), compiled: writes the counter-clockwise
    hull into ``out`` (2n, 2) and returns its length (collinear points dropped; fewer than three
    distinct points: those points, sorted)."""
    n = xs.shape[0]
    order = np.arange(n)
    for a in range(1, n):  # stable insertion sort by (x, y): numpy's lexsort order
        j, b = a, order[a]
        while j > 0 and (xs[order[j - 1]] > xs[b] or (xs[order[j - 1]] == xs[b] and ys[order[j - 1]] > ys[b])):
            order[j] = order[j - 1]
            j -= 1
        order[j] = b
    ux, uy = np.empty(n), np.empty(n)
    m = 0
    for a in range(n):  # exact duplicates dropped (sorted, so adjacent)
        x, y = xs[order[a]], ys[order[a]]
        if m == 0 or x != ux[m - 1] or y != uy[m - 1]:
            ux[m], uy[m] = x, y
            m += 1
    if m < 3:
        for a in range(m):
            out[a, 0], out[a, 1] = ux[a], uy[a]
        return m
    h = 0
    for rev in (False, True):  # lower half, then upper half
        start = h
        for a in range(m):
            i = m - 1 - a if rev else a
            px, py = ux[i], uy[i]
            while h - start >= 2:
                ox, oy, ax, ay = out[h - 2, 0], out[h - 2, 1], out[h - 1, 0], out[h - 1, 1]
                if (ax - ox) * (py - oy) - (ay - oy) * (px - ox) <= 1e-12:
                    h -= 1
                else:
                    break
            out[h, 0], out[h, 1] = px, py
            h += 1
        h -= 1  # each half's last point starts the other half
    return h


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise hull (m, 2) of (n, 2) points (Andrew's monotone chain); collinear dropped."""
    pts = np.asarray(points, float).reshape(-1, 2)
    out = np.empty((2 * len(pts) + 1, 2))
    return out[:_hull(np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1]), out)]


def stability_margin(support_xy: np.ndarray, cog_xy: np.ndarray) -> float:
    """Signed distance (m) from ``cog_xy`` (2,) to the boundary of the hull of ``support_xy`` (n, 2).

    Positive inside, zero on an edge, negative outside (the distance to the nearest edge). Fewer
    than three non-collinear support points give no area: the margin is minus the distance to
    the points' hull (a segment or a point), i.e. never positive.
    """
    hull = convex_hull(support_xy)
    if len(hull) == 0:
        return float("nan")
    cx, cy = float(cog_xy[0]), float(cog_xy[1])
    pts = hull.tolist()
    if len(pts) == 1:
        return -math.hypot(cx - pts[0][0], cy - pts[0][1])
    if len(pts) == 2:
        return -_seg_dist(cx, cy, pts[0], pts[1])
    # plain floats over the (few) hull edges: numpy's per-call cost exceeds this arithmetic
    d, inside = math.inf, True
    for a, b in zip(pts, pts[1:] + pts[:1]):
        d = min(d, _seg_dist(cx, cy, a, b))
        if (b[0] - a[0]) * (cy - a[1]) - (b[1] - a[1]) * (cx - a[0]) < 0:
            inside = False
    return d if inside else -d


def _seg_dist(px: float, py: float, a, b) -> float:
    """Distance from (px, py) to the segment a-b."""
    ex, ey = b[0] - a[0], b[1] - a[1]
    den = ex * ex + ey * ey
    u = 0.0 if den < 1e-18 else min(1.0, max(0.0, ((px - a[0]) * ex + (py - a[1]) * ey) / den))
    return math.hypot(px - a[0] - u * ex, py - a[1] - u * ey)
