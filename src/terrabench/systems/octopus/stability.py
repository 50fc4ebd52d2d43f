"""Static stability margin: distance from the COG's ground projection to the support polygon.

Evaluation-only ground truth (the task computes it from MuJoCo contacts); controllers never see it.
"""

from __future__ import annotations

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
    c = np.asarray(cog_xy, float)
    if len(hull) == 0:
        return float("nan")
    if len(hull) == 1:
        return -float(np.hypot(*(c - hull[0])))
    if len(hull) == 2:
        return -float(_seg_dists(c, hull[:1], hull[1:])[0])
    a, b = hull, np.roll(hull, -1, axis=0)
    d = float(_seg_dists(c, a, b).min())
    e, w = b - a, c - a
    inside = bool((e[:, 0] * w[:, 1] - e[:, 1] * w[:, 0] >= 0).all())
    return d if inside else -d


def _seg_dists(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances from p (2,) to the segments a[i]-b[i] (k, 2) each."""
    ab, ap = b - a, p - a
    t = np.clip((ap * ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-18), 0.0, 1.0)
    q = a + t[:, None] * ab
    return np.hypot(p[0] - q[:, 0], p[1] - q[:, 1])
