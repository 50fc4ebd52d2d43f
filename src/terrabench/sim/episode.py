"""The episode loop every MuJoCo system shares.

One control period of an episode is, in this order (the order is part of the contract: the
stored results of every system depend on it):

1. ``obs = task.observe()`` (after the physics of the previous period);
2. ``task.check(obs, slow)``: the task's stop check (success, fell, turned over, ...); every
   ``check_period`` the check is *slow* (the task may do housekeeping) and the loop then
   tests the state for divergence;
3. the time limit: the episode is *truncated* (status ``timeout``) once ``timeout`` simulated
   seconds have passed;
4. ``cmd = controller(obs)``, ``task.apply(cmd)``;
5. the log row ``task.row(obs, cmd)`` plus the energy so far, ``on_step(task, obs, cmd)``;
6. energy += control period x ``task.power(obs)``;
7. the physics: ``mj_step(model, data, nsub)`` in C, or, when the task has a
   ``before_substep(model, data)`` hook (soil forces), the hook and one ``mj_step`` per
   physics step.

When the episode stops, one last row is logged with ``cmd=None``. :class:`Episode` exposes
the loop one period at a time (the Gymnasium envs step it); :func:`run_episode` drives it
with a controller (the benchmark). Both run the same code, so an env stepped with the
benchmark's controller gives the benchmark's numbers bitwise.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Protocol, Sequence

import mujoco
import numpy as np

from terrabench.sim.physics import PhysicsConfig, diverged
from terrabench.sim.scene import SceneTask, compile_scene

#: ``(status, reason)`` that stops an episode (None: it goes on)
Stop = tuple[str, str]
#: ``on_step(task, obs, cmd)``: called once per control period after the command is applied
OnStep = Callable[[Any, Any, Any], None]


@dataclass(frozen=True)
class Timing:
    """The clock of an episode.

    Attributes:
        control_period: controller period (s); a whole number of physics steps.
        timeout: simulated-time limit (s); reaching it truncates the episode (status
            ``timeout``), it is not a failure of the robot's physics.
        check_period: how often the slow stop check and the divergence test run (s).
        log_period: period of the stored (thinned) time series (s); metrics use every period.
    """

    control_period: float
    timeout: float
    check_period: float
    log_period: float

    def __post_init__(self) -> None:
        for name in ("control_period", "timeout", "check_period", "log_period"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a positive finite number of seconds, got {v!r}")

    def substeps(self, timestep: float) -> int:
        """Physics steps per control period; ValueError if they do not divide."""
        ratio = self.control_period / timestep
        if abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1:
            raise ValueError(f"control period {self.control_period} s must be a whole number of physics "
                             f"steps ({timestep} s)")
        return int(round(ratio))


class EpisodeTask(SceneTask, Protocol):
    """What the loop reads of a task: the part of :class:`terrabench.systems.base.Task` it steps.

    Restated structurally because :mod:`terrabench.systems.base` imports this module; the type
    checker verifies that a ``Task`` is an ``EpisodeTask`` where ``run_task`` hands one over.
    Observations and commands are the system's own types.
    """

    @property
    def timing(self) -> Timing: ...

    @property
    def columns(self) -> tuple[str, ...]: ...

    @property
    def before_substep(self) -> Callable[[mujoco.MjModel, mujoco.MjData], None] | None: ...

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> Any: ...

    def observe(self) -> Any: ...

    def check(self, obs: Any, slow: bool) -> Stop | None: ...

    def apply(self, cmd: Any) -> None: ...

    def row(self, obs: Any, cmd: Any | None) -> Sequence[float]: ...

    def power(self, obs: Any) -> float: ...


@dataclass
class EpisodeLog:
    """A finished (or running) episode: status, the per-period log, energy and timing.

    Attributes:
        status: ``success``, ``timeout``, ``fell``, ``stuck``, ``turned_over``, ``diverged``
            (see :data:`terrabench.benchmark.trial.STATUSES`); ``running`` while stepping.
        reason: one line saying why it stopped.
        steps: control periods simulated.
        period: control period (s).
        columns: names of ``data``'s columns: the task's columns, then ``"energy"`` (J).
        data: (steps + 1, len(columns)) rows, one per control instant, the last one with the
            command columns NaN (no command was issued at the stop).
        timing: wall-clock figures (s): ``wall``, ``loop``, ``engine`` (inside ``mj_step``),
            ``cpu`` (this process's CPU time over the loop, what ``terrabench perf`` compares)
            and ``physics_steps``.
    """

    status: str
    reason: str
    steps: int
    period: float
    columns: tuple[str, ...]
    data: np.ndarray
    timing: dict[str, float] = field(default_factory=dict)

    @property
    def sim_time(self) -> float:
        return self.steps * self.period

    @property
    def energy(self) -> float:
        return float(self.data[-1, -1])

    def column(self, name: str) -> np.ndarray:
        """One column as a contiguous array, e.g. ``log.column("x")``."""
        return np.ascontiguousarray(self.data[:, self.columns.index(name)])

    def block(self, names: tuple[str, ...] | list[str]) -> np.ndarray:
        """Several adjacent-or-not columns as a contiguous (n, len(names)) array."""
        idx = [self.columns.index(n) for n in names]
        return np.ascontiguousarray(self.data[:, idx])

    def thinned(self, log_period: float) -> dict[str, np.ndarray]:
        """The stored time series: every ``log_period``, the last row always kept, ``t`` first."""
        n = self.data.shape[0]
        stride = max(1, int(round(log_period / self.period)))
        idx = np.arange(0, n, stride)
        if idx[-1] != n - 1:
            idx = np.append(idx, n - 1)
        out = {"t": idx * self.period}
        for j, name in enumerate(self.columns):
            out[name] = self.data[idx, j]
        return out


class Episode:
    """A task's scene stepped one control period at a time.

    ``ep = Episode(task)`` builds and compiles the scene; ``obs, stop = ep.begin()``;
    then ``obs, stop = ep.step(cmd)`` until ``stop`` is a ``(status, reason)`` pair;
    ``ep.log()`` is the :class:`EpisodeLog`.
    """

    def __init__(self, task: EpisodeTask, *, on_step: OnStep | None = None) -> None:
        self.wall0 = time.perf_counter()
        self.task = task
        self.model, self.data = compile_scene(task)
        self.obs = task.bind(self.model, self.data)
        tm: Timing = task.timing
        phys: PhysicsConfig = task.physics
        self.period = tm.control_period
        self.nsub = tm.substeps(phys.timestep)
        self.n_max = int(math.ceil(tm.timeout / self.period)) + 1
        self.check_every = max(1, int(round(tm.check_period / self.period)))
        self.max_speed = phys.max_speed
        self.columns = tuple(task.columns) + ("energy",)
        self._nc = len(task.columns)
        self._log = np.full((self.n_max, len(self.columns)), np.nan)
        self._substep = task.before_substep
        self.on_step = on_step
        self.energy = 0.0
        self.k = 0
        self.stop: Stop | None = None
        self.engine_time = 0.0
        self._loop0 = self._cpu0 = 0.0

    def begin(self) -> tuple[Any, Stop | None]:
        """Observe the dropped start; returns ``(obs, stop)`` (stop is None or (status, reason))."""
        self._loop0, self._cpu0 = time.perf_counter(), time.process_time()
        return self._observe()

    def _observe(self) -> tuple[Any, Stop | None]:
        task, k = self.task, self.k
        obs = task.observe()
        slow = k % self.check_every == 0
        stop = task.check(obs, slow)
        if stop is None and slow:
            why = diverged(self.model, self.data, self.max_speed)
            if why:
                stop = ("diverged", why)
        if stop is None and k == self.n_max - 1:
            stop = ("timeout", "time limit reached")
        if stop is not None:
            self.stop = stop
            self._store(k, task.row(obs, None))
        self.obs = obs
        return obs, stop

    def _store(self, k: int, values: Sequence[float]) -> None:
        """Log row ``k``: the task's row, then the energy so far (a tuple in one assignment)."""
        if isinstance(values, tuple):
            self._log[k] = (*values, self.energy)
        else:
            row = self._log[k]
            row[: self._nc] = values
            row[self._nc] = self.energy

    def step(self, cmd: Any) -> tuple[Any, Stop | None]:
        """Apply ``cmd`` for one control period; returns ``(obs, stop)``."""
        if self.stop is not None:
            raise RuntimeError(f"the episode has ended ({self.stop[0]}: {self.stop[1]}); start a new one")
        task, obs, k = self.task, self.obs, self.k
        task.apply(cmd)
        self._store(k, task.row(obs, cmd))
        if self.on_step is not None:
            self.on_step(task, obs, cmd)
        self.energy += self.period * task.power(obs)
        m, d = self.model, self.data
        t_in = time.perf_counter()
        if self._substep is None:
            mujoco.mj_step(m, d, self.nsub)
        else:
            hook = self._substep
            for _ in range(self.nsub):
                hook(m, d)
                mujoco.mj_step(m, d)
        self.engine_time += time.perf_counter() - t_in
        self.k = k + 1
        return self._observe()

    def log(self) -> EpisodeLog:
        """The episode so far (the whole episode once it has stopped)."""
        n = self.k + 1 if self.stop is not None else self.k
        status, reason = self.stop or ("running", "not finished")
        now = time.perf_counter()
        timing = {"wall": now - self.wall0, "loop": now - self._loop0, "engine": self.engine_time,
                  "cpu": time.process_time() - self._cpu0, "physics_steps": float(self.k * self.nsub)}
        return EpisodeLog(status, reason, self.k, self.period, self.columns, self._log[:n], timing)


def run_episode(task: EpisodeTask, controller: Callable[[Any], Any], *,
                on_step: OnStep | None = None) -> EpisodeLog:
    """Run ``task`` with ``controller`` (``obs -> cmd``) to its stop; returns the log.

    ``on_step(task, obs, cmd)``, if given, is called once per control period after the
    command is applied (studies that sample more than the stored columns; it must not change
    the state).
    """
    ep = Episode(task, on_step=on_step)
    obs, stop = ep.begin()
    step = ep.step
    while stop is None:
        obs, stop = step(controller(obs))
    return ep.log()
