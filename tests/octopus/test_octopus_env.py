"""The OCTOPUS Gymnasium env: check_env, the sensing boundary as observation, benchmark agreement."""

import math
import warnings

import gymnasium
import numpy as np
from gymnasium.utils.env_checker import check_env

import terrabench.envs  # noqa: F401  (registers the ids)
from terrabench.systems.octopus.scenarios import SYSTEM

ENV_ID = "terrabench/Octopus-v1"
SHORT = {"protocol.timeout": 1.0}


def test_check_env_passes_and_the_observation_is_the_sensing_boundary():
    env = gymnasium.make(ENV_ID, method="clm", instance="step-400", overrides=SHORT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # advisory: unbounded observation boxes
        check_env(env.unwrapped)
    assert set(env.observation_space.spaces) == {"imu", "q_flip", "q_arm", "tau_flip", "tau_elbow", "time"}
    assert env.action_space.shape == (18,)
    obs, _ = env.reset(seed=0)
    for _ in range(20):  # turn in place: the gyro's yaw rate is the third IMU entry
        obs, *_ = env.step(np.r_[-0.1, 0.1, np.zeros(16)])
    sensed = env.unwrapped.sensed
    assert obs["imu"].shape == (3,)
    assert obs["imu"].tolist() == [sensed.roll, sensed.pitch, sensed.yaw_rate] and sensed.yaw_rate > 0
    env.close()


def test_the_benchmark_controller_through_the_env_gives_the_benchmark_metrics():
    over = {"protocol.timeout": 2.0}
    env = gymnasium.make(ENV_ID, method="clm", instance="step-400", overrides=over).unwrapped
    env.reset(seed=0)
    ctrl = env.reference_controller()
    while True:
        _, r, term, trunc, info = env.step(env.adapter.reference_action(ctrl(env.sensed)))
        assert r == sum(info["reward_terms"].values())
        if term or trunc:
            break
    got = env.trial_result()
    ref = SYSTEM.run_trial(SYSTEM.plan(methods=["clm"], instances=["step-400"], overrides=over)[0])
    assert got.status == ref.status
    assert got.metrics.keys() == ref.metrics.keys()
    # figures over the controller's modes (climb rows, walking rows) and the tip slip (the arm in
    # transfer is no support) need its state codes,
    # which an action does not carry
    by_mode = {"tracks_stopped_share", "walk_speed_mean_mps", "crawler_load_share_min", "tip_slip_max_m",
               "tip_slip_walk_max_m", "tip_slip_climb_max_m", "crawlers_enclosed_share",
               "walk_three_supports_share", "margin_gain_walk_min_m", "margin_gained_share",
               "crawler_load_share_phase_min"}
    for k in ref.metrics.keys() - by_mode:
        a, b = got.metrics[k], ref.metrics[k]
        assert (math.isnan(a) and math.isnan(b)) or a == b, k
    # the controller's state codes (mode, moving arm) are not in an action: the rest is bitwise
    for k in ref.timeseries:
        if k not in ("mode", "moving_arm", "track_cmd", "tip_slip", "tip_slip_mode", "crawlers_in_tips"):
            np.testing.assert_array_equal(got.timeseries[k], ref.timeseries[k], err_msg=k)
