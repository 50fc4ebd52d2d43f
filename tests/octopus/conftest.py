"""Fixtures the OCTOPUS tests share: an episode begun (step-400 unless said), or CLM stepped a few
seconds on step-400."""

import pytest

from terrabench.sim.episode import Episode
from terrabench.systems.octopus.scenarios import SYSTEM


def begin(method: str = "clm", overrides: dict | None = None, instance: str = "step-400"):
    """An episode of ``method`` on ``instance`` (seed 0, a 30 s limit unless ``overrides`` say),
    begun: (task, controller, episode, first observation, stop)."""
    spec = SYSTEM.trial_spec(method, instance, 0, {"protocol.timeout": 30.0, **(overrides or {})})
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    return task, ctl, ep, obs, stop


def step_in(seconds: float = 3.0, method: str = "clm", overrides: dict | None = None):
    """An episode on step-400 stepped ``seconds`` in (arms placed, tracks and tips on the ground):
    (task, controller, episode, last observation, last command)."""
    task, ctl, ep, obs, stop = begin(method, overrides)
    cmd = None
    while obs.t < seconds and stop is None:
        cmd = ctl(obs)
        obs, stop = ep.step(cmd)
    assert stop is None
    return task, ctl, ep, obs, cmd


@pytest.fixture
def octopus_begin():
    """:func:`begin`, for a test that steps its own episode."""
    return begin


@pytest.fixture
def octopus_episode():
    """:func:`step_in`, for a test that needs its own episode (other seconds or settings)."""
    return step_in


@pytest.fixture(scope="module")
def walking():
    """CLM 3 s into step-400, shared by a module's tests."""
    return step_in()
