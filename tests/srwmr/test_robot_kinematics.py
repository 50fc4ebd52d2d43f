"""HIT-MRII model and kinematics: pinned counts, geometry against the simulator, IK/FK."""

import math

import mujoco
import numpy as np
import pytest

from terrabench.systems.srwmr import kinematics as kin
from terrabench.systems.srwmr.robot import LINK_BIT, WHEEL_BIT, WHEELS, Names, RobotConfig, add_robot, joint_counts

CFG = RobotConfig()


def _model(rigid: bool = False, delta: float = 0.0):
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.002
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.worldbody.add_geom(
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[20, 20, 0.1],
        contype=0,
        conaffinity=LINK_BIT | (WHEEL_BIT if rigid else 0),
        friction=[1.0, 0.005, 0.0001],
    )
    add_robot(spec, (0, 0, CFG.hinge_height + 0.002), 0.0, CFG)
    m = spec.compile()
    d = mujoco.MjData(m)
    for s in ("L", "R"):
        d.qpos[m.joint(Names.rocker(s)).qposadr[0]] = -delta
        d.qpos[m.joint(Names.front(s)).qposadr[0]] = CFG.z_ratio * delta
        d.qpos[m.joint(Names.bogie(s)).qposadr[0]] = delta
    mujoco.mj_forward(m, d)
    return m, d


def test_model_counts_are_pinned():
    m, _ = _model()
    # 1 chassis + per side diff, rear, bogie, front + 6 pillars + 6 wheels (+ world)
    assert joint_counts(m) == {"nbody": 22, "njnt": 21, "nq": 27, "nv": 26, "nu": 14, "neq": 5, "nsensor": 8}
    assert CFG.total_mass == pytest.approx(225.0)  # [S] 225 kg
    assert m.jnt_range[m.joint(Names.steer("c1")).id][1] == pytest.approx(1.75)  # radians, not degrees


def test_axles_match_the_simulator_at_two_rocker_angles():
    for delta in (0.0, 0.3):
        m, d = _model(delta=delta)
        ch = m.body(Names.CHASSIS).id
        R = d.xmat[ch].reshape(3, 3)
        sim = np.array([R.T @ (d.xpos[m.body(Names.wheel(c)).id] - d.xpos[ch]) for c in WHEELS])
        ref = kin.axle_positions(CFG, [delta, delta], kin.level_zeta(CFG, [delta, delta]))
        assert np.allclose(sim, ref, atol=1e-9)


def test_stated_dimensions():
    p = kin.axle_positions(CFG, [0.0, 0.0])
    assert p[0, 1] - p[1, 1] == pytest.approx(1.304)  # d_wt [S]
    assert p[0, 0] - p[4, 0] == pytest.approx(1.90, abs=0.02)  # [S] 2200 mm long, 1900 mm wheelbase
    assert p[0, 0] - p[4, 0] == pytest.approx(CFG.wheelbase)
    assert kin.chassis_clearance(CFG, [0.0, 0.0]) == pytest.approx(0.25)  # [S] 250 mm
    lo, hi = kin.clearance_range(CFG)
    assert lo < 0.15 and hi > 0.52  # the tested 150-550 mm reachable to 529 mm (the fitted linkage's reach)
    for c in (0.15, 0.33, 0.48, 0.52):
        d = kin.delta_for_clearance(CFG, c)
        assert kin.chassis_clearance(CFG, [d, d]) == pytest.approx(c, abs=1e-6)


def test_closing_lifts_and_narrows_the_wheelbase():
    wb0 = kin.wheelbase_front_middle(CFG, [0.0, 0.0])
    wb1 = kin.wheelbase_front_middle(CFG, [0.4, 0.4])
    assert np.all(wb1 < wb0)
    assert kin.chassis_clearance(CFG, [0.4, 0.4]) > 0.25


def test_forward_inverse_consistency():
    rng = np.random.default_rng(1)
    for _ in range(20):
        u = np.array(
            [rng.uniform(-0.05, 0.05), rng.uniform(-0.02, 0.02), rng.uniform(-0.05, 0.05), *rng.uniform(-0.02, 0.02, 2)]
        )
        delta = rng.uniform(-0.2, 0.6, 2)
        mu0 = rng.uniform(-0.3, 0.3, 6)  # steering that places the offset contact points
        mu, spin = kin.inverse_kinematics(CFG, u, delta, mu_prev=mu0)
        twist = kin.forward_kinematics(CFG, spin, mu, delta, u[3:5], mu_geom=mu0)
        assert np.allclose(twist, u[:3], atol=1e-9)


