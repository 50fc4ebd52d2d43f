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
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import gymnasium

from terrabench.benchmark.trial import TRUNCATIONS, TrialResult


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
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 40}

    def __init__(self, system: str, method: str | None = None, instance: str | None = None,
                 instances: Sequence[str] | None = None, group: str | None = None, seed: int = 0,
                 overrides: Mapping[str, Any] | None = None, render_mode: str | None = None,
                 width: int = 480, height: int = 360):
        from terrabench.catalog import system as get_system

        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"unknown render_mode {render_mode!r}; valid: None, {', '.join(self.metadata['render_modes'])}")
        if sum(x is not None for x in (instance, instances, group)) > 1:
            raise ValueError("give one of instance, instances or group")
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise ValueError(f"seed (the trial seed) must be an integer >= 0, got {seed!r}")
        self.system = get_system(system)
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
        self.observation_space = self.adapter.observation_space(probe)
        self.action_space = self.adapter.action_space(probe)
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
        return self._x, self._info(stop, {})

    def step(self, action):
        if self.episode is None:
            raise RuntimeError("call reset() before step()")
        ep = self.episode
        if self._stop is not None:
            raise RuntimeError(f"the episode has ended ({self._stop[0]}); call reset()")
        cmd = self.adapter.command(action, self.task)
        e0 = ep.energy
        obs, stop = ep.step(cmd)
        self._stop = stop
        x = self.adapter.observation(obs)
        status = stop[0] if stop else "running"
        reward, terms = self.adapter.reward(self._x, x, ep.energy - e0, status)
        self._x = x
        truncated = stop is not None and stop[0] in TRUNCATIONS
        terminated = stop is not None and not truncated
        return x, float(reward), terminated, truncated, self._info(stop, terms)

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
