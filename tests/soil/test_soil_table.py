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
    # Random operating points: load 30-400 N, slip -1..1 (locked included), lateral ratio
    # C 0..1 and 0..5. Tolerances (fraction of the load): W 3 %, DP, T/r and Fy 1.5 %. Measured
    # with the default 65 x 81 x 41 grid: W <= 0.6 % on the classic presets and <= 2.2 % on the
    # two Mars presets (their theta_m and exponent move fast with slip); DP, T/r, Fy <= 1.05 %.
    sp, tb = pair
    rng = np.random.default_rng(1)
    load = rng.uniform(30, 400, 400)
    s = np.r_[rng.uniform(-1.0, 1.0, 398), -1.0, 1.0]
    q = np.r_[rng.uniform(0, 1.0, 200), rng.uniform(0, 5.0, 200)]
    z = solve_sinkage(load, s, sp, WHEEL, q)
    f = wheel_forces(z, s, sp, WHEEL, q=q)
    W, DP, T, Fy = tb.lookup(z, s, q)
    assert np.max(np.abs(W - f["W"]) / load) < 0.03
    assert np.max(np.abs(DP - f["DP"]) / load) < 0.015
    assert np.max(np.abs(T - f["T"]) / (load * WHEEL.radius)) < 0.015
    assert np.max(np.abs(Fy - f["Fy"]) / load) < 0.015


def test_table_edges(pair):
    sp, tb = pair
    W, DP, T, Fy = tb.lookup(np.array([-0.01, 0.0]), np.array([0.3, 0.3]), np.array([0.5, 0.5]))
    assert np.all(W == 0) and np.all(DP == 0) and np.all(T == 0) and np.all(Fy == 0)
    zm = tb.z_max
    assert zm == WHEEL.radius
    W2 = tb.lookup(np.array([zm, zm + 0.01]), np.zeros(2))[0]
    assert W2[1] > W2[0] > 0, "beyond the grid W keeps rising"
    assert tb.static_sinkage(100.0) == pytest.approx(float(solve_sinkage(100.0, 0.0, sp, WHEEL)), rel=0.005)
    # a wheel dragged sideways (C -> inf) is the last node, not an extrapolation
    z = float(solve_sinkage(100.0, 0.0, sp, WHEEL))
    direct = float(wheel_forces(z, 0.0, sp, WHEEL, q=1e9)["Fy"])
    assert tb.lookup([z], [0.0], [np.inf])[3][0] == pytest.approx(direct, rel=0.005)


def test_bad_grid_names_the_value():
    with pytest.raises(ValueError, match="nq=1"):
        SoilTable(SOILS["mars_soft"], WHEEL, nq=1)
