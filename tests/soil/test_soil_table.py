"""The lookup table against the direct integral."""

import numpy as np
import pytest

from terrabench.soil.presets import HIT_MRII_WHEEL, SOILS
from terrabench.soil.table import SoilTable
from terrabench.soil.terramechanics import solve_sinkage, wheel_forces

WHEEL = HIT_MRII_WHEEL


@pytest.fixture(scope="module", params=list(SOILS.values()), ids=lambda s: s.name)
def pair(request):
    return request.param, SoilTable(request.param, WHEEL)


def test_table_matches_integral(pair):
    # Tolerance: W, DP, T/r within 0.5 % of the load, Fy within 1.5 % of the load, at random
    # operating points (load 30-300 N, slip -0.9..1, q 0..1). Measured: <= 0.3 % and <= 1 %.
    sp, tb = pair
    rng = np.random.default_rng(1)
    load = rng.uniform(30, 300, 300)
    s = rng.uniform(-0.9, 1.0, 300)
    q = rng.uniform(0, 1.0, 300)
    z = solve_sinkage(load, s, sp, WHEEL)
    f = wheel_forces(z, s, sp, WHEEL, q=q)
    W, DP, T, Fy = tb.lookup(z, s, q)
    assert np.max(np.abs(W - f["W"]) / load) < 0.005
    assert np.max(np.abs(DP - f["DP"]) / load) < 0.005
    assert np.max(np.abs(T - f["T"]) / (load * WHEEL.radius)) < 0.005
    assert np.max(np.abs(Fy - f["Fy"]) / load) < 0.015


def test_table_edges(pair):
    sp, tb = pair
    W, DP, T, Fy = tb.lookup(np.array([-0.01, 0.0]), np.array([0.3, 0.3]), np.array([0.5, 0.5]))
    assert np.all(W == 0) and np.all(DP == 0) and np.all(T == 0) and np.all(Fy == 0)
    zm = tb.z_max
    W2 = tb.lookup(np.array([zm, zm + 0.01]), np.zeros(2))[0]
    assert W2[1] > W2[0] > 0, "beyond the grid W keeps rising"
    assert tb.static_sinkage(100.0) == pytest.approx(float(solve_sinkage(100.0, 0.0, sp, WHEEL)), rel=0.005)
