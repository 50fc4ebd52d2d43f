"""Static stability margin: distance from the COG's ground projection to the support polygon.

Evaluation-only ground truth (the task computes it from MuJoCo contacts); controllers never see it.
"""

from __future__ import annotations

import math

import numpy as np


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise hull (m, 2) of (n, 2) points (Andrew's monotone chain); collinear dropped.

    Plain-float loop over the (few) sorted points: the contact sets here have 4-40 points, where
    numpy's per-call overhead would dominate.
    """
    pts = np.asarray(points, float).reshape(-1, 2)
    if len(pts) == 0:
        return pts
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    ps = [tuple(p) for p in pts[order].tolist()]
    # drop exact duplicates (sorted, so they are adjacent)
    uniq = [ps[0]]
    for p in ps[1:]:
        if p != uniq[-1]:
            uniq.append(p)
    if len(uniq) < 3:
        return np.array(uniq)

    def half(seq):
        out: list = []
        for p in seq:
            while len(out) >= 2:
                (ox, oy), (ax, ay) = out[-2], out[-1]
                if (ax - ox) * (p[1] - oy) - (ay - oy) * (p[0] - ox) <= 1e-12:
                    out.pop()
                else:
                    break
            out.append(p)
        return out

    lower, upper = half(uniq), half(uniq[::-1])
    return np.array(lower[:-1] + upper[:-1])


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
