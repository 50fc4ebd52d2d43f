"""The compiled Python hypot (terrabench.sim.pymath) gives CPython's own bits."""

import math

import numba
import numpy as np

from terrabench.sim.pymath import hypot


@numba.njit(cache=True)
def _ours(x, y, out):
    for i in range(x.shape[0]):
        out[i] = hypot(x[i], y[i])


@numba.njit(cache=True)
def _libm(x, y, out):
    for i in range(x.shape[0]):
        out[i] = math.hypot(x[i], y[i])


def _pythons(x, y):
    return np.array([math.hypot(a, b) for a, b in zip(x.tolist(), y.tolist())])


def _differ(a, b):
    return int((~((a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b)))).sum())


def _pairs(rng, n):
    """Pairs across magnitudes (normal, scaled apart by up to 16 decades, and at random binary
    exponents from the subnormals to the largest doubles), both signs."""
    e1 = rng.integers(-1074, 1024, n)
    e2 = np.clip(e1 + rng.integers(-60, 60, n), -1074, 1023)
    sign = rng.choice([-1.0, 1.0], n)
    xs = [rng.normal(size=n), rng.uniform(-2, 2, n), np.ldexp(rng.uniform(0.5, 1, n), e1) * sign]
    ys = [rng.normal(size=n), rng.uniform(-2, 2, n) * 10.0 ** rng.integers(-8, 8, n),
          np.ldexp(rng.uniform(0.5, 1, n), e2)]
    return np.concatenate(xs), np.concatenate(ys)


def test_hypot_is_pythons_bit_for_bit():
    rng = np.random.default_rng(7)
    x, y = _pairs(rng, 100_000)
    specials = [0.0, -0.0, 5e-324, 2.2250738585072014e-308, 1e-310, 1.7976931348623157e308, math.inf,
                -math.inf, math.nan, 1.0, 3.0, 4.0, -4.0]
    x = np.concatenate([x, np.repeat(specials, len(specials))])
    y = np.concatenate([y, np.tile(specials, len(specials))])
    ours = np.empty_like(x)
    _ours(x, y, ours)
    assert _differ(ours, _pythons(x, y)) == 0


def test_the_check_tells_libms_hypot_apart():
    """The comparison above can fail: libm's hypot (numba's ``math.hypot``) is not Python's."""
    x, y = _pairs(np.random.default_rng(8), 100_000)
    libm = np.empty_like(x)
    _libm(x, y, libm)
    assert _differ(libm, _pythons(x, y)) > 100
