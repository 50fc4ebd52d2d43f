"""The Gymnasium envs: registration, check_env, bitwise agreement with the benchmark, semantics."""

import math
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import terrabench.envs
from terrabench.envs.adapter import EnvAdapter
from terrabench.systems.mrs_cwc.scenarios import SYSTEM

ENV_ID = "terrabench/MRSCWC-v1"
SHORT = {"protocol.timeout": 2.0}


def make(**kw):
    kw.setdefault("overrides", SHORT)
    return gymnasium.make(ENV_ID, **kw)


def test_ids_come_from_the_systems_and_registration_is_idempotent():
    assert ENV_ID in gymnasium.registry
    assert set(SYSTEM.env_ids) <= set(terrabench.envs.register_envs())
    assert gymnasium.registry[ENV_ID].kwargs == {"system": "mrs-cwc"}
    assert isinstance(SYSTEM.env_adapter(), EnvAdapter)


@pytest.mark.parametrize("method", ["cwc-tdt", "mj-tdt", "d-tdt"])
def test_check_env_passes(method):
    env = make(method=method, instance="A-01")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # advisory: unbounded observation boxes, non-normalised actions
        check_env(env.unwrapped)
    n = 6
    extra = {"cwc-tdt": 1, "mj-tdt": n - 1, "d-tdt": 0}[method]
    assert env.action_space.shape == (2 * n + extra,)
    env.close()


def _same(a, b):
    return a.keys() == b.keys() and all(
        (math.isnan(a[k]) and math.isnan(b[k])) or a[k] == b[k] for k in a)


def test_the_benchmark_controller_through_the_env_gives_the_benchmark_bitwise():
    over = {"protocol.timeout": 5.0}
    env = make(method="cwc-tdt", instance="A-01", overrides=over).unwrapped
    env.reset(seed=0)
    ctrl = env.reference_controller()
    total, n = 0.0, 0
    while True:
        act = env.adapter.reference_action(ctrl(env.sensed))
        assert env.action_space.contains(act)
        _, r, term, trunc, info = env.step(act)
        total += r
        n += 1
        assert r == pytest.approx(sum(info["reward_terms"].values()))
        if term or trunc:
            break
    got = env.trial_result()
    ref = SYSTEM.run_trial(SYSTEM.plan(methods=["cwc-tdt"], instances=["A-01"], overrides=over)[0])
    assert got.status == ref.status == "timeout"
    assert _same(got.metrics, ref.metrics)
    assert _same(info["metrics"], ref.metrics)
    assert got.timeseries.keys() == ref.timeseries.keys()
    for k in ref.timeseries:
        if k != "tau_env":  # the body law's diagnostic: an action carries none (NaN in the env)
            np.testing.assert_array_equal(got.timeseries[k], ref.timeseries[k], err_msg=k)
    assert np.isnan(got.timeseries["tau_env"]).all() and not np.isnan(ref.timeseries["tau_env"][:-1]).any()
    assert n == 200 and set(info["reward_terms"]) == {"progress", "energy", "success"}


def test_timeout_truncates_and_a_fall_terminates():
    env = make(method="d-tdt", instance="A-01", overrides={"protocol.timeout": 0.1}).unwrapped
    env.reset(seed=1)
    zero = np.zeros(env.action_space.shape)
    flags = [env.step(zero)[2:4] for _ in range(4)]
    assert flags[:3] == [(False, False)] * 3 and flags[3] == (False, True)
    with pytest.raises(RuntimeError, match="call reset"):
        env.step(zero)
    # a fall ends the episode by the task's own check: terminated, not truncated
    env = make(method="d-tdt", instance="A-01", overrides={"protocol.timeout": 0.1, "protocol.fall_z": 10.0}).unwrapped
    _, info = env.reset(seed=0)
    assert info["status"] == "fell"
    env = make(method="d-tdt", instance="A-01",
               overrides={"protocol.timeout": 0.1, "protocol.success_threshold": 20.0}).unwrapped
    _, info = env.reset(seed=0)
    assert info["status"] == "success"


def test_step_terminates_on_success_with_the_bonus():
    env = make(method="cwc-tdt", instance="A-01",
               overrides={"protocol.timeout": 5.0, "protocol.success_threshold": 12.6}).unwrapped
    env.reset(seed=0)
    ctrl = env.reference_controller()
    for _ in range(200):
        _, r, term, trunc, info = env.step(env.adapter.reference_action(ctrl(env.sensed)))
        if term or trunc:
            break
    assert (term, trunc, info["status"]) == (True, False, "success")
    assert info["reward_terms"]["success"] == 10.0 and "metrics" in info


def test_group_sampling_uses_the_env_rng_and_reset_options_pick_an_instance():
    env = make(group="B").unwrapped
    assert len(env.instance_ids) == 50 and all(i.startswith("B-") for i in env.instance_ids)
    a = [env.reset(seed=s)[1]["instance"] for s in (3, 4, 3)]
    assert a[0] == a[2]
    assert env.reset(options={"instance": "B-07"})[1]["instance"] == "B-07"
    with pytest.raises(ValueError, match="not one of"):
        env.reset(options={"instance": "A-01"})
    env = make(instances=["A-02", "B-03"]).unwrapped
    assert {env.reset(seed=s)[1]["instance"] for s in range(8)} <= {"A-02", "B-03"}


def test_rgb_array_render():
    env = make(instance="A-01", render_mode="rgb_array", width=96, height=64)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (64, 96, 3) and frame.dtype == np.uint8 and frame.std() > 1
    env.close()


@pytest.mark.parametrize("kw, match", [
    ({"method": "nope"}, "unknown mrs-cwc method"),
    ({"instance": "Z-99"}, "unknown terrain"),
    ({"group": "C"}, "unknown mrs-cwc group"),
    ({"instance": "A-01", "group": "A"}, "one of instance"),
    ({"overrides": {"protocol.nope": 1}}, "nope"),
])
def test_bad_arguments_are_value_errors(kw, match):
    with pytest.raises(ValueError, match=match):
        gymnasium.make(ENV_ID, **kw)


def test_unknown_system_and_systems_without_env():
    from terrabench.envs.core import TerrabenchEnv

    with pytest.raises(ValueError, match="nosuch"):
        TerrabenchEnv("nosuch")
    with pytest.raises(ValueError, match="no Gymnasium environment"):
        TerrabenchEnv("beams")
    with pytest.raises(ValueError, match="render_mode"):
        TerrabenchEnv("mrs-cwc", render_mode="depth_array")
