"""Speed of a system's episode loop against the raw MuJoCo engine on the same trajectory.

For each instance, passes from the same start, through the system contract:

1. a recording pass (not timed) that keeps a copy of every control period's command;
2. *loop*: a real episode (controller, sensing, logging), from its first observation to its
   stop;
3. *raw*: a fresh copy of the scene replaying exactly those commands: ``task.apply`` (the
   command's limits and run-time model changes, so the motion is the loop's) and ``mj_step``
   (with the task's per-substep hook, which is physics, when it has one); no sensing, no
   controller, no logging.

Loop and raw alternate ``repeats`` times and each keeps its fastest pass. Both are timed in
CPU time of this process (``time.process_time``; the loop's is the episode's own ``cpu``
timing), so a busy machine (another benchmark on the
other core) slows neither side's figure by preemption; scene compilation is outside both.

Reported: physics steps/s, real-time factor (simulated s per CPU s), loop/raw (1.0 = the
episode adds nothing) and the share of the loop's wall time spent inside ``mj_step``.
"""

from __future__ import annotations

import copy
import math
import time
from typing import TYPE_CHECKING, Any, Sequence

import mujoco
import numpy as np

from terrabench.sim.episode import EpisodeTask, run_episode
from terrabench.sim.scene import compile_scene

if TYPE_CHECKING:
    from rich.table import Table

    from terrabench.benchmark.trial import TrialSpec
    from terrabench.systems.base import System


def _specs(system: System, method: str | None, instances: Sequence[str] | None, seconds: float,
           repeats: int, overrides: dict[str, Any] | None) -> list[TrialSpec]:
    """The timed specs: seed 0 of each instance (default: the system's perf sample), the episode
    cut at ``seconds`` simulated seconds, with config ``overrides``; the arguments checked first."""
    if not (isinstance(seconds, (int, float)) and 0 < seconds < float("inf")):
        raise ValueError(f"--seconds must be a positive finite number, got {seconds!r}")
    if not (isinstance(repeats, int) and repeats >= 1):
        raise ValueError(f"--repeats must be a whole number >= 1, got {repeats!r}")
    chosen = list(instances) if instances else list(system.perf_instances)
    # a system without a time limit (a testbed that runs a fixed protocol) is timed as it is
    overrides = dict(overrides or {})
    if system.timeout_key:
        overrides[system.timeout_key] = seconds
    return system.plan(methods=[method or system.default_methods()[0]], instances=chosen, seeds=1,
                       overrides=overrides)


