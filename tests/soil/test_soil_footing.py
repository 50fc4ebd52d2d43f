"""Static footing of a still wheel (SoilWheels(footing=True), docs/soil.md "Static footing").

A braked wheel under a horizontal push below the soil's sliding strength must move only by the
Janosi-Hanamoto displacement that mobilises the push, then hold (no viscous drift); a larger
push slides at the steady-state locked-wheel force; a rolling wheel feels the steady-state
forces only."""

import math

import mujoco
import numpy as np
import pytest

from terrabench.soil.mujoco_soil import SoilWheels, _footing
from terrabench.soil.presets import HIT_MRII_WHEEL, MARS_SOFT
from terrabench.soil.rover import build_rover, wheel_name
from terrabench.soil.table import cached_table
from terrabench.soil.terramechanics import steady_state, wheel_forces

WHEEL = HIT_MRII_WHEEL
SOIL = MARS_SOFT
LOAD = 368.0  # N, HIT-MRII's share (225 kg g / 6)
DT = 0.0005

_XML = """<mujoco><option timestep="{dt}"/>
<worldbody><body name="cart" pos="0 0 0.2">
 <joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
 <inertial pos="0 0 0" mass="{mass}" diaginertia="1 1 1"/>
 <body name="wheel">{hinge}<geom type="cylinder" size="0.15 0.06" euler="90 0 0" mass="2"/></body>
</body></worldbody></mujoco>"""


def _rig(footing=True, hinge=False, v_eps=0.004):
    """One wheel on a carriage free in x and z; without a hinge the wheel is braked rigidly."""
    h = '<joint name="spin" type="hinge" axis="0 1 0"/>' if hinge else ""
    m = mujoco.MjModel.from_xml_string(_XML.format(dt=DT, mass=LOAD / 9.81 - 2.0, hinge=h))
    d = mujoco.MjData(m)
    sw = SoilWheels(m, d, ["wheel"], WHEEL, cached_table(SOIL, WHEEL), v_eps=v_eps, footing=footing, refresh=True)
    return m, d, sw


def _push(force, seconds, footing=True, hinge=False, settle=1.0):
    """Settle, then push the carriage along +x; returns (times, x - x0, the rig)."""
    m, d, sw = _rig(footing, hinge)
    for _ in range(int(settle / DT)):
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
    x0 = float(d.qpos[0])
    t, x = [], []
    for k in range(int(seconds / DT)):
        d.qfrc_applied[0] = force
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
        if k % 20 == 0:
            t.append(k * DT)
            x.append(float(d.qpos[0]) - x0)
    return np.array(t), np.array(x), (m, d, sw)


def _strength(sw):
    """The footing's sliding strength along the heading at the wheel's sinkage (N)."""
    z = float(sw.truth["sinkage"][0])
    return float(np.interp(z, sw.table.z, sw._caps[:, 0])), z


def test_the_footing_strength_is_mohr_coulomb_plus_the_sunk_wheels_resistance():
    # the strength is the model's locked-wheel drawbar resistance: at least the Mohr-Coulomb shear
    # c A + W tan(phi) of the patch's horizontal projection, plus compaction and front ploughing
    m, d, sw = _rig()
    for _ in range(int(1.0 / DT)):
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
    cap, z = _strength(sw)
    th1 = math.acos(1 - z / WHEEL.radius)
    area = WHEEL.width * WHEEL.radius * math.sin(th1)
    mohr = SOIL.c * area + LOAD * SOIL.tan_phi
    locked = -float(wheel_forces(z, -1.0, SOIL, WHEEL)["DP"])
    assert cap == pytest.approx(locked, rel=0.02)
    assert mohr < cap < 3 * mohr


def test_a_braked_wheel_under_a_push_below_its_strength_creeps_a_bounded_distance_and_holds():
    m, d, sw = _rig()
    for _ in range(int(1.0 / DT)):
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
    cap, _ = _strength(sw)
    for frac in (0.3, 0.6):
        t, x, (m, d, sw) = _push(frac * cap, 12.0)
        # Janosi-Hanamoto: the push is mobilised at j = -K ln(1 - F / F_max)
        j = -SOIL.K * math.log(1 - frac)
        assert x[-1] == pytest.approx(j, rel=0.25, abs=1e-3)
        late = x[t >= 8.0]
        assert np.ptp(late) < 2e-4, f"push {frac} of the strength: still drifting {np.ptp(late) * 1e3:.2f} mm in 4 s"
        assert abs(float(d.qvel[0])) < 1e-4
        assert 0 < sw.foot[0, 0] < 1
        # without the footing the same wheel drifts like a viscous damper and keeps moving
        t0, x0, (m0, d0, _) = _push(frac * cap, 12.0, footing=False)
        assert np.ptp(x0[t0 >= 8.0]) > 5e-3 * frac and float(d0.qvel[0]) > 5e-4


