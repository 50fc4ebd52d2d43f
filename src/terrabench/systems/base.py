"""The contract between a system and the hallway (runner, store, CLI, envs, perf, render).

A system writes four things and registers one object:

* a **Task** (:class:`Task`): one episode of the robot on one instance. It builds its arena and
  robot into an ``MjSpec`` with named parts, binds the names to ids and sensor views, applies a
  command (limits and run-time model changes included), checks whether to stop, logs one row,
  reports instantaneous power, and turns the finished :class:`~terrabench.sim.episode.EpisodeLog`
  into named metrics. The shared loop in :mod:`terrabench.sim.episode` steps it.
* a **Controller**: a callable ``obs -> cmd`` that sees only the task's observation (what the
  real robot measures), never the simulator.
* its **scenarios**: methods, instances and groups, the config class.
* its **report**: ``summarize(rows)`` (a rich table beside the paper) and ``report(store, out)``.

:class:`System` holds the generic parts (planning trial specs from a user's request, resolving
and validating configs, running one spec through the episode loop); a system subclasses it and
fills the hooks. The CLI and runner read nothing else: ``timeout_key`` names the config field
that ``--timeout`` sets, ``headline_metrics`` the columns of the per-trial table.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Mapping, Protocol, Sequence, runtime_checkable

import numpy as np

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.config import from_dict, override, to_dict

if TYPE_CHECKING:  # types of the contract only (no import at run time)
    import mujoco
    from rich.console import RenderableType

    from terrabench.benchmark.store import ResultsStore
    from terrabench.envs.adapter import EnvAdapter
    from terrabench.registry import Registry
    from terrabench.sim.episode import EpisodeLog, OnStep, Timing
    from terrabench.sim.physics import PhysicsConfig


@runtime_checkable
class Task(Protocol):
    """One episode of a MuJoCo system (see :mod:`terrabench.sim.episode` for the loop order).

    Attributes:
        physics: :class:`~terrabench.sim.physics.PhysicsConfig` of the scene.
        timing: :class:`~terrabench.sim.episode.Timing` (control period, timeout, cadences).
        columns: names of the values :meth:`row` returns, in order.
        before_substep: optional ``(model, data) -> None`` called before every physics step
            (e.g. soil forces into ``data.xfrc_applied``); None (:class:`TaskBase`'s default)
            keeps the C fast path.
    """

    physics: PhysicsConfig
    timing: Timing
    columns: tuple[str, ...]
    before_substep: Callable[[mujoco.MjModel, mujoco.MjData], None] | None

    def build(self, spec: mujoco.MjSpec) -> None:
        """Add the arena and the robot to an empty ``mujoco.MjSpec`` (physics is set already)."""

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> Any:
        """Resolve names to ids after compiling; return the observation object."""

    def observe(self) -> Any:
        """The observation after the last physics step (may be the same object, refreshed)."""

    def apply(self, cmd: Any) -> None:
        """Write a command into ``data.ctrl`` / the model (limits applied here)."""

    def check(self, obs: Any, slow: bool) -> tuple[str, str] | None:
        """``(status, reason)`` to stop, else None. ``slow`` every ``timing.check_period``."""

    def row(self, obs: Any, cmd: Any | None) -> Sequence[float]:
        """One log row (``cmd`` None at the final instant: command columns NaN)."""

    def power(self, obs: Any) -> float:
        """Instantaneous electrical-mechanical power drawn (W), for the energy integral."""

    def metrics(self, log: EpisodeLog) -> dict[str, float]:
        """Named figures of the finished episode."""

    def info(self) -> dict[str, Any]:
        """JSON-serialisable extras stored in the trial's ``info`` (e.g. the start height)."""


class TaskBase:
    """Defaults for the optional parts of :class:`Task`; a system's task subclasses it."""

    #: ``(model, data) -> None`` before every physics step, or None for the C fast path
    before_substep: Callable[[mujoco.MjModel, mujoco.MjData], None] | None = None

    def info(self) -> dict[str, Any]:
        return {}


class Controller(Protocol):
    """``obs -> cmd``: sees only the task's observation.

    A controller may also define ``info() -> dict`` (JSON-serialisable): it is merged into the
    trial's stored ``info`` after the episode (see :func:`episode_result`). Controllers with
    discrete states record their changes as :class:`Transition` records and return them with
    :func:`events_info` under the key ``"events"``; reports draw a mode timeline from them.
    """

    def __call__(self, obs: Any) -> Any: ...


@dataclass(frozen=True)
class Transition:
    """One state change of a controller: at ``t`` (s, simulated) from ``src`` to ``dst``.

    ``reason`` is one line a reader understands (e.g. ``"pitch 1.21 rad >= 1.2"``). Stored in a
    trial's ``info["events"]`` as ``[t, src, dst, reason]`` lists (see :func:`events_info`).
    """

    t: float
    src: str
    dst: str
    reason: str = ""

    def as_list(self) -> list[Any]:
        return [round(float(self.t), 6), self.src, self.dst, self.reason]

    @classmethod
    def from_list(cls, item: Sequence[Any]) -> "Transition":
        t, src, dst, *rest = item
        return cls(float(t), str(src), str(dst), str(rest[0]) if rest else "")


class ModeMachine:
    """The current mode of a controller with discrete modes, and every change of it.

    A controller holds one machine and changes mode only through :meth:`go`, so the record of
    transitions (``info()["events"]``, the reports' mode timelines) cannot miss a change or
    record one that did not happen. Modes are named by strings, or by codes with ``names``
    mapping each code to its name (a controller that logs its mode as a number).
    :meth:`note` records an event that is not a change of the machine's mode (a sub-state of
    one limb, a guard firing inside a mode).
    """

    __slots__ = ("state", "events", "_names")

    def __init__(self, initial: Any, names: Mapping[Any, str] | None = None) -> None:
        self.state = initial
        self.events: list[Transition] = []
        self._names = names

    def name(self, state: Any = None) -> str:
        """The name of ``state`` (default: the current one)."""
        s = self.state if state is None else state
        return self._names[s] if self._names is not None else str(s)

    def go(self, t: float, dst: Any, reason: str = "") -> bool:
        """Enter ``dst`` at ``t`` (s) for ``reason``; True if that was a change (it is recorded)."""
        if dst == self.state:
            return False
        self.events.append(Transition(t, self.name(), self.name(dst), reason))
        self.state = dst
        return True

    def note(self, t: float, src: str, dst: str, reason: str = "") -> None:
        """Record an event that leaves the machine's mode as it is."""
        self.events.append(Transition(t, src, dst, reason))

    def info(self) -> dict[str, Any]:
        """``{"events": [...]}`` (:func:`events_info`) for the controller's ``info()``."""
        return events_info(self.events)


class MachineController:
    """Base of a controller whose discrete state is a :class:`ModeMachine` (``self.machine``, set
    by the subclass): its current ``state``, its recorded ``events`` and ``info()`` read from it."""

    machine: ModeMachine

    @property
    def state(self) -> Any:
        return self.machine.state

    @property
    def events(self) -> list[Transition]:
        return self.machine.events

    def info(self) -> dict[str, Any]:
        return self.machine.info()


def events_info(events: Sequence[Transition]) -> dict[str, Any]:
    """``{"events": [...]}`` for a controller's ``info()``: the transitions as JSON lists."""
    return {"events": [e.as_list() for e in events]}


def controller_info(controller: object) -> dict[str, Any]:
    """The controller's ``info()`` extras, or ``{}`` when it defines none."""
    fn = getattr(controller, "info", None)
    return dict(fn()) if callable(fn) else {}


@dataclass(frozen=True)
class MethodInfo:
    """A method a user can name: its id, one line for ``terrabench list`` and tags."""

    id: str
    summary: str
    tags: tuple[str, ...] = ()


class System:
    """Base of every system definition. Subclasses set the class attributes and hooks.

    Class attributes:
        id: the system id (``terrabench run ID``).
        summary: one line for ``terrabench list``: the paper and the robot (README's system table).
        status: one short line of what is built (README's system table, rendered with the groups'
            sizes by :mod:`terrabench.report.readme`).
        config_cls: root frozen dataclass of a trial's config (nested sections).
        groups: group id -> one-line description (``--group``); ``all`` is implied.
        default_group: the group planned when neither ``--group`` nor instances are given.
        timeout_key: dotted config key that ``--timeout`` sets (None: the system has none).
        threshold_key: dotted config key that ``--threshold`` sets (None: none).
        headline_metrics: metric names shown per trial by the CLI.
        env_ids: Gymnasium ids registered for this system (``terrabench list`` shows them).
        perf_instances: instances ``terrabench perf`` times by default.
        realtime_factor: simulated seconds per wall second of this system's slowest measured
            configuration with 2 processes on 2 cores; the runner's hung-trial budget divides the
            simulated timeout by it (:func:`terrabench.benchmark.runner.default_wall_budget`).
        status_notes: status -> what it means for this system (``terrabench list --statuses``).
        instance_format: one line on how instance ids are spelt (``terrabench list SYSTEM``);
            '' = shown as the ids' shapes with digits as N.
        smoke: keyword arguments of :meth:`plan` for a request that runs in seconds (the
            contract test in ``tests/test_contract.py`` runs it for every registered system).
        golden: plan requests (keyword arguments of :meth:`plan`) of a few short trials whose
            stored bits are pinned and must not depend on the CPU (:mod:`terrabench.benchmark.golden`;
            ``tests/test_portable_bits.py`` requires them of every registered system).
    """

    id: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    status: ClassVar[str] = ""
    config_cls: ClassVar[type] = object
    groups: ClassVar[Mapping[str, str]] = {}
    default_group: ClassVar[str | None] = None
    timeout_key: ClassVar[str | None] = None
    threshold_key: ClassVar[str | None] = None
    headline_metrics: ClassVar[tuple[str, ...]] = ()
    env_ids: ClassVar[tuple[str, ...]] = ()
    perf_instances: ClassVar[tuple[str, ...]] = ()
    realtime_factor: ClassVar[float] = 20.0
    instance_format: ClassVar[str] = ""
    status_notes: ClassVar[Mapping[str, str]] = {}
    smoke: ClassVar[Mapping[str, Any]] = {}
    golden: ClassVar[tuple[Mapping[str, Any], ...]] = ()

    # ------------------------------------------------------------------ scenarios (override)
    def methods(self) -> dict[str, MethodInfo]:
        """Every method id -> :class:`MethodInfo` (plug-ins may add to it at import time)."""
        raise NotImplementedError

    def default_methods(self) -> list[str]:
        return list(self.methods())

    def instances(self, group: str | None) -> list[str]:
        """Instance ids of ``group`` (None or ``"all"``: every instance), in run order."""
        raise NotImplementedError

    def scenario(self, method: str, instance: str) -> str:
        """The versioned scenario id a trial belongs to."""
        raise NotImplementedError

    def applies(self, method: str, instance: str) -> bool:
        """Whether ``method`` can run on ``instance``. The planner keeps only such pairs and
        ``terrabench list`` shows them per group; default: every pair."""
        return True

    def check_trial(self, method: str, instance: str, cfg: Any) -> None:
        """ValueError (one line naming the bad value and the valid ones) when ``cfg`` cannot run
        ``method`` on ``instance``; called by the planner for every planned pair before any
        simulation. Default: nothing to check beyond the config's own fields and relations."""

    def trial_config(self, method: str, instance: str, cfg: Any) -> dict[str, Any]:
        """The config stored with (and hashed into) a trial: by default the whole resolved one."""
        return to_dict(cfg)

    def seeds_for(self, method: str, instance: str, config: dict[str, Any], seeds: int) -> range:
        """The seeds a trial is run with (deterministic trials may need only seed 0)."""
        return range(seeds)

    def base_config(self) -> Any:
        return self.config_cls()

    # ------------------------------------------------------------------ planning (generic)
    def resolve_config(self, overrides: Mapping[str, Any] | None = None) -> Any:
        """The default config with ``--set`` overrides applied and validated."""
        return override(self.base_config(), dict(overrides or {}))

    def plan(self, *, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
             group: str | None = None, seeds: int = 1, overrides: Mapping[str, Any] | None = None) -> list[TrialSpec]:
        """Trial specs for (methods x instances x seeds); ValueError on any bad input.

        ``methods=["all"]`` means every method; ``instances`` and ``group`` are exclusive. The
        generic planner is :func:`terrabench.benchmark.plan.plan_specs`.
        """
        from terrabench.benchmark.plan import plan_specs

        return plan_specs(self, methods=methods, instances=instances, group=group, seeds=seeds, overrides=overrides)

    def trial_spec(self, method: str, instance: str, seed: int = 0,
                   overrides: Mapping[str, Any] | None = None) -> TrialSpec:
        """The spec of one trial (``method`` on ``instance``, ``seed``): the one :meth:`plan` gives
        for it among seeds 0..seed, checked the same way (for a probe, a study or a test that runs
        or steps one trial). ValueError for a seed the trial is not run with (a deterministic one
        runs seed 0 only, :meth:`seeds_for`)."""
        if not isinstance(seed, int) or seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
        specs = self.plan(methods=[method], instances=[instance], seeds=seed + 1, overrides=overrides)
        for s in specs:
            if s.seed == seed:
                return s
        raise ValueError(f"{self.id}: {method} on {instance} runs with seed(s) {sorted({s.seed for s in specs})}, "
                         f"not seed {seed}")

    def select_instances(self, ids: Sequence[str]) -> list[str]:
        """Validate user-given instance ids (default: members of ``instances(None)``)."""
        from terrabench.benchmark.plan import split_ids

        return split_ids(ids, f"{self.id} instance(s)", self.instances(None)) or []

    # ------------------------------------------------------------------ running (generic)
    def load_config(self, config: Mapping[str, Any]) -> Any:
        """Rebuild the config object a spec carries (missing sections take their defaults)."""
        return from_dict(self.config_cls, config)

    def make_task(self, spec: TrialSpec, cfg: Any) -> Task:
        """The task of one trial (MuJoCo systems override this)."""
        raise NotImplementedError(f"system {self.id!r} does not run through the episode loop")

    def make_controller(self, spec: TrialSpec, cfg: Any, task: Task) -> Callable[[Any], Any]:
        raise NotImplementedError

    def trial_parts(self, spec: TrialSpec) -> tuple[Any, Task, Any]:
        """(resolved config, task, controller) of one spec: what :meth:`run_trial` runs, for a
        study or probe that steps the episode itself (``Episode(task)``)."""
        cfg = self.load_config(spec.config)
        task = self.make_task(spec, cfg)
        return cfg, task, self.make_controller(spec, cfg, task)

    def run_trial(self, spec: TrialSpec, *, on_step: OnStep | None = None) -> TrialResult:
        """Run one spec through the shared episode loop; physics trouble is a status, not a raise."""
        t0 = time.perf_counter()
        _, task, controller = self.trial_parts(spec)
        result = run_task(task, controller, on_step=on_step)
        result.wall_time = time.perf_counter() - t0
        return result

    def env_adapter(self) -> EnvAdapter:
        """The Gymnasium glue of this system (spaces, observation/action mapping, reward terms);
        see :mod:`terrabench.envs`. Systems without an env leave this unimplemented."""
        raise NotImplementedError(f"system {self.id!r} has no Gymnasium environment")

    def render_overlay(self, task: Task, obs: Any) -> str:
        """The system's line of a rendered frame's text overlay (e.g. the stiffness K); '' for none."""
        return ""

    def clip_events(self, row: Mapping[str, Any], series: Mapping[str, np.ndarray]) -> dict[str, float]:
        """Named instants (simulated s) of one stored trial that a clip can be cut at (``terrabench
        render --at NAME``), read off its stored row and series: e.g. a mode switch, a lift. Every
        system has ``start`` and ``end``; a system adds its own."""
        t = np.asarray(series.get("t", ()), float)
        end = float(t[-1]) if t.size else float((row.get("metrics") or {}).get("sim_time", 0.0) or 0.0)
        return {"start": 0.0, "end": end}

    # ------------------------------------------------------------------ results (override)
    def summarize(self, rows: list[dict[str, Any]]) -> RenderableType:
        """A rich renderable of stored rows beside the paper's numbers."""
        from rich.table import Table

        t = Table(title=f"{self.id}: statuses")
        for c in ("method", "n", "statuses"):
            t.add_column(c)
        by: dict[str, dict[str, int]] = {}
        for r in rows:
            d = by.setdefault(r["method"], {})
            d[r["status"]] = d.get(r["status"], 0) + 1
        for m, d in by.items():
            t.add_row(m, str(sum(d.values())), ", ".join(f"{k} {v}" for k, v in sorted(d.items())))
        return t

    def report(self, store: ResultsStore, out_dir: Path) -> Path:
        raise NotImplementedError(f"system {self.id!r} has no report yet")

    # ------------------------------------------------------------------ registry
    def register(self, registry: Registry, target: str, scenario_summaries: Mapping[str, str] | None = None) -> None:
        """Add this system, its scenarios and its methods to ``registry``."""
        from terrabench.registry import Record

        registry.register(Record("system", self.id, self.summary, target, self.id))
        for sid, text in (scenario_summaries or {}).items():
            registry.register(Record("scenario", sid, text, target, self.id))
        for m in self.methods().values():
            registry.register(Record("method", m.id, m.summary, target, self.id, m.tags))


def run_task(task: Task, controller: Callable[[Any], Any], *, on_step: OnStep | None = None) -> TrialResult:
    """One episode of ``task`` driven by ``controller``, as a trial result (:func:`episode_result`)."""
    from terrabench.sim.episode import run_episode

    return episode_result(task, run_episode(task, controller, on_step=on_step), controller)


def episode_result(task: Task, log: EpisodeLog, controller: object = None) -> TrialResult:
    """A finished episode's :class:`TrialResult` (the benchmark's and the Gymnasium env's).

    Metrics are the task's plus ``sim_time``; the series is the log thinned to
    ``task.timing.log_period``; ``info`` holds the stop reason, the task's and the controller's
    ``info()`` extras (:func:`controller_info`, e.g. its ``events``) and the timing figures; the
    wall time is the episode's, scene compilation included.
    """
    metrics = task.metrics(log)
    metrics["sim_time"] = log.sim_time
    info = {"reason": log.reason, **task.info(), **controller_info(controller), "control_steps": log.steps,
            "physics_steps": int(log.timing["physics_steps"]), "wall_time": log.timing["wall"],
            "loop_time": log.timing["loop"], "engine_time": log.timing["engine"]}
    return TrialResult(log.status, metrics, log.thinned(task.timing.log_period), log.timing["wall"], info)


def check_finite_positive(name: str, value: Any, unit: str) -> None:
    """ValueError naming ``name`` unless ``value`` is a positive finite number."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number ({unit}), got {value!r}")

