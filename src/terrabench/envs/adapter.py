"""The system-specific glue of a Gymnasium env: :class:`EnvAdapter`.

:class:`~terrabench.envs.core.TerrabenchEnv` is generic over the hallway contract (a system's
``make_task``, the shared :class:`~terrabench.sim.episode.Episode`); everything that depends on
what the robot measures and commands lives in the adapter that ``System.env_adapter()``
returns (a new object per env). The env calls, per episode::

    adapter.reset(task)                         # after the task is bound, before begin()
    x = adapter.observation(obs)                # after begin() and every step
    cmd = adapter.command(action, task)         # the system's command for Episode.step
    r, terms = adapter.reward(prev_x, x, energy_j, status)

``observation_space(task)`` / ``action_space(task)`` may read only the task's configuration
(method, config), not its compiled model: the env asks for them before any episode, and they
must be the same for every instance the env samples. ``reference_action(cmd)`` maps the
benchmark controller's command back to an action, so that the benchmark's controller can drive
the env (the test that the env and the benchmark agree bitwise does that).
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np
from gymnasium import spaces


def box(*shape: int, low: float = -np.inf, high: float = np.inf) -> spaces.Box:
    """A float64 ``Box`` of ``shape`` (unbounded by default): the observation blocks of adapters."""
    return spaces.Box(low=low, high=high, shape=shape, dtype=np.float64)


@runtime_checkable
class EnvAdapter(Protocol):
    def observation_space(self, task: Any) -> Any:
        """The ``gymnasium.spaces`` space of :meth:`observation` (a ``Box`` or a ``Dict``)."""

    def action_space(self, task: Any) -> Any:
        """The ``gymnasium.spaces`` space of the actions :meth:`command` accepts."""

    def reset(self, task: Any) -> None:
        """A new episode of ``task`` starts (the task is bound): clear per-episode state."""

    def observation(self, obs: Any) -> Any:
        """The task's observation object as an element of the observation space (a copy)."""

    def command(self, action: Any, task: Any) -> Any:
        """The system's command for ``action`` (clipped to the action space)."""

    def reward(self, prev: Any, obs: Any, energy: float, status: str) -> tuple[float, dict[str, float]]:
        """``(reward, terms)`` of one period: ``prev``/``obs`` are :meth:`observation` values before
        and after it, ``energy`` the joules drawn in it, ``status`` the episode's status after it
        (``running`` or the stop status). ``reward == sum(terms.values())``."""

    def reference_action(self, cmd: Any) -> Any:
        """The action whose :meth:`command` is ``cmd`` (the benchmark controller as a policy)."""
