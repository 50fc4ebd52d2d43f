"""The hull's sort (stability._sorted_order: a merge sort beyond MERGE_FROM points) is the stable
insertion sort it replaced, index for index, and the margins built on it keep their bits."""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.octopus.stability import (
    MERGE_FROM,
    _insertion_order,
    _margin_parts,
    _sorted_order,
    convex_hull,
)


def _cases(rng):
    for n in list(range(0, 3 * MERGE_FROM)) + [63, 64, 65, 100, 127, 128, 129, 200, 257]:
        for _ in range(12):
            kind = rng.integers(4)
            if kind == 0:  # distinct points
                pts = rng.normal(size=(n, 2))
            elif kind == 1:  # a few values: many ties in x, in y, exact duplicates
                pts = rng.integers(-2, 3, size=(n, 2)).astype(float) * 0.25
            elif kind == 2:  # zeros of both signs
                pts = rng.choice([-0.0, 0.0, 1.0, -1.0], size=(n, 2))
            else:  # duplicated rows of a footprint, shuffled
                base = rng.normal(size=(max(n // 4, 1), 2))
                pts = base[rng.integers(len(base), size=n)]
            yield np.ascontiguousarray(pts)
    for n in (MERGE_FROM, 40):  # NaN inputs keep the insertion sort
        pts = rng.normal(size=(n, 2))
        pts[rng.integers(n), rng.integers(2)] = np.nan
        yield pts


def test_merge_order_is_the_insertion_order():
    rng = np.random.default_rng(11)
    for pts in _cases(rng):
        xs, ys = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
        assert np.array_equal(_sorted_order(xs, ys), _insertion_order(xs, ys))
        if len(pts) and not np.isnan(pts).any():
            assert np.array_equal(_sorted_order(xs, ys), np.lexsort((ys, xs)))


def _same(a: float, b: float) -> bool:
    return (math.isnan(a) and math.isnan(b)) or (a == b and math.copysign(1.0, a) == math.copysign(1.0, b))


def test_hull_and_margin_bits_on_the_insertion_order():
    """The hull from the insertion order (the points presorted by it, which both sorts leave in
    place) is the hull now; the margin likewise, bit for bit."""
    rng = np.random.default_rng(12)
    for pts in _cases(rng):
        if np.isnan(pts).any():
            continue
        xs, ys = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
        pre = np.ascontiguousarray(pts[_insertion_order(xs, ys)])
        h, h_pre = convex_hull(pts), convex_hull(pre)
        assert np.array_equal(h, h_pre) and np.array_equal(np.signbit(h), np.signbit(h_pre))
        for c in rng.normal(size=(3, 2)):
            m, inside, d = _margin_parts(pts, float(c[0]), float(c[1]))
            m2, inside2, d2 = _margin_parts(pre, float(c[0]), float(c[1]))
            assert (m, inside) == (m2, inside2) and _same(d, d2)