def test_a_push_above_the_strength_slides_at_the_steady_state_locked_wheel_force():
    m, d, sw = _rig()
    for _ in range(int(1.0 / DT)):
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
    cap, _ = _strength(sw)
    # sliding sinks a locked wheel deeper than at rest (skid exponent, stress angles), so the
    # sliding force at its load exceeds the footing strength at the static sinkage
    sliding = -float(steady_state(LOAD, -1.0, SOIL, WHEEL)["DP_N"])
    assert sliding > cap
    F = 1.2 * sliding
    t, x, (m, d, sw) = _push(F, 3.0)
    mass = LOAD / 9.81
    # from the motion over the last second: resistance = F - M a (the wheel accelerates)
    k = t >= 2.0
    a = np.polyfit(t[k], x[k], 2)[0] * 2
    resist = F - mass * a
    z = float(sw.truth["sinkage"][0])
    locked = -float(wheel_forces(z, -1.0, SOIL, WHEEL)["DP"])
    assert float(d.qvel[0]) > 0.05  # sliding, well above v_eps
    assert resist == pytest.approx(locked, rel=0.05)


def test_the_footing_follows_janosi_hanamoto_in_the_patch_displacement_and_renews_as_the_wheel_rolls():
    # the state law itself (the kernel's inlined function), at rest (fade 0) and rolling
    foot = np.zeros((1, 3))
    caps = np.array([[300.0, 200.0, 0.5], [300.0, 200.0, 0.5]])
    tp = np.array([0.15, 1 / 0.15, 1.0, 1.0])
    K, dt, v = 0.02, 0.0005, 0.001
    fp = np.array([1.0, dt, K, K, 0.0, 0.0, 0.004])
    fs = []
    for _ in range(2000):  # the patch pushed forward 1 mm at 1 mm/s, nothing rolls
        fx, fy, _ = _footing(0, 0.05, 0.0, v, 0.0, 0.0, 0.15, foot, caps, tp, fp)
        fs.append(fx)
    x = np.arange(1, 2001) * v * dt
    np.testing.assert_allclose(-np.array(fs), 300.0 * (1 - np.exp(-x / K)), rtol=1e-6, atol=1e-9)
    assert fy == 0.0
    # reversing (0.1 m back, 5 K): the reaction turns and stays inside the strength
    for _ in range(4000):
        fx, _, _ = _footing(0, 0.05, 0.0, -50 * v, 0.0, 0.0, 0.15, foot, caps, tp, fp)
        assert abs(fx) <= 300.0 + 1e-9
    assert fx > 0.9 * 300.0
    # rolling without slip at rim speed U: the mobilisation decays over one contact length
    m0 = foot[0, 0]
    U = 0.01
    lc = 0.15 * math.acos(1 - 0.05 / 0.15)
    n = 1000
    for _ in range(n):
        _footing(0, 0.05, U, U, 0.0, 1.0, 0.15, foot, caps, tp, fp)
    assert foot[0, 0] == pytest.approx(m0 * math.exp(-U * n * dt / lc), rel=1e-6)


def test_a_free_wheel_still_rolls_and_a_rolling_rover_feels_the_steady_state_forces():
    # a free wheel pushed with a force well below the footing strength rolls away (the footing
    # acts on the patch's slip, not on the hub): the rolling resistance is the steady-state one
    t, x, (m, d, sw) = _push(80.0, 3.0, hinge=True)
    assert x[-1] > 0.05
    # six-wheeled rover driving: once rolling, footing on and off give the same motion
    res = []
    for footing in (True, False):
        mr = build_rover(WHEEL).compile()
        dr = mujoco.MjData(mr)
        sw = SoilWheels(mr, dr, [wheel_name(i) for i in range(6)], WHEEL, cached_table(SOIL, WHEEL), footing=footing)
        dr.ctrl[:] = 2.0
        for _ in range(2500):
            sw.before_substep(mr, dr)
            mujoco.mj_step(mr, dr)
        res.append((float(dr.qvel[0]), sw.truth["slip"].copy(), sw.truth["DP"].copy()))
    assert res[0][0] == pytest.approx(res[1][0], rel=0.01)
    np.testing.assert_allclose(res[0][1], res[1][1], atol=0.01)
    np.testing.assert_allclose(res[0][2], res[1][2], atol=0.01 * LOAD)


def test_pushed_back_into_its_own_rut_the_footing_keeps_only_its_shear_part():
    # a wheel that travelled forward has its rut behind it: pushed backwards there is no fresh soil
    # to compact or plough, so the strength is the shear share (caps[:, 2]) of the full strength
    caps = np.array([[400.0, 200.0, 0.55], [400.0, 200.0, 0.55]])
    tp = np.array([0.15, 1 / 0.15, 1.0, 1.0])
    fp = np.array([1.0, 0.0005, 0.02, 0.02, 0.0, 0.0, 0.004])
    for direction, strength, at_rim in ((+1.0, 400.0, 0.55), (-1.0, 0.55 * 400.0, 1.0)):
        foot = np.zeros((1, 3))
        _footing(0, 0.05, 0.01, 0.01, 0.0, 1.0, 0.15, foot, caps, tp, fp)  # rolled forward
        assert foot[0, 2] == 1.0
        for _ in range(4000):  # braked, the patch slid 0.1 m (5 K) forward or backward
            fx, _, phs = _footing(0, 0.05, 0.0, direction * 0.05, 0.0, 0.0, 0.15, foot, caps, tp, fp)
        assert -fx * direction == pytest.approx(strength, rel=0.01)
        assert foot[0, 2] == 1.0  # sliding braked does not move the rut
        assert phs == at_rim
    foot = np.zeros((1, 3))
    _footing(0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.15, foot, caps, tp, fp)  # out of the soil: fresh soil again
    assert foot[0, 2] == 0.0