def test_crab_and_turn_in_place_angles():
    mu, spin = kin.inverse_kinematics(CFG, [0.0, 0.02, 0.0, 0.0, 0.0], [0.0, 0.0])
    assert np.allclose(np.abs(mu), math.pi / 2)
    mu, _ = kin.inverse_kinematics(CFG, [0.0, 0.0, 0.05, 0.0, 0.0], [0.0, 0.0])
    # turning about the hinge line: the middle wheels, nearest to it in x, steer least; the left
    # and right wheel of an axle steer opposite ways, and the wheels ahead opposite to those behind
    assert np.all(np.abs(mu[2:4]) < np.abs(mu[0:2])) and np.all(np.abs(mu[2:4]) < np.abs(mu[4:6]))
    assert np.allclose(mu[0::2], -mu[1::2]) and mu[0] * mu[4] < 0 and abs(mu[0]) > 0.5


def test_lift_heights():
    assert kin.lift_height(CFG, "front", 0.0) == pytest.approx(0.0, abs=1e-12)
    # no change of the closing angle is no lift, from any start posture (the 500 mm clearance's
    # start had read 11 mm for the front wheel and tripled the lift's lever)
    for clearance in (0.25, 0.35, 0.5):
        d0 = float(kin.delta_for_clearance(CFG, clearance))
        for which in ("front", "middle", "rear"):
            assert kin.lift_height(CFG, which, 0.0, d0) == pytest.approx(0.0, abs=1e-12)
        # the rise is smooth through the start: the lever from one side equals the other's
        up, down = (kin.lift_height(CFG, "front", s * 1e-3, d0) / (s * 1e-3) for s in (-1, 1))
        assert up == pytest.approx(down, rel=0.02)
    assert kin.lift_height(CFG, "front", -0.2) > 0.1
    assert kin.lift_height(CFG, "middle", 0.2) > 0.05
    assert kin.lift_height(CFG, "rear", -0.2) > 0.1
    with pytest.raises(ValueError, match="valid: front, middle, rear"):
        kin.lift_height(CFG, "left", 0.1)


def test_the_rockers_open_far_enough_for_the_papers_rear_lift_and_stop_with_the_box_on_the_ground():
    from terrabench.systems.srwmr.ik import IKLimits
    from terrabench.systems.srwmr.legged import SHIFT

    stop = -CFG.rocker_range[1]  # the opening stop as a closing angle
    # the stop: the chassis box's bottom at flat ground with all six wheels on it
    assert kin.chassis_clearance(CFG, [stop, stop]) == pytest.approx(0.0, abs=0.002)
    lo = IKLimits().delta_range[0]
    assert lo == pytest.approx(stop + 0.05)  # the IK keeps 0.05 rad off the stop, as at the closing end
    # Task 13 lifts the rear wheel 200 mm [S] after the rear CoM shift lowers the chassis (175 mm):
    # on rigid flat ground the rise reaches 200 mm before the IK's limit, with room for the soil
    # (the middle wheels sink under ~880 N: -0.48 to -0.50 rad measured in T13 rear DWLM)
    d0 = kin.delta_for_clearance(CFG, SHIFT["rear"])
    assert kin.lift_height(CFG, "rear", lo + 0.01 - d0, d0) > 0.2 + 0.1
    # the box stays off the ground through that lift (rigid side: front and middle wheels grounded)
    assert kin.chassis_clearance(CFG, [lo, lo]) > 0.0


def test_rolling_without_slip_on_rigid_ground_matches_the_command():
    """Rigid wheel contact (friction 1): the IK's wheel commands reproduce the body twist."""
    m, d = _model(rigid=True)
    steer = [m.actuator(Names.steer(c)).id for c in WHEELS]
    drive = [m.actuator(Names.drive(c)).id for c in WHEELS]
    rock = [m.actuator(Names.rocker(s)).id for s in ("L", "R")]
    u = np.array([0.05, 0.0, 0.04, 0.0, 0.0])
    mu, spin = kin.inverse_kinematics(CFG, u, [0.0, 0.0])
    d.ctrl[rock] = 0.0
    yaw, xs = [], []
    for k in range(int(6.0 / 0.002)):
        d.ctrl[steer] = mu
        d.ctrl[drive] = spin if d.time > 1.0 else 0.0
        mujoco.mj_step(m, d)
        if d.time > 3.0 and k % 50 == 0:
            q = d.xquat[m.body(Names.CHASSIS).id]
            yaw.append((d.time, math.atan2(2 * (q[0] * q[3] + q[1] * q[2]), 1 - 2 * (q[2] ** 2 + q[3] ** 2))))
            xs.append(d.qvel[:3].copy())
    t, y = np.array(yaw).T
    wz = np.polyfit(t, np.unwrap(y), 1)[0]
    speed = np.mean([np.hypot(v[0], v[1]) for v in xs])
    assert wz == pytest.approx(0.04, rel=0.05)
    assert speed == pytest.approx(0.05, rel=0.05)
