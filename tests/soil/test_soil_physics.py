"""Issue 18 physics: slip-sinkage, skid and the locked wheel, combined shear, Reece form, exit
angle, sinkage to the radius, bulldozing, and the two Mars-simulant presets."""

import dataclasses

import numpy as np
import pytest

from terrabench.soil.presets import HIT_MRII_WHEEL, MARS_LOOSE, MARS_SOFT, MARS_VERY_LOOSE, soil
from terrabench.soil.terramechanics import SoilParams, solve_sinkage, steady_state, wheel_forces

WHEEL = HIT_MRII_WHEEL
ROVER_LOAD = 225 * 9.81 / 6  # HIT-MRII: 225 kg on six wheels (spec srwmr.md)


def test_slip_dependent_exponent_sinks_the_wheel_as_it_slips():
    # n(s) = n + n1 s (driving), n + n2 |s| (skid): with n1, n2 > 0 the sinkage rises
    # monotonically away from s = 0 on both sides; without them (and without the theta_m shift)
    # it hardly moves. z < 1 m, so a larger exponent means softer soil.
    base = dataclasses.replace(MARS_SOFT, a1=0.0)
    ss = dataclasses.replace(base, n1=0.3, n2=0.3)
    drive = np.linspace(0.0, 0.9, 10)
    skid = np.linspace(0.0, -1.0, 11)
    z_flat = solve_sinkage(100.0, drive, base, WHEEL)
    z_d = solve_sinkage(100.0, drive, ss, WHEEL)
    z_s = solve_sinkage(100.0, skid, ss, WHEEL)
    assert np.all(np.diff(z_d) > 0) and np.all(np.diff(z_s) > 0)
    assert z_d[-1] / z_d[0] > 1.4
    assert abs(z_flat[-1] / z_flat[0] - 1) < 0.15
    np.testing.assert_allclose(ss.exponent([0.5, -0.5, 0.0]), [1.15, 1.15, 1.0])


def test_locked_wheel_is_finite_and_the_limit_of_skid():
    # The braked-wheel displacement j = r[(1 + s)(theta_1 - theta) - (sin theta_1 - sin theta)]
    # is finite at s = -1: no slip clip, the locked wheel is the limit of heavy skid.
    z = 0.03
    f_lock = wheel_forces(z, -1.0, MARS_LOOSE, WHEEL)
    f_near = wheel_forces(z, -0.999, MARS_LOOSE, WHEEL)
    for k in ("W", "DP", "T"):
        assert np.isfinite(f_lock[k])
        assert f_near[k] == pytest.approx(f_lock[k], rel=2e-3, abs=1e-6)
    assert f_lock["DP"] < 0 and f_lock["T"] < 0, "a locked wheel is braked and the soil turns it backwards"
    r = steady_state(ROVER_LOAD, np.array([-1.0, -0.5, 0.0]), MARS_LOOSE, WHEEL)
    assert r["DP_N"][0] < r["DP_N"][1] < r["DP_N"][2]
    assert r["omega_rps"][0] == 0.0 and r["v_mps"][0] == pytest.approx(WHEEL.radius)


def test_driving_and_skid_forms_meet_at_zero_slip():
    for sp in (MARS_SOFT, MARS_LOOSE):
        a = wheel_forces(0.03, 1e-9, sp, WHEEL, q=0.2)
        b = wheel_forces(0.03, -1e-9, sp, WHEEL, q=0.2)
        for k in ("W", "DP", "T", "Fy"):
            assert a[k] == pytest.approx(b[k], rel=1e-6)


def test_combined_shear_stays_inside_mohr_coulomb():
    # |(tau_x, tau_y)| <= c + sigma tan(phi) pointwise, so the resultant tangential force cannot
    # exceed the full strength integrated over the contact: sqrt((T/r)^2 + Fy^2) <= Fy(C -> inf)
    # (everything saturated sideways). The old independent shear gave 1.11x at beta 30
    # deg, slip 0.2. Sigma is made independent of slip and C (n1 = n2 = a1 = 0, no bulldozing)
    # so both sides see the same normal stress.
    sp = dataclasses.replace(MARS_SOFT, n1=0.0, n2=0.0, a1=0.0, a1_skid=0.0, bulldoze=0.0, plough=0.0)
    z = 0.03
    limit = wheel_forces(z, 0.2, sp, WHEEL, q=1e9)["Fy"]
    for s in (0.2, 0.5, 0.9):
        for beta in (15, 30, 45, 60):
            C = (1 - s) * np.tan(np.radians(beta))
            f = wheel_forces(z, s, sp, WHEEL, q=C)
            assert np.hypot(f["T"] / WHEEL.radius, f["Fy"]) <= limit * (1 + 1e-9)
    # and the lateral force takes strength from the longitudinal one
    t0 = wheel_forces(z, 0.2, sp, WHEEL, q=0.0)["T"]
    t30 = wheel_forces(z, 0.2, sp, WHEEL, q=0.8 * np.tan(np.radians(30)))["T"]
    assert t30 < t0


