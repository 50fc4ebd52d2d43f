"""The controllers on hand-made inputs (no physics)."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from terrabench.systems.mrs_cwc import control as ctl
from terrabench.systems.mrs_cwc.sensing import wrap


def law(**kw):
    return ctl.StiffnessLaw(ctl.StiffnessLawConfig(**kw), 0.025)


def test_wrap_range():
    a = np.array([0.0, math.pi, -math.pi, 3 * math.pi, -0.1, 7.0])
    w = wrap(a)
    assert np.all(w > -math.pi - 1e-12) and np.all(w <= math.pi + 1e-12)
    assert np.allclose(np.cos(w), np.cos(a)) and np.allclose(np.sin(w), np.sin(a))
    assert wrap(-math.pi) == pytest.approx(math.pi)


def test_quiet_drive_converges_to_k_low_with_the_released_memory():
    s = law()
    for _ in range(2000):  # the 5-sample mean fed back into the EMA gives a ~4 s time constant
        k = s.update(e=0.1, yaw_rate=0.0, tau_l=1.0, tau_r=1.0, q1=0.0)
    assert s.memory == -1.0  # |0.5 e| < 0.6: memory untouched
    assert k == pytest.approx(5.0, rel=1e-3)


def test_large_torque_latches_soft_until_it_falls_below_one():
    s = law()
    s.memory = 1.0  # spring has been helping: target would be K_high
    s.update(0.0, 0.0, tau_l=0.0, tau_r=20.0, q1=0.0)  # tau_m = 24 > 20
    assert s.soft
    s.update(0.0, 0.0, tau_l=0.0, tau_r=5.0, q1=0.0)  # 6 N m: between thresholds, stays soft
    assert s.soft
    s.update(0.0, 0.0, tau_l=0.0, tau_r=0.5, q1=0.0)  # 0.6 N m < 1: released
    assert not s.soft


def test_sign_memory_turns_positive_when_spring_helps_the_turn():
    s = law()
    s.k = 50.0
    # e > 0 (turn left), spring torque -K*q1 > 0 when q1 < 0: they agree
    for _ in range(30):
        s.update(e=1.5, yaw_rate=0.0, tau_l=0.0, tau_r=0.0, q1=-0.01)
    assert s.memory > 0
    for _ in range(2000):
        k = s.update(e=0.0, yaw_rate=0.0, tau_l=0.0, tau_r=0.0, q1=0.0)
    assert k == pytest.approx(100.0, rel=1e-3)


def test_smoothing_is_an_ema_followed_by_a_five_sample_mean():
    s = law()
    ks = [s.update(0.0, 0.0, 0.0, 0.0, 0.0) for _ in range(3)]
    k1 = 0.03 * 5 + 0.97 * 0.1
    assert ks[0] == pytest.approx(k1)
    k2 = (k1 + (0.03 * 5 + 0.97 * k1)) / 2
    assert ks[1] == pytest.approx(k2)


def test_tau_env_uses_the_released_balance():
    s = law()
    s.update(0.0, yaw_rate=0.0, tau_l=1.0, tau_r=2.0, q1=0.0)
    s.k = 10.0
    s.update(0.0, yaw_rate=0.25, tau_l=1.0, tau_r=2.0, q1=0.1)
    expect = 0.0042181 * (0.25 / 0.025) + 1.2 * 1.0 - (-10.0 * 0.1)
    assert s.tau_env == pytest.approx(expect)


def test_eq12_goes_stiff_only_when_torques_agree_and_the_environment_is_quiet():
    s = law(mode="eq12")
    s.k = 10.0
    for _ in range(2000):
        k = s.update(0.0, 0.0, tau_l=0.0, tau_r=1.0, q1=-0.05)  # tau_m = 1.2 > 0, spring = +0.5 > 0
    assert k == pytest.approx(100.0, rel=1e-2)
    for _ in range(2000):
        k = s.update(0.0, 0.0, tau_l=0.0, tau_r=1.0, q1=+0.05)  # spring opposes
    assert k == pytest.approx(5.0, rel=1e-2)


def test_bad_mode_is_rejected():
    with pytest.raises(ValueError, match="valid: released, eq12, constant"):
        ctl.StiffnessLawConfig(mode="stiff")


def fake_obs(pos, yaw, t=0.0):
    n = len(yaw)
    return SimpleNamespace(pos=np.asarray(pos, float), yaw=np.asarray(yaw, float), t=t,
                           wheel_torque=np.zeros((n, 2)), yaw_rate=np.zeros(n), joint_yaw=np.zeros(n - 1),
                           yaw_torque=np.zeros(n - 1), target_bearing=0.0)


def test_waypoints_advance_skip_and_time_out():
    wp = np.array([[1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [9.0, -9.0]])
    g = ctl.WaypointGuidance(wp)
    g.heading(fake_obs([[0, 0, 0]], [0.0]))
    assert g.index == 0
    g.heading(fake_obs([[0.7, 0, 0]], [0.0]))  # within 0.5 m of waypoint 0
    assert g.index == 1
    g.heading(fake_obs([[2.9, 0.1, 0]], [0.0]))  # waypoint 2 is closer than waypoint 1: skip
    assert g.index == 2
    g.heading(fake_obs([[2.0, 2.0, 0]], [0.0], t=10.0))
    assert g.index == 2
    g.heading(fake_obs([[2.0, 2.0, 0]], [0.0], t=101.0))  # 90 s on one waypoint: give up on it
    assert g.index == 3


def test_followers_copy_the_predecessor_heading():
    body = ctl.CWCLaw(3, ctl.DriveConfig(), ctl.StiffnessLawConfig(), 0.025)
    cmd = ctl.Command(3)
    obs = fake_obs(np.zeros((3, 3)), [0.0, 0.2, 0.0])
    body(obs, 0.0, cmd)
    # unit 1 is 0.2 rad left of the leader's heading: it turns right (left wheel faster)
    assert cmd.wheel_speed[1, 0] == pytest.approx(1.5 + 0.6 * 0.2)
    assert cmd.wheel_speed[1, 1] == pytest.approx(1.5 - 0.6 * 0.2)
    # unit 2 must turn left toward unit 1
    assert cmd.wheel_speed[2, 1] > cmd.wheel_speed[2, 0]


def test_head_following_delays_each_joint_by_twenty_periods():
    cfg = ctl.HeadFollowingConfig()
    body = ctl.HeadFollowing(4, ctl.DriveConfig(), cfg)
    cmd = ctl.Command(4)
    history = []
    obs = fake_obs(np.zeros((4, 3)), [0.0] * 4)
    for _ in range(60):
        body(obs, 1.0, cmd)  # e = 1 rad > 25 deg: head target +35 deg
        history.append(cmd.yaw_target.copy())
    h = np.array(history)
    assert h[0, 0] > 0 and h[19, 1] == 0.0 and h[20, 1] == pytest.approx(h[0, 0])
    assert h[40, 2] == pytest.approx(h[0, 0])
    assert np.all(cmd.wheel_speed[1:] == pytest.approx(math.pi / 2))


def test_distributed_followers_stop_close_and_chase_when_far():
    body = ctl.FollowByPosition(3, ctl.DriveConfig(), ctl.FollowConfig())
    cmd = ctl.Command(3)
    obs = fake_obs([[0, 0, 0], [-0.05, 0, 0], [-1.05, 0, 0]], [0.0, 0.0, 0.0])
    body(obs, 0.0, cmd)
    assert np.all(cmd.wheel_speed[1] == 0.0)
    assert cmd.wheel_speed[2, 0] == pytest.approx(5.0 * (1.0 - 0.1))


def test_a_follower_far_behind_is_capped_at_the_wheel_speed_limit():
    body = ctl.FollowByPosition(2, ctl.DriveConfig(), ctl.FollowConfig(max_wheel_speed=6.0))
    cmd = ctl.Command(2)
    obs = fake_obs([[0, 0, 0], [-5.0, 0.5, 0]], [0.0, 0.0])  # 5 m behind and off to the side
    body(obs, 0.0, cmd)
    assert np.all(np.abs(cmd.wheel_speed[1]) <= 6.0)
    assert cmd.wheel_speed[1, 1] == pytest.approx(6.0)  # still turning towards it at full speed


def test_the_scalar_cwc_law_is_the_vector_law_bitwise():
    """CWCLaw runs on Python floats for speed; it must equal the array formulation exactly
    (wrap of the heading errors, then v -/+ g e per unit), so stored results do not move."""
    from terrabench.systems.mrs_cwc.sensing import wrap

    drive = ctl.DriveConfig()
    rng = np.random.default_rng(7)
    for _ in range(200):
        yaw = rng.uniform(-7.0, 7.0, 6)
        ref = float(rng.uniform(-4.0, 4.0))
        body = ctl.CWCLaw(6, drive, ctl.StiffnessLawConfig(), 0.025)
        cmd = ctl.Command(6)
        body(fake_obs(np.zeros((6, 3)), yaw), ref, cmd)
        e = np.concatenate([[wrap(ref - yaw[0])], wrap(yaw[:-1] - yaw[1:])])
        want = np.multiply(e, drive.turn_gain)[:, None] * np.array([-1.0, 1.0]) + drive.wheel_speed
        np.testing.assert_array_equal(cmd.wheel_speed, want)


def test_index_view_writes_through_when_it_can():
    from terrabench.sim.scene import index_view, writer

    a = np.zeros(30)
    assert np.shares_memory(index_view(a, [3, 8, 13, 18]), a)  # evenly spaced: a view
    assert not np.shares_memory(index_view(a, [3, 4, 9]), a)  # not: a copy
    for ids in ([3, 8, 13, 18], [3, 4, 9], [5], []):
        b = np.zeros(30)
        writer(b, ids)(7.0)
        want = np.zeros(30)
        want[ids] = 7.0
        np.testing.assert_array_equal(b, want)
