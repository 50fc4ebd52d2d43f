"""One generic Gymnasium env over the hallway contract: :class:`TerrabenchEnv`.

``reset()`` plans the trial spec exactly as ``terrabench run`` does (``system.plan``), builds
the task with ``system.make_task(spec, cfg)``, compiles it with
:class:`~terrabench.sim.episode.Episode` and calls ``begin()``; ``step(action)`` turns the
action into the system's command with the system's adapter (``System.env_adapter()``, see
:mod:`terrabench.envs.adapter`) and calls ``Episode.step(cmd)``. The physics, the stop checks,
the log and the energy integral are therefore the benchmark's own: driven by the benchmark's
controller (through ``adapter.reference_action``) the env reproduces ``system.run_trial``
bitwise (:meth:`TerrabenchEnv.trial_result`).

``terminated`` is True when the task's stop check ended the episode (any status but
``timeout``: success, fell, diverged, ...); ``truncated`` when the time limit
(``timing.timeout``, e.g. ``overrides={"protocol.timeout": 20.0}``) did. ``info`` carries
``status`` (``running`` until the stop), ``reason``, ``reward_terms``, ``energy`` (J so far),
``instance`` and, at the stop, ``metrics`` (the benchmark's metrics of the episode).

Actions: a non-finite entry (NaN, inf) is a ``ValueError`` naming the entries; an action of the
wrong shape too, and one that is not numbers (strings, bools, complex, an int beyond float64);
entries outside the action space are **clipped** to it (``info["clipped"]`` counts them), as
the benchmark's own commands would be. ``overrides`` go through the same validation as
``terrabench run --set`` (a value outside a field's declared range is one ``ValueError``
naming the dotted key, before anything is built).

For learning libraries (e.g. Stable-Baselines3, whose ``check_env`` asks for float32 spaces,
actions normalised to [-1, 1] and 1-D observations), three options, all off by default so that
the default env is the benchmark's float64 interface, bitwise:

* ``dtype="float32"``: every observation block and the action space in float32;
* ``normalize_actions=True``: the action space is ``Box(-1, 1)``; an action ``a`` means
  ``low + (a + 1) (high - low) / 2`` of the original space (clipped to [-1, 1] first);
* ``flat_observations=True``: every observation block raveled to 1-D (e.g. ``pos`` (6, 3) ->
  (18,), unit-major).

``gymnasium.make(ID, dtype="float32", normalize_actions=True, flat_observations=True)`` gives
all three (:data:`LEARNER_OPTIONS`).
"""

from __future__ import annotations

import numbers
from typing import Any, Mapping, Sequence

import gymnasium
import numpy as np
from gymnasium import spaces

from terrabench.benchmark.trial import TRUNCATIONS, TrialResult

#: the keyword arguments that make an env Stable-Baselines3's checker accepts without warnings
LEARNER_OPTIONS = {"dtype": "float32", "normalize_actions": True, "flat_observations": True}

DTYPES = ("float64", "float32")


def _box_as(space: spaces.Box, dtype: Any, flat: bool) -> spaces.Box:
    low, high = space.low, space.high
    if flat:
        low, high = low.ravel(), high.ravel()
    return spaces.Box(low=low.astype(dtype), high=high.astype(dtype), dtype=dtype)


def _space_as(space: Any, dtype: Any, flat: bool) -> Any:
    """``space`` (a Box or a Dict of Boxes) with ``dtype`` and, if ``flat``, 1-D blocks."""
    if isinstance(space, spaces.Dict):
        return spaces.Dict({k: _space_as(v, dtype, flat) for k, v in space.spaces.items()})
    if isinstance(space, spaces.Box):
        return _box_as(space, dtype, flat)
    raise TypeError(f"only Box and Dict observation spaces can be converted, got {type(space).__name__}")


def _value_as(x: Any, dtype: Any, flat: bool) -> Any:
    if isinstance(x, dict):
        return {k: _value_as(v, dtype, flat) for k, v in x.items()}
    a = np.asarray(x, dtype=dtype)
    return a.ravel() if flat else a


