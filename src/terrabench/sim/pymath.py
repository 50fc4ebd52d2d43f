"""Python's own float functions, compiled: the same bits inside a numba kernel as in plain Python.

Most of :mod:`math` is a thin call into the C library, and a numba kernel calls the same C library
(``sin``, ``cos``, ``atan2``, ``acos``, ``sqrt``: 0 of 30 M random arguments differ, with the pins of
:mod:`terrabench.portable`). ``math.hypot`` is not: CPython computes it with its own algorithm
(``vector_norm`` in ``Modules/mathmodule.c``: the coordinates scaled by a power of two, squared and
summed in double length, a square root and one differential correction), while numba's
``math.hypot`` is libm's, which differs in the last bit on 0.7 % of random pairs. A kernel that
must keep the bits of a Python reference (a stored trial's columns) calls :func:`hypot` here.

Every operation below is an IEEE-754 add, multiply, divide or square root, or an exact power-of-two
scaling, so the result is the same on every x86-64 CPU (numba is pinned to plain x86-64 by
``NUMBA_CPU_NAME=generic``, and LLVM does not contract a multiply and an add into an FMA without
fast-math). ``tests/sim/test_pymath.py`` compares it with the running interpreter's ``math.hypot``
on tens of millions of pairs across magnitudes, signs, zeros, subnormals, infinities and NaN.
"""

from __future__ import annotations

import math

import numba

_VELTKAMP = 134217729.0  # 2 ** 27 + 1: splits a double into two halves of 26 bits


@numba.njit(cache=True, inline="always")
def _two_product(x, y):  # pragma: no cover
    """(p, e) with p + e = x y exactly (Dekker's product of Veltkamp-split halves)."""
    t = x * _VELTKAMP
    xh = t - (t - x)
    xl = x - xh
    t = y * _VELTKAMP
    yh = t - (t - y)
    yl = y - yh
    p = xh * yh
    q = xh * yl + xl * yh
    z = p + q
    return z, p - z + q + xl * yl


@numba.njit(cache=True)
def _norm2(a, b, big):  # pragma: no cover
    """sqrt(a^2 + b^2) for finite a, b >= 0 with big = max(a, b) > 0, Python's way: scaled so the
    larger is in [0.5, 1), the squares summed in double length onto a running 1.0, then one
    Newton step on the residual."""
    _, e = math.frexp(big)
    if e < -1023:  # 2 ** -e would overflow (big < 2 ** -1024, a subnormal): divided by big instead
        acc, lo = 1.0, 0.0
        for v in (a, b):
            v /= big
            v = v * v
            s = acc + v
            lo += (acc - s) + v
            acc = s
        return big * math.sqrt(acc - 1.0 + lo)
    scale = math.ldexp(1.0, -e)
    acc, lo1, lo2 = 1.0, 0.0, 0.0
    for v in (a, b):
        v *= scale
        p, pe = _two_product(v, v)
        s = acc + p
        lo2 += (acc - s) + p
        acc = s
        lo1 += pe
    h = math.sqrt(acc - 1.0 + (lo1 + lo2))
    p, pe = _two_product(-h, h)
    s = acc + p
    lo2 += (acc - s) + p
    acc = s
    lo1 += pe
    r = acc - 1.0 + (lo1 + lo2)
    h += r / (2.0 * h)
    return h / scale


@numba.njit(cache=True)
def hypot(x, y):  # pragma: no cover
    """``math.hypot(x, y)`` of CPython 3.11 bit for bit, compiled (see the module's note)."""
    a, b = abs(x), abs(y)
    if math.isinf(a) or math.isinf(b):
        return math.inf
    if math.isnan(a) or math.isnan(b):
        return math.nan
    big = a if a > b else b
    if big == 0.0:
        return big
    return _norm2(a, b, big)
