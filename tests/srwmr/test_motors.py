"""Electrical power of the HIT-MRII actuators (motors.py): physics, not copied numbers."""

import math

import numpy as np
import pytest

from terrabench.systems.srwmr import motors as mo

SPECS = (mo.WHEEL_DRIVE, mo.WHEEL_STEER, mo.ROCKER_HINGE)
RNG = np.random.default_rng(27)


def _random_points(spec, n=4000):
    """Torques and speeds across +-3 x the continuous rating, with exact zeros mixed in."""
    tau = RNG.uniform(-3, 3, n) * spec.continuous_torque
    w = RNG.uniform(-1.5, 1.5, n) * spec.max_speed / 4
    tau[::17] = 0.0
    w[::13] = 0.0
    return tau, w


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_standstill_without_torque_costs_nothing(spec):
    # decided: I_0 is the friction torque as a current, acting against motion -> zero at rest
    assert mo.electrical_power(spec, 0.0, 0.0) == 0.0
    assert mo.motor_current(spec, 0.0, 0.0) == 0.0


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_free_running_costs_only_no_load_losses(spec):
    m = spec.motor
    for w in (0.3 * spec.max_speed / 4, -0.1 * spec.max_speed / 4):
        p = mo.electrical_power(spec, 0.0, w)
        w_m = spec.ratio * abs(w)
        assert p > 0.0
        # friction k_M I_0 |w_m| plus the copper loss of I_0
        assert p == pytest.approx(m.friction_torque * w_m + m.R * m.I_0**2, rel=1e-12)


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_holding_a_load_costs_copper_loss_only(spec):
    tau = np.array([0.5, -0.5, 1.0]) * spec.continuous_torque
    p = mo.electrical_power(spec, tau, 0.0)
    i = tau / (spec.ratio * spec.eta * spec.motor.k_M)
    assert np.all(p > 0.0)  # no mechanical power, still a cost
    np.testing.assert_allclose(p, i**2 * spec.motor.R, rtol=1e-12)
    assert p[0] == pytest.approx(p[1])  # symmetric in the torque's sign
    assert p[2] == pytest.approx(4 * p[0])  # I^2 R


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_motoring_input_exceeds_mechanical_power(spec):
    tau, w = _random_points(spec)
    p = mo.electrical_power(spec, tau, w)
    motoring = tau * w > 0
    assert motoring.sum() > 1000
    assert np.all(p[motoring] >= tau[motoring] * w[motoring])
    # the gear alone already costs a factor 1/eta
    assert np.all(p[motoring] >= tau[motoring] * w[motoring] / spec.eta)


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_no_regeneration_never_negative_and_regen_bounded(spec):
    tau, w = _random_points(spec)
    p = mo.electrical_power(spec, tau, w)
    assert np.all(p >= 0.0)
    p_regen = mo.electrical_power(spec, tau, w, regen=True)
    np.testing.assert_array_equal(p, np.maximum(p_regen, 0.0))
    back = tau * w < 0
    assert (p_regen[back] < 0).any()  # hard back-driving does generate
    # never more recovered than the mechanical power put in, and only eta of it at most
    assert np.all(p_regen[back] >= spec.eta * tau[back] * w[back] - 1e-9)


def test_gear_efficiency_applies_in_the_direction_of_power_flow():
    spec = mo.WHEEL_DRIVE
    tau, w = 0.5 * spec.continuous_torque, 0.1
    i_motor = mo.motor_current(spec, tau, w) - spec.motor.I_0
    i_back = mo.motor_current(spec, tau, -w) + spec.motor.I_0
    assert i_motor == pytest.approx(tau / (spec.ratio * spec.eta * spec.motor.k_M))
    assert i_back == pytest.approx(tau * spec.eta / (spec.ratio * spec.motor.k_M))
    assert i_back == pytest.approx(i_motor * spec.eta**2)


