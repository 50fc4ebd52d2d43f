"""Static stability margin: distance from the COG's ground projection to the support polygon.

Evaluation-only ground truth (the task computes it from MuJoCo contacts); controllers never see it.
"""

from __future__ import annotations

import collections
import math

import numba
import numpy as np

from terrabench.sim.pymath import hypot

#: from this many points :func:`_sorted_order` merges instead of inserting
MERGE_FROM = 16


@numba.njit(cache=True)
def _insertion_order(xs, ys):  # pragma: no cover
    """The indices of the points (xs, ys) by a stable insertion sort on (x, y): numpy's lexsort
    order, whatever the values (NaN included)."""
    n = xs.shape[0]
    order = np.arange(n)
    for a in range(1, n):
        j, b = a, order[a]
        while j > 0 and (xs[order[j - 1]] > xs[b] or (xs[order[j - 1]] == xs[b] and ys[order[j - 1]] > ys[b])):
            order[j] = order[j - 1]
            j -= 1
        order[j] = b
    return order


@numba.njit(cache=True)
def _sorted_order(xs, ys):  # pragma: no cover
    """The indices of the points (xs, ys) in stable (x, y) order: :func:`_insertion_order`'s (the
    hull's order before this helper; kept for short or NaN-holding inputs). Beyond MERGE_FROM
    points without NaN, a stable bottom-up merge sort: the ordering is then a strict weak one,
    whose stable sorted permutation is unique, so the same indices in O(n log n) rather than
    O(n^2) (tests/octopus/test_octopus_hull_sort.py checks it)."""
    n = xs.shape[0]
    finite = n >= MERGE_FROM
    if finite:
        for a in range(n):
            if xs[a] != xs[a] or ys[a] != ys[a]:
                finite = False
                break
    if not finite:
        return _insertion_order(xs, ys)
    src, dst = np.arange(n), np.empty(n, np.int64)
    width = 1
    while width < n:
        lo = 0
        while lo < n:
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i, j, k = lo, mid, lo
            while i < mid and j < hi:
                p, q = src[i], src[j]
                # the right one first only when strictly before the left one: stable
                if xs[q] < xs[p] or (xs[q] == xs[p] and ys[q] < ys[p]):
                    dst[k] = q
                    j += 1
                else:
                    dst[k] = p
                    i += 1
                k += 1
            while i < mid:
                dst[k] = src[i]
                i += 1
                k += 1
            while j < hi:
                dst[k] = src[j]
                j += 1
                k += 1
            lo = hi
        src, dst = dst, src
        width *= 2
    return src


@numba.njit(cache=True)
def _hull(xs, ys, out):  # pragma: no cover
    """Andrew's monotone chain over the n points (xs, ys), compiled: writes the counter-clockwise
    hull into ``out`` (2n, 2) and returns its length (collinear points dropped; fewer than three
    distinct points: those points, sorted)."""
    n = xs.shape[0]
    order = _sorted_order(xs, ys)
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


@numba.njit(cache=True)
def _margin_parts(pts, cx, cy):  # pragma: no cover
    """The margin's work, compiled: the hull of the points (:func:`_hull`), whether (cx, cy) is
    inside it, and the distance from (cx, cy) to the nearest point of the hull's edges; returns
    (hull length, inside, distance). The distance is the least ``hypot`` (Python's own algorithm,
    :func:`terrabench.sim.pymath.hypot`, so the margin keeps the bits of the all-Python version)
    of the offsets of the edges whose squared length is within 1e-9 (relative) of the least: an
    edge whose hypot is the least has a squared distance within ~1e-15 of the least (a hull
    vertex is the nearest point of both its edges, each computed its own way)."""
    n = pts.shape[0]
    hull, cand = np.empty((2 * n + 1, 2)), np.empty((2 * n + 1, 2))
    m = _hull(np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1]), hull)
    if m == 0:
        return 0, False, math.nan
    if m == 1:
        h = hypot(cx - hull[0, 0], cy - hull[0, 1])
        return 1, False, (h if h < math.inf else math.inf)  # Python's min(inf, h): NaN gives inf
    ne = 1 if m == 2 else m
    inside = m > 2
    best = math.inf
    for a in range(ne):
        b = a + 1 if a + 1 < m else 0
        ax, ay, bx, by = hull[a, 0], hull[a, 1], hull[b, 0], hull[b, 1]
        ex, ey = bx - ax, by - ay
        den = ex * ex + ey * ey
        u = 0.0
        if not den < 1e-18:
            t = ((cx - ax) * ex + (cy - ay) * ey) / den
            u = t if t > 0.0 else 0.0  # Python's max(0.0, t): NaN gives 0.0
            u = u if u < 1.0 else 1.0  # min(1.0, u)
        dx, dy = cx - ax - u * ex, cy - ay - u * ey
        cand[a, 0], cand[a, 1] = dx, dy
        sq = dx * dx + dy * dy
        if sq < best:
            best = sq
        if m > 2 and ex * (cy - ay) - ey * (cx - ax) < 0:
            inside = False
    d = math.inf
    for a in range(ne):
        dx, dy = cand[a, 0], cand[a, 1]
        if dx * dx + dy * dy <= best * (1.0 + 1e-9) + 1e-300:
            h = hypot(dx, dy)
            d = h if h < d else d  # Python's min(d, h)
    return m, inside, d


