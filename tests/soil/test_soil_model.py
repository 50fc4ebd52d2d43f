"""Physics of the wheel-soil model (terramechanics.py, presets.py)."""

import dataclasses

import numpy as np
import pytest

from terrabench.soil.presets import DRY_SAND, HIT_MRII_WHEEL, LUNAR, MARS_SOFT, SOILS, soil
from terrabench.soil.terramechanics import (
    SoilParams,
    WheelParams,
    bekker_sinkage,
    kappa_from_slip,
    solve_sinkage,
    steady_state,
    wheel_forces,
)

WHEEL = HIT_MRII_WHEEL
PRESETS = list(SOILS.values())
#: the presets without slip-sinkage: their DP rises monotonically and saturates (with
#: slip-sinkage, mars_very_loose / mars_loose peak and fall: tests/soil/test_soil_physics.py)
CLASSIC = [MARS_SOFT, DRY_SAND, LUNAR]
LOAD = 100.0


@pytest.mark.parametrize("sp", PRESETS, ids=lambda s: s.name)
def test_integral_matches_bekker_closed_form(sp):
    # Bekker's formula: vertical pressure only, no shear, theta_m = theta_r = 0, parabola for
    # the rim. Same assumptions in the integral: c = 0, phi ~ 0, a0 = a1 = 0. Tolerance 3 %
    # for z/D <= 0.1 (measured: <= 1.5 % for n = 1; n = 1.1 adds Bekker's own series
    # approximation of the (3 - n)/3 factor, -1.3 %).
    pure = dataclasses.replace(sp, c=0.0, phi_deg=1e-4, a0=0.0, a1=0.0, c_exit=0.0, c_exit1=0.0, n1=0.0, n2=0.0)
    loads = np.array([5.0, 20.0, 50.0, 100.0])
    z = solve_sinkage(loads, 0.0, pure, WHEEL)
    zb = bekker_sinkage(loads, pure, WHEEL)
    assert np.all(z / (2 * WHEEL.radius) <= 0.1)
    np.testing.assert_allclose(z, zb, rtol=0.03)


@pytest.mark.parametrize("sp", CLASSIC, ids=lambda s: s.name)
def test_drawbar_pull_rises_and_saturates(sp):
    s = np.linspace(0.0, 0.95, 20)
    r = steady_state(LOAD, s, sp, WHEEL)
    dp = r["DP_N"]
    assert dp[0] < 0, "zero slip: rolling resistance"
    assert np.all(np.diff(dp) > 0)
    assert dp[-1] > 0
    low = np.interp(0.3, s, dp) - np.interp(0.1, s, dp)
    high = np.interp(0.95, s, dp) - np.interp(0.75, s, dp)
    assert high < 0.4 * low, "saturation at high slip"
    # Coulomb limit: thrust <= c A + W tan(phi)
    area = WHEEL.width * WHEEL.radius * np.pi / 3  # contact arc <= 60 deg (sinkage <= r/2)
    assert np.all(r["DP_coeff"] < sp.tan_phi + sp.c * area / LOAD)


@pytest.mark.parametrize("sp", PRESETS, ids=lambda s: s.name)
def test_torque_rises_with_slip_and_skid_brakes(sp):
    s = np.linspace(-0.8, 0.95, 30)
    r = steady_state(LOAD, s, sp, WHEEL)
    assert np.all(np.diff(r["torque_Nm"]) > 0)
    skid = s < 0
    assert np.all(r["DP_N"][skid] < 0)
    assert np.all(r["DP_N"][skid] < steady_state(LOAD, 0.0, sp, WHEEL)["DP_N"])
    assert r["torque_Nm"][0] < 0, "strong skid: the soil drives the wheel (braking torque)"


@pytest.mark.parametrize("sp", PRESETS, ids=lambda s: s.name)
def test_sinkage_rises_with_load_and_slip(sp):
    loads = np.array([30.0, 60.0, 120.0, 240.0])
    for s in (-0.3, 0.0, 0.3, 0.7):
        assert np.all(np.diff(solve_sinkage(loads, s, sp, WHEEL)) > 0)
    # slip sinkage in Wong-Reece comes only from the stress redistribution (theta_m moves
    # back, shear takes load): monotone from s ~ 0.2 on (docs/soil.md, limitations)
    slips = np.linspace(0.2, 0.95, 10)
    assert np.all(np.diff(solve_sinkage(LOAD, slips, sp, WHEEL)) > 0)