def test_vectorised_and_broadcast():
    spec = mo.WHEEL_DRIVE
    tau = RNG.normal(0, 10, (7, 6))
    w = RNG.normal(0, 0.1, (7, 6))
    p = mo.electrical_power(spec, tau, w)
    assert p.shape == (7, 6)
    assert p[3, 2] == pytest.approx(float(mo.electrical_power(spec, tau[3, 2], w[3, 2])))
    assert mo.electrical_power(spec, tau, 0.05).shape == (7, 6)


def test_energy_of_a_constant_power_log_is_power_times_duration():
    spec = mo.WHEEL_DRIVE
    t = np.cumsum(np.r_[0.0, RNG.uniform(0.005, 0.02, 400)])  # uneven sampling
    tau = np.full((t.size, 6), 20.0)
    w = np.full((t.size, 6), 0.1)
    p = float(mo.electrical_power(spec, 20.0, 0.1))
    assert mo.electrical_energy(spec, t, tau, w) == pytest.approx(6 * p * (t[-1] - t[0]), rel=1e-12)
    # trapezoid of a linear ramp is exact
    assert mo.integrate_power(t, 3.0 * t) == pytest.approx(1.5 * (t[-1] ** 2 - t[0] ** 2), rel=1e-12)
    assert mo.integrate_power(t[:1], [5.0]) == 0.0
    with pytest.raises(ValueError, match="log length"):
        mo.integrate_power(t, np.ones(t.size + 1))
    with pytest.raises(ValueError, match="non-decreasing"):
        mo.integrate_power(t[::-1], np.ones(t.size))


def test_drivetrain_groups_and_simulator_arrays():
    dt = mo.HIT_MRII
    assert mo.GROUP_SIZES == {"drive": 6, "steer": 6, "rocker": 2}
    T = 50
    tau = {g: RNG.normal(0, 0.3, (T, n)) * dt.groups()[g].continuous_torque for g, n in mo.GROUP_SIZES.items()}
    w = {g: RNG.normal(0, 0.05, (T, n)) for g, n in mo.GROUP_SIZES.items()}
    per = dt.power(tau, w)
    total = dt.total_power(tau, w)
    assert total.shape == (T,)
    np.testing.assert_allclose(total, sum(p.sum(axis=1) for p in per.values()))
    # the simulator's layout: steer/drive interleaved per wheel, then the rockers
    ids = {"steer": np.arange(0, 12, 2), "drive": np.arange(1, 12, 2), "rocker": np.array([12, 13])}
    force = np.empty((T, 14))
    vel = np.empty((T, 14))
    for g, i in ids.items():
        force[:, i], vel[:, i] = tau[g], w[g]
    np.testing.assert_allclose(dt.power_of(force, vel, ids), total)
    t = np.linspace(0.0, 0.49, T)
    assert mo.electrical_energy(dt, t, tau, w) == pytest.approx(mo.integrate_power(t, total))
    with pytest.raises(ValueError, match="last axis must hold 6"):
        dt.power({"drive": np.zeros((T, 5))}, {"drive": np.zeros((T, 5))})