def test_reece_and_bekker_forms_convert_exactly():
    # sigma = (c k_c' + gamma b k_phi') (z/b)^n  ==  (k_c/b + k_phi) z^n for this width
    for sp in (MARS_SOFT, MARS_LOOSE):
        flat = dataclasses.replace(sp, n1=0.0, n2=0.0)
        reece = flat.to_reece(WHEEL.width)
        assert reece.form == "reece"
        k_b, L_b = flat.modulus(WHEEL.width)
        k_r, L_r = reece.modulus(WHEEL.width)
        for z in (0.01, 0.05):
            assert k_b * (z / L_b) ** sp.n == pytest.approx(k_r * (z / L_r) ** sp.n, rel=1e-12)
        back = reece.to_bekker(WHEEL.width)
        assert back.k_c == pytest.approx(flat.k_c) and back.k_phi == pytest.approx(flat.k_phi)
        fb = wheel_forces(0.04, 0.3, flat, WHEEL, q=0.1)
        fr = wheel_forces(0.04, 0.3, reece, WHEEL, q=0.1)
        for k in ("W", "DP", "T", "Fy"):
            assert fr[k] == pytest.approx(fb[k], rel=1e-9)
    with pytest.raises(ValueError, match="'form' = 'reese'"):
        SoilParams(form="reese")


def test_exit_angle_puts_contact_behind_the_axle():
    z = 0.03
    sp = dataclasses.replace(MARS_SOFT, c_exit=0.3)
    f0 = wheel_forces(z, 0.2, MARS_SOFT, WHEEL)
    f1 = wheel_forces(z, 0.2, sp, WHEEL)
    assert f0["theta_r"] == 0.0
    assert f1["theta_r"] == pytest.approx(-0.3 * f1["theta1"])
    assert f1["W"] > f0["W"], "the rear contact carries load"
    assert solve_sinkage(100.0, 0.2, sp, WHEEL) < solve_sinkage(100.0, 0.2, MARS_SOFT, WHEEL)


def test_sinkage_up_to_the_wheel_radius():
    # more than r/2 is allowed (measured sinkage can be larger); past r the solver refuses
    z = solve_sinkage(ROVER_LOAD, 0.9, MARS_VERY_LOOSE, WHEEL)
    assert 0.5 * WHEEL.radius < z < WHEEL.radius
    with pytest.raises(ValueError, match="beyond its radius"):
        solve_sinkage(5000.0, 0.0, MARS_VERY_LOOSE, WHEEL)


def test_sidewall_bulldozing_adds_lateral_force():
    z = 0.04
    no = dataclasses.replace(MARS_LOOSE, bulldoze=0.0)
    for C in (0.2, 1.0, 5.0):
        assert wheel_forces(z, 0.3, MARS_LOOSE, WHEEL, q=C)["Fy"] > wheel_forces(z, 0.3, no, WHEEL, q=C)["Fy"]
    assert wheel_forces(z, 0.3, MARS_LOOSE, WHEEL, q=0.0)["Fy"] == 0.0
    # with sigma independent of slip (at fixed z a larger exponent softens the soil) the lateral
    # force grows with the lateral ratio
    flat = dataclasses.replace(MARS_LOOSE, n1=0.0, n2=0.0, a1=0.0, a1_skid=0.0, c_exit1=0.0)
    fy = wheel_forces(z, 0.3, flat, WHEEL, q=np.linspace(0, 3, 10))["Fy"]
    assert np.all(np.diff(fy) > 0)


def test_front_ploughing_brakes_a_skidding_wheel():
    no = dataclasses.replace(MARS_LOOSE, plough=0.0)
    for s in (-0.3, -1.0):
        assert wheel_forces(0.04, s, MARS_LOOSE, WHEEL)["DP"] < wheel_forces(0.04, s, no, WHEEL)["DP"]
    assert wheel_forces(0.04, 0.3, MARS_LOOSE, WHEEL)["DP"] == wheel_forces(0.04, 0.3, no, WHEEL)["DP"]


@pytest.mark.parametrize("name, slips", [("mars_very_loose", (0.3, 0.65)), ("mars_loose", (0.0, 0.4))])
def test_mars_presets_carry_the_rover(name, slips):
    # HIT-MRII T1: WRM slip 0.3-0.65 on very loose, 0-0.4 on loose soil (spec srwmr.md). The
    # presets must give positive drawbar pull somewhere in that slip range for the 0.15 m wheel
    # at 300-400 N, and sinkage rising with slip.
    sp = soil(name)
    s = np.linspace(*slips, 8)
    for load in (300.0, ROVER_LOAD, 400.0):
        r = steady_state(load, s, sp, WHEEL)
        assert np.max(r["DP_coeff"]) > 0.02, (load, r["DP_coeff"])
        assert np.all(r["DP_coeff"] < sp.tan_phi)
        assert np.all(np.diff(r["sinkage_m"]) > 0)
    z = steady_state(ROVER_LOAD, np.array([0.0, 0.6]), sp, WHEEL)["sinkage_m"]
    assert z[1] / z[0] > 1.2