class TerrabenchEnv(gymnasium.Env):
    """A benchmark system as a Gymnasium env.

    Args:
        system: system id (e.g. ``"mrs-cwc"``).
        method: the method whose robot variant is built and whose controller is the reference
            (default: the system's first default method).
        instance: one instance (terrain) id; or
        instances: a list of ids, one sampled with the env's ``np_random`` on every reset; or
        group: a group id (e.g. ``"B"``) to sample from. None of the three: the system's
            default group. ``reset(options={"instance": id})`` picks one explicitly.
        seed: the trial seed (the benchmark's ``--seeds`` index: 0 = the released start,
            > 0 jitters it); the env's RNG is seeded by ``reset(seed=...)``.
        overrides: ``--set``-style config overrides, e.g. ``{"protocol.timeout": 20.0}``.
        render_mode: None or ``"rgb_array"`` (frames from a camera following the robot).
        width, height: rendered frame size (pixels).
        dtype: ``"float64"`` (default, the benchmark's values) or ``"float32"`` spaces.
        normalize_actions: the action space is ``Box(-1, 1)``, mapped linearly onto the system's.
        flat_observations: every observation block 1-D.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 40}

    def __init__(self, system: str, method: str | None = None, instance: str | None = None,
                 instances: Sequence[str] | None = None, group: str | None = None, seed: int = 0,
                 overrides: Mapping[str, Any] | None = None, render_mode: str | None = None,
                 width: int = 480, height: int = 360, dtype: str = "float64", normalize_actions: bool = False,
                 flat_observations: bool = False):
        from terrabench import portable
        from terrabench.catalog import system as get_system

        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"unknown render_mode {render_mode!r}; "
                             f"valid: None, {', '.join(self.metadata['render_modes'])}")
        if sum(x is not None for x in (instance, instances, group)) > 1:
            raise ValueError("give one of instance, instances or group")
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise ValueError(f"seed (the trial seed) must be an integer >= 0, got {seed!r}")
        if dtype not in DTYPES:
            raise ValueError(f"unknown dtype {dtype!r}; valid: {', '.join(DTYPES)}")
        for name, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, int) or v <= 0:
                raise ValueError(f"{name} must be a positive whole number of pixels, got {v!r}")
        for name, v in (("normalize_actions", normalize_actions), ("flat_observations", flat_observations)):
            if not isinstance(v, bool):
                raise ValueError(f"{name} must be True or False, got {v!r}")
        self.system = get_system(system)
        portable.warn_if_unpinned(f"gymnasium env over {system!r}")
        try:
            self.adapter = self.system.env_adapter()
        except NotImplementedError as exc:
            raise ValueError(str(exc)) from None
        sysobj = self.system
        mid = method if method is not None else sysobj.default_methods()[0]
        if instance is not None:
            instances = [instance]
        specs = sysobj.plan(methods=[mid], instances=instances, group=group, seeds=seed + 1,
                            overrides=overrides)
        self.specs = {s.instance: s for s in specs if s.seed == seed}
        if not self.specs:
            raise ValueError(f"method {mid!r} runs on none of the chosen instances")
        self.method = mid
        self.instance_ids = list(self.specs)
        self.render_mode, self.width, self.height = render_mode, width, height
        first = self.specs[self.instance_ids[0]]
        probe = sysobj.make_task(first, sysobj.load_config(first.config))  # not compiled: spaces only
        self._dtype, self._flat, self._normalized = np.dtype(dtype), flat_observations, normalize_actions
        self.system_observation_space = self.adapter.observation_space(probe)
        self.system_action_space = act = self.adapter.action_space(probe)
        self._low, self._high = act.low.astype(np.float64), act.high.astype(np.float64)
        if normalize_actions and not (np.isfinite(self._low).all() and np.isfinite(self._high).all()):
            raise ValueError(f"normalize_actions needs a bounded action space; {system!r} has unbounded entries")
        self._plain = dtype == "float64" and not flat_observations
        self.observation_space = (self.system_observation_space if self._plain else
                                  _space_as(self.system_observation_space, self._dtype, flat_observations))
        if normalize_actions:
            self.action_space = spaces.Box(-1.0, 1.0, shape=act.shape, dtype=self._dtype)
        else:
            self.action_space = act if dtype == "float64" else _box_as(act, self._dtype, False)
        self.metadata = {**self.metadata, "render_fps": 1.0 / probe.timing.control_period}
        self.spec_ = first
        self.task = None
        self.episode = None
        self._renderer = None
        self._x = None

    # ------------------------------------------------------------------ gymnasium API
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        from terrabench.sim.episode import Episode

        super().reset(seed=seed)
        options = dict(options or {})
        inst = options.pop("instance", None)
        if options:
            raise ValueError(f"unknown reset option(s) {sorted(options)}; valid: instance")
        if inst is None:
            inst = self.instance_ids[int(self.np_random.integers(len(self.instance_ids)))]
        elif inst not in self.specs:
            raise ValueError(f"instance {inst!r} is not one of this env's: {', '.join(self.instance_ids)}")
        self.spec_ = spec = self.specs[inst]
        self.cfg = self.system.load_config(spec.config)
        self.task = self.system.make_task(spec, self.cfg)
        self._close_renderer()
        self.episode = Episode(self.task)
        self.adapter.reset(self.task)
        obs, stop = self.episode.begin()
        self._stop = stop
        self._x = self.adapter.observation(obs)
        return self._out(self._x), self._info(stop, {})

    def step(self, action):
        if self.episode is None:
            raise RuntimeError("call reset() before step()")
        ep = self.episode
        if self._stop is not None:
            raise RuntimeError(f"the episode has ended ({self._stop[0]}); call reset()")
        a, clipped = self.system_action(action)
        cmd = self.adapter.command(a, self.task)
        e0 = ep.energy
        obs, stop = ep.step(cmd)
        self._stop = stop
        x = self.adapter.observation(obs)
        status = stop[0] if stop else "running"
        reward, terms = self.adapter.reward(self._x, x, ep.energy - e0, status)
        self._x = x
        truncated = stop is not None and stop[0] in TRUNCATIONS
        terminated = stop is not None and not truncated
        info = self._info(stop, terms)
        info["clipped"] = clipped
        return self._out(x), float(reward), terminated, truncated, info

    def render(self):
        if self.render_mode != "rgb_array" or self.episode is None:
            return None
        from terrabench.report.render import SceneRenderer, overlay_text

        if self._renderer is None:
            self._renderer = SceneRenderer(self.episode.model, self.width, self.height)
        status = self._stop[0] if self._stop else "running"
        return self._renderer.render(self.episode.data, overlay_text(self.episode.data.time, status))

    def close(self):
        self._close_renderer()
        super().close()

    # ------------------------------------------------------------------ actions and observations
    def system_action(self, action: Any) -> tuple[np.ndarray, int]:
        """``action`` as the system's float64 action, clipped to its space, and how many entries
        were clipped; ValueError for a wrong shape or a non-finite entry (naming the entries)."""
        try:
            raw = np.asarray(action)
            # numbers only: a string ("0.1"), a bool or a complex entry is not silently cast
            if raw.dtype.kind == "O":
                if not all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)) for v in raw.flat):
                    raise TypeError("not numbers")
            elif raw.dtype.kind not in "iuf":
                raise TypeError(f"dtype {raw.dtype}")
            a = np.array(raw, dtype=np.float64)
        except (TypeError, ValueError, OverflowError):
            shown = " ".join(repr(action).split())
            shown = shown if len(shown) <= 120 else shown[:117] + "..."
            raise ValueError(f"action must be an array of numbers of shape {self.action_space.shape}, "
                             f"got {shown}") from None
        if a.shape != self.action_space.shape:
            raise ValueError(f"action must have shape {self.action_space.shape}, got {a.shape}")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            shown = ", ".join(f"[{i}] = {a.flat[i]}" for i in bad[:8]) + (" ..." if bad.size > 8 else "")
            raise ValueError(f"action has {bad.size} non-finite entr{'y' if bad.size == 1 else 'ies'} ({shown}); "
                             "every entry must be a finite number")
        if self._normalized:
            n = int(((a < -1.0) | (a > 1.0)).sum())
            a = self._low + (np.clip(a, -1.0, 1.0) + 1.0) * 0.5 * (self._high - self._low)
            return np.clip(a, self._low, self._high), n
        n = int(((a < self._low) | (a > self._high)).sum())
        return (np.clip(a, self._low, self._high) if n else a), n

    def normalized_action(self, action: Any) -> np.ndarray:
        """The normalised action (in [-1, 1]) whose system action is ``action`` (e.g. the
        benchmark controller's ``adapter.reference_action(cmd)``)."""
        a = np.clip(np.asarray(action, dtype=np.float64), self._low, self._high)
        return (2.0 * (a - self._low) / (self._high - self._low) - 1.0).astype(self._dtype)

    def _out(self, x: Any) -> Any:
        return x if self._plain else _value_as(x, self._dtype, self._flat)

    # ------------------------------------------------------------------ extras
    @property
    def sensed(self) -> Any:
        """The task's own observation object (what the benchmark's controller reads)."""
        return self.episode.obs

    def reference_controller(self):
        """The benchmark's controller of this episode's spec, built on the env's task."""
        return self.system.make_controller(self.spec_, self.cfg, self.task)

    def trial_result(self) -> TrialResult:
        """The finished episode as the benchmark's :class:`TrialResult` (status, metrics, series)."""
        if self._stop is None:
            raise RuntimeError("the episode has not ended yet")
        from terrabench.systems.base import episode_result

        return episode_result(self.task, self.episode.log())

    def _info(self, stop, terms: dict[str, float]) -> dict[str, Any]:
        info = {"status": stop[0] if stop else "running", "reason": stop[1] if stop else "",
                "reward_terms": dict(terms), "energy": float(self.episode.energy), "instance": self.spec_.instance}
        if stop is not None:
            info["metrics"] = self.trial_result().metrics
        return info

    def _close_renderer(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