def test_stiffer_soil_sinks_less():
    stiff = dataclasses.replace(MARS_SOFT, k_phi=2 * MARS_SOFT.k_phi)
    for s in (0.0, 0.4):
        assert solve_sinkage(LOAD, s, stiff, WHEEL) < 0.7 * solve_sinkage(LOAD, s, MARS_SOFT, WHEEL)
    assert solve_sinkage(LOAD, 0.0, DRY_SAND, WHEEL) < solve_sinkage(LOAD, 0.0, MARS_SOFT, WHEEL)


def test_lateral_force_grows_with_slip_angle():
    z = solve_sinkage(LOAD, 0.2, MARS_SOFT, WHEEL)
    q = np.linspace(0, 1, 11)
    fy = wheel_forces(z, 0.2, MARS_SOFT, WHEEL, q=q)["Fy"]
    assert fy[0] == 0 and np.all(np.diff(fy) > 0)
    assert fy[-1] < 1.2 * LOAD


def test_slip_conventions():
    np.testing.assert_allclose(kappa_from_slip([0.0, 0.5, 1.0, -0.5, -1.0]), [1.0, 0.5, 0.0, 2.0, np.inf])
    for bad in (1.5, -1.01, np.nan):
        with pytest.raises(ValueError, match="slip"):
            kappa_from_slip(bad)


def test_efficiency_definition():
    r = steady_state(LOAD, 0.3, LUNAR, WHEEL, omega=2.0)
    v = 0.7 * WHEEL.radius * 2.0
    assert r["efficiency"] == pytest.approx(r["DP_N"] * v / (r["torque_Nm"] * 2.0))
    assert 0 < r["efficiency"] < 1 - 0.3 + 1e-9  # tractive efficiency <= (1 - s)


BAD_SOIL = [("n", 0.0), ("n", 3.5), ("k_c", -1.0), ("k_phi", 0.0), ("k_phi", -5.0), ("c", -1.0),
            ("phi_deg", 0.0), ("phi_deg", 90.0), ("phi_deg", -10.0), ("K", 0.0), ("K_y", -0.01),
            ("a0", -0.1), ("a0", 1.0), ("a1", -1.1), ("a1", 0.7), ("n1", 2.5), ("n2", -1.5), ("gamma", 0.0),
            ("bulldoze", -1.0), ("plough", 11.0), ("a1_skid", 1.5), ("c_exit", -0.1), ("c_exit", 1.5),
            ("k_phi", float("nan"))]


@pytest.mark.parametrize("field,value", BAD_SOIL)
def test_bad_soil_raises_naming_value(field, value):
    with pytest.raises(ValueError, match=f"'{field}' = ") as e:
        SoilParams(**{field: value})
    assert "valid:" in str(e.value)


@pytest.mark.parametrize("field,value", [("radius", 0.0), ("radius", -0.1), ("width", 0.0), ("mass", -1.0)])
def test_bad_wheel_raises_naming_value(field, value):
    with pytest.raises(ValueError, match=f"'{field}' = {value!r}"):
        WheelParams(**{field: value})


def test_bad_load_and_unknown_preset():
    with pytest.raises(ValueError, match="load="):
        solve_sinkage(-1.0, 0.0, MARS_SOFT, WHEEL)
    with pytest.raises(ValueError, match="load="):
        solve_sinkage(1e6, 0.0, MARS_SOFT, WHEEL)
    with pytest.raises(ValueError, match="mars_soft"):
        soil("mud")


# Reference: no published per-slip DP/W of a planetary simulant is quoted here (we could not
# recall one with confidence; docs/soil.md). The check is the well-known qualitative envelope
# of smooth rigid wheels on loose sand: negative DP/W at zero slip, zero crossing at small
# positive slip, concave rise, bounded well below tan(phi) by s = 0.6.
REF_SLIPS = (0.2, 0.4, 0.6)
#: Measured by this model at 100 N on the HIT-MRII-like wheel (regression pins, +-0.01).
PINNED = {"mars_soft": (-0.002, 0.084, 0.131), "dry_sand": (0.131, 0.211, 0.244),
          "lunar_regolith": (0.055, 0.155, 0.209)}


@pytest.mark.parametrize("sp", CLASSIC, ids=lambda s: s.name)
def test_dp_coefficient_envelope(sp):
    pc = steady_state(LOAD, np.array(REF_SLIPS), sp, WHEEL)["DP_coeff"]
    assert np.all(np.diff(pc) > 0)
    assert pc[2] - pc[1] < pc[1] - pc[0], "concave: gains shrink with slip"
    assert -0.1 < pc[0] and pc[2] < sp.tan_phi
    np.testing.assert_allclose(pc, PINNED[sp.name], atol=0.01)