def test_reference_data_sheet_reproduced():
    """The one data sheet found (3564 K 024 B): the model's derived rows match the sheet's."""
    m, sheet = mo.FAULHABER_3564K024B, mo.FAULHABER_3564K024B_SHEET
    assert m.k_E * 1e3 / (60 / (2 * math.pi)) == pytest.approx(2.107, rel=1e-3)  # k_E 2,107 mV/rpm
    assert m.omega_0 / mo.RPM == pytest.approx(sheet["n_0_rpm"], rel=0.01)
    assert m.eta_max == pytest.approx(sheet["eta_max"], abs=0.02)
    # friction: k_M I_0 equals the sheet's static + dynamic friction at no-load speed
    # (C_o 1,10 mNm + C_v 2,4e-4 mNm/rpm x 11 300 rpm)
    assert m.friction_torque == pytest.approx(1.10e-3 + 2.4e-7 * 11_300, rel=0.02)
    # the rated point: current at M_e max, within a few % of I_e max
    assert m.M_cont / m.k_M + m.I_0 == pytest.approx(sheet["I_e_max"], rel=0.06)
    # stall torque from the rounded R (1,2 ohm) lands within 10 % of M_H
    assert m.stall_torque == pytest.approx(sheet["M_H"], rel=0.10)


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_rated_point_efficiency_is_motor_times_gear(spec):
    """On the motor's n-M line at U_N, P_in = U_N I, and P_mech / P_in = eta_motor x eta_gear;
    the best motor efficiency on that line is the closed form eta_max."""
    m = spec.motor
    for frac in (0.25, 1.0):
        M = frac * m.M_cont
        w_m = float(m.speed_at(M))
        tau, w = spec.ratio * spec.eta * M, w_m / spec.ratio
        p = float(mo.electrical_power(spec, tau, w))
        i = M / m.k_M + m.I_0
        assert float(mo.motor_voltage(spec, tau, w)) == pytest.approx(m.U_N, rel=1e-12)
        assert p == pytest.approx(m.U_N * i, rel=1e-12)
        eta_motor = M * w_m / (m.U_N * i)
        assert tau * w / p == pytest.approx(eta_motor * spec.eta, rel=1e-12)
    M = np.linspace(1e-6, m.stall_torque, 200_001)
    eta = M * m.speed_at(M) / (m.U_N * (M / m.k_M + m.I_0))
    assert eta.max() == pytest.approx(m.eta_max, rel=1e-6)


def test_scaled_motor_follows_its_laws():
    ref = mo.FAULHABER_3564K024B
    same = mo.scaled_motor(ref, "same", ref.diameter, ref.length)
    assert (same.R, same.I_0, same.M_cont, same.omega_max) == pytest.approx(
        (ref.R, ref.I_0, ref.M_cont, ref.omega_max))
    big = mo.scaled_motor(ref, "x2", 2 * ref.diameter, 2 * ref.length)
    assert big.motor_constant == pytest.approx(ref.motor_constant * 2**2.5)
    assert big.M_cont == pytest.approx(ref.M_cont * 2**3.5)
    # the estimates sit on either side of the reference, ordered by frame size
    w, h = mo.FAULHABER_3056K024B, mo.FAULHABER_4490K024B
    assert w.motor_constant < ref.motor_constant < h.motor_constant
    assert w.M_cont < ref.M_cont < h.M_cont


@pytest.mark.parametrize(("spec", "design"), [(mo.WHEEL_DRIVE, mo.WHEEL_DESIGN), (mo.WHEEL_STEER, mo.WHEEL_DESIGN),
                                              (mo.ROCKER_HINGE, mo.HINGE_DESIGN)], ids=["drive", "steer", "rocker"])
def test_seed_loads_and_speeds_inside_the_continuous_rating(spec, design):
    """Our gear choices: the design torque within the continuous rating, the design speed within
    the motor's maximum speed and reachable at the nominal voltage while carrying that torque."""
    assert design.torque <= spec.continuous_torque <= 1.25 * design.torque
    assert design.speed <= spec.max_speed
    assert float(mo.motor_voltage(spec, design.torque, design.speed)) <= spec.motor.U_N


def test_invalid_specs_rejected():
    with pytest.raises(ValueError, match="eta"):
        mo.ActuatorSpec("x", mo.FAULHABER_3056K024B, ratio=10.0, eta=1.2)
    with pytest.raises(ValueError, match="ratio"):
        mo.ActuatorSpec("x", mo.FAULHABER_3056K024B, ratio=0.0, eta=0.5)
    with pytest.raises(ValueError, match="R must be"):
        mo.MotorSpec("x", 24.0, 0.0, 0.02, 0.1, 0.03, 1000.0, 0.03, 0.05)