def measure(system: System, method: str | None, instances: Sequence[str] | None, seconds: float,
            repeats: int = 2, overrides: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """One row per instance (seed 0, the episode cut at ``seconds`` simulated seconds), with
    config ``overrides`` (dotted keys, as ``--set``)."""
    specs = _specs(system, method, instances, seconds, repeats, overrides)
    rows = []
    for spec in specs:
        cfg = system.load_config(spec.config)
        try:
            commands = _record(system, spec, cfg)
        except NotImplementedError:
            raise ValueError(f"system {system.id!r} does not run through the MuJoCo episode loop; "
                             f"perf times systems that do (see `terrabench list`)") from None
        loop_time = raw_time = float("inf")
        for _ in range(repeats):
            task = system.make_task(spec, cfg)
            log = run_episode(task, system.make_controller(spec, cfg, task))
            loop_time = min(loop_time, log.timing["cpu"])
            raw_time = min(raw_time, _replay(system.make_task(spec, cfg), commands))
        steps = log.timing["physics_steps"]
        rows.append({
            "instance": spec.instance, "method": spec.method, "status": log.status,
            "raw_steps_per_s": steps / raw_time, "raw_rtf": log.sim_time / raw_time,
            "loop_steps_per_s": steps / loop_time, "loop_rtf": log.sim_time / loop_time,
            "loop_over_raw": raw_time / loop_time, "engine_share": log.timing["engine"] / log.timing["loop"],
        })
    return rows


def _record(system: System, spec: TrialSpec, cfg: Any) -> list[Any]:
    commands: list[Any] = []
    task = system.make_task(spec, cfg)
    # controllers may return one command object mutated in place: keep copies
    run_episode(task, system.make_controller(spec, cfg, task),
                on_step=lambda task, obs, cmd: commands.append(copy.deepcopy(cmd)))
    return commands


def _replay(task: EpisodeTask, commands: list[Any]) -> float:
    m, d = compile_scene(task)
    task.bind(m, d)
    nsub = task.timing.substeps(task.physics.timestep)
    hook = task.before_substep
    apply = task.apply
    t0 = time.process_time()
    for cmd in commands:
        apply(cmd)
        if hook is None:
            mujoco.mj_step(m, d, nsub)
        else:
            for _ in range(nsub):
                hook(m, d)
                mujoco.mj_step(m, d)
    return time.process_time() - t0


#: the task's per-tick calls the parts table times (the episode contract's, ``EpisodeTask``)
PARTS = ("observe", "check", "row", "apply", "power")
#: the parts table's columns after the instance: us per control tick
PART_COLUMNS = ("loop", "mj_step", "controller", *PARTS, "rest", "outside")


def parts(system: System, method: str | None, instances: Sequence[str] | None, seconds: float,
          repeats: int = 2, overrides: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """Where the loop's time goes: one row per instance (the specs of :func:`measure`) with the
    wall-clock us per control tick of the whole loop, of ``mj_step`` (the episode's own engine
    timer), of the controller call and of each task call of :data:`PARTS`; ``rest`` the shared
    loop (and the timers, ~0.1-0.3 us a part), ``outside`` everything but ``mj_step`` and
    ``apply`` (what perf's raw replay does not run). Each figure is its fastest of ``repeats``
    episodes."""
    rows = []
    for spec in _specs(system, method, instances, seconds, repeats, overrides):
        best: dict[str, float] = {}
        for _ in range(repeats):
            us = _timed_parts(system, spec)
            best = {k: min(best.get(k, math.inf), v) for k, v in us.items()}
        best["rest"] = best["loop"] - sum(best[k] for k in ("mj_step", "controller", *PARTS))
        best["outside"] = best["loop"] - best["mj_step"] - best["apply"]
        rows.append({"instance": spec.instance, "method": spec.method, **best})
    return rows


def _timed_parts(system: System, spec: TrialSpec) -> dict[str, float]:
    cfg = system.load_config(spec.config)
    task = system.make_task(spec, cfg)
    try:
        controller = system.make_controller(spec, cfg, task)
    except NotImplementedError:
        raise ValueError(f"system {system.id!r} does not run through the MuJoCo episode loop; "
                         f"perf times systems that do (see `terrabench list`)") from None
    acc = dict.fromkeys(("controller", *PARTS), 0.0)
    clock = time.perf_counter

    def timed(name: str, fn: Any) -> Any:
        def call(*args: Any) -> Any:
            t0 = clock()
            out = fn(*args)
            acc[name] += clock() - t0
            return out
        return call

    for name in PARTS:  # instance attributes shadow the methods the loop looks up
        setattr(task, name, timed(name, getattr(task, name)))
    log = run_episode(task, timed("controller", controller))
    ticks = max(log.steps, 1)
    us = {k: 1e6 * v / ticks for k, v in acc.items()}
    us["loop"], us["mj_step"] = 1e6 * log.timing["loop"] / ticks, 1e6 * log.timing["engine"] / ticks
    us["ticks"] = float(ticks)
    return us


def parts_table(system_id: str, rows: list[dict[str, Any]]) -> Table:
    from rich.table import Table

    t = Table(title=f"{system_id}: where the loop's time goes, us per control tick (wall clock, each part's "
                    f"fastest of the repeats)")
    t.add_column("part")
    for r in rows:
        t.add_column(r["instance"], justify="right")
    notes = {"rest": "rest (the shared loop, timers)", "outside": "outside mj_step + apply (not in raw)"}
    for c in PART_COLUMNS:
        t.add_row(notes.get(c, c), *(f"{r[c]:.1f}" for r in rows))
    t.add_row("control ticks", *(f"{r['ticks']:.0f}" for r in rows))
    return t


def perf_table(system_id: str, rows: list[dict[str, Any]]) -> Table:
    from rich.table import Table

    methods = ", ".join(sorted({r["method"] for r in rows}))
    t = Table(title=f"{system_id} ({methods}) speed (CPU time): the episode loop vs raw mj_step replaying "
                    f"the same commands")
    for c in ("instance", "raw steps/s", "raw RTF", "loop steps/s", "loop RTF", "loop/raw", "mj_step share of loop"):
        t.add_column(c, justify="right")
    for r in rows:
        t.add_row(r["instance"], f"{r['raw_steps_per_s']:.0f}", f"{r['raw_rtf']:.0f}", f"{r['loop_steps_per_s']:.0f}",
                  f"{r['loop_rtf']:.0f}", f"{r['loop_over_raw']:.2f}", f"{100 * r['engine_share']:.0f} %")
    mean = lambda k: float(np.mean([r[k] for r in rows]))  # noqa: E731
    total_raw = sum(1 / r["raw_steps_per_s"] for r in rows)
    total_loop = sum(1 / r["loop_steps_per_s"] for r in rows)
    t.add_row("mean", f"{mean('raw_steps_per_s'):.0f}", f"{mean('raw_rtf'):.0f}", f"{mean('loop_steps_per_s'):.0f}",
              f"{mean('loop_rtf'):.0f}", f"{total_raw / total_loop:.2f}", f"{100 * mean('engine_share'):.0f} %")
    return t
