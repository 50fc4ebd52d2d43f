"""Static stability margin: distance from the COG's ground projection to the support polygon.

Evaluation-only ground truth (the task computes it from MuJoCo contacts); controllers never see it.
"""

from __future__ import annotations

import numpy as np


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise hull (m, 2) of (n, 2) points (Andrew's monotone chain); collinear dropped."""
    pts = np.unique(np.asarray(points, float).reshape(-1, 2), axis=0)
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 1e-12:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in pts[::-1]:
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 1e-12:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])


def stability_margin(support_xy: np.ndarray, cog_xy: np.ndarray) -> float:
    """Signed distance (m) from ``cog_xy`` (2,) to the boundary of the hull of ``support_xy`` (n, 2).

    Positive inside, zero on an edge, negative outside (the distance to the nearest edge). Fewer
    than three non-collinear support points give no area: the margin is minus the distance to
    the points' hull (a segment or a point), i.e. never positive.
    """
    hull = convex_hull(support_xy)
    c = np.asarray(cog_xy, float)
    if len(hull) == 0:
        return float("nan")
    if len(hull) < 3:
        if len(hull) == 1:
            return -float(np.linalg.norm(c - hull[0]))
        return -_seg_dist(c, hull[0], hull[1])
    dists = [_seg_dist(c, hull[i], hull[(i + 1) % len(hull)]) for i in range(len(hull))]
    d = min(dists)
    inside = all(_cross2(hull[(i + 1) % len(hull)] - hull[i], c - hull[i]) >= 0 for i in range(len(hull)))
    return d if inside else -d


def _cross2(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _seg_dist(p, a, b) -> float:
    ab = b - a
    t = float(np.clip(np.dot(p - a, ab) / max(np.dot(ab, ab), 1e-18), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + t * ab)))
