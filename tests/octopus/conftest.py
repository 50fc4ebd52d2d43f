"""Fixtures the OCTOPUS tests share: a CLM episode stepped a few seconds into step-400."""

import pytest

from terrabench.sim.episode import Episode
from terrabench.systems.octopus.scenarios import SYSTEM


def step_in(seconds: float = 3.0, method: str = "clm", overrides: dict | None = None):
    """An episode on step-400 stepped ``seconds`` in (arms placed, tracks and tips on the ground):
    (task, controller, episode, last observation, last command)."""
    spec = SYSTEM.plan(methods=[method], instances=["step-400"], seeds=1,
                       overrides={"protocol.timeout": 30.0, **(overrides or {})})[0]
    cfg = SYSTEM.load_config(spec.config)
    task = SYSTEM.make_task(spec, cfg)
    ctl = SYSTEM.make_controller(spec, cfg, task)
    ep = Episode(task)
    obs, stop = ep.begin()
    cmd = None
    while obs.t < seconds and stop is None:
        cmd = ctl(obs)
        obs, stop = ep.step(cmd)
    assert stop is None
    return task, ctl, ep, obs, cmd


@pytest.fixture
def octopus_episode():
    """:func:`step_in`, for a test that needs its own episode (other seconds or settings)."""
    return step_in


@pytest.fixture(scope="module")
def walking():
    """CLM 3 s into step-400, shared by a module's tests."""
    return step_in()