@numba.njit(cache=True)
def least_depth(support_xy, points_xy):  # pragma: no cover
    """The least signed distance (m) of the (k, 2) ``points_xy`` from the edge of the hull of the
    (n, 2) ``support_xy`` (positive inside): :func:`stability_margin` of each point, compiled in
    one call (the Fig. 7 property's reading; the support must span an area, n >= 3)."""
    best = math.inf
    for k in range(points_xy.shape[0]):
        m, inside, d = _margin_parts(support_xy, points_xy[k, 0], points_xy[k, 1])
        v = d if inside else -d
        if v < best:
            best = v
    return best


@numba.njit(cache=True)
def signed_margin(pts, cx, cy):  # pragma: no cover
    """:func:`stability_margin` of the (n, 2) float ``pts`` about (cx, cy), callable from compiled
    code (NaN without points)."""
    m, inside, d = _margin_parts(pts, cx, cy)
    if m == 0:
        return math.nan
    return d if inside else -d


def stability_margin(support_xy: np.ndarray, cog_xy: np.ndarray) -> float:
    """Signed distance (m) from ``cog_xy`` (2,) to the boundary of the hull of ``support_xy`` (n, 2).

    Positive inside, zero on an edge, negative outside (the distance to the nearest edge). Fewer
    than three non-collinear support points give no area: the margin is minus the distance to
    the points' hull (a segment or a point), i.e. never positive. Compiled (:func:`_margin_parts`).
    """
    pts = support_xy if isinstance(support_xy, np.ndarray) and support_xy.dtype == np.float64 else \
        np.asarray(support_xy, float)
    return signed_margin(pts.reshape(-1, 2), float(cog_xy[0]), float(cog_xy[1]))


class Footprint:
    """The support points of the last ``memory`` s: each stored row adds the ground points of its
    loaded contacts (:meth:`add`, rows in time order); :meth:`points` is the window, oldest
    first, as a view of one contiguous buffer (what a list of rows stacked would hold, without the
    stacking)."""

    def __init__(self, memory: float, capacity: int = 256):
        self.memory = memory
        self._buf = np.empty((capacity, 2))
        self._start = self._end = 0
        self._rows: collections.deque[tuple[float, int]] = collections.deque()  # (t, points) per row

    def add(self, t: float, pts: np.ndarray) -> None:
        """Row ``t``'s points (m, 2); rows older than ``memory`` (+1e-9) s before ``t`` leave."""
        rows = self._rows
        while rows and t - rows[0][0] > self.memory + 1e-9:
            self._start += rows.popleft()[1]
        m, n = len(pts), self._end - self._start
        if self._end + m > len(self._buf):  # move the window to the front, growing if it must
            buf = np.empty((max(len(self._buf), 2 * (n + m)), 2)) if n + m > len(self._buf) else self._buf
            buf[:n] = self._buf[self._start:self._end].copy()
            self._buf, self._start, self._end = buf, 0, n
        self._buf[self._end:self._end + m] = pts
        self._end += m
        rows.append((t, m))

    def points(self) -> np.ndarray:
        return self._buf[self._start:self._end]
