"""Run trial specs on local processes or a Ray cluster, writing each result as it lands.

The runner knows nothing about robots: it ships a :class:`TrialSpec` to a worker, the worker
looks the system up in the catalog and calls its ``run_trial(spec)`` (the contract in
:mod:`terrabench.systems.base`). Every finished trial
is written to the store at once, so an interrupted run loses only the trials in flight, and a
re-run skips the keys already stored. A trial that raises becomes a row with status
``error`` (and the traceback in ``info``), never a lost run.

The backends live beside this module: :mod:`terrabench.benchmark.pool` (local processes),
:mod:`terrabench.benchmark.ray_backend` (Ray), both running :func:`terrabench.benchmark.worker.execute`.

Faults (see "Runner faults" in ``docs/design.md``):

- The local backend runs its own small pool: one spawned process per slot, fed one spec at a
  time over a pipe, so the parent always knows which spec a worker holds. A worker that dies
  mid-trial (signal, segfault, ``os._exit``, OOM kill) costs only that trial: it is run once
  more in a fresh worker, and if that worker dies too the trial is stored as ``error`` with
  ``info["error"] = "worker died: signal 9 (SIGKILL)"`` (or ``"exit code 3"``).
- A trial that returns nothing within its wall-clock budget (:func:`default_wall_budget`, or
  ``wall_budget=``) is killed with its worker and stored as ``error`` (``"hung: ..."``); it is
  not retried within the run.
- On Ray, tasks have ``max_retries=1``: Ray reruns a task whose worker died once; a second
  death, a hang past the budget, or a lost node give an ``error`` row.
- ``error`` rows are faults, not physics: the next run of the same specs runs them again
  (``RunSummary.rerun_errors``); every other status is final.
"""

from __future__ import annotations

import contextlib
import math
import signal
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence, Union

from terrabench.benchmark.pool import run_pool
from terrabench.benchmark.ray_backend import run_ray
from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.benchmark.worker import code_fingerprint, default_workers, execute, host_fingerprint

__all__ = ["BACKENDS", "RunSummary", "code_fingerprint", "default_wall_budget", "default_workers", "execute",
           "host_fingerprint", "run_trials", "sim_timeout"]

BACKENDS = ("local", "ray")

#: The default budget allows this many times the measured-speed wall time ...
BUDGET_SAFETY = 5.0
#: ... plus this much for building the model, planning and logging (seconds).
BUDGET_OVERHEAD_S = 120.0
#: Budget when a spec's simulated timeout cannot be read from its config (one hour).
FALLBACK_WALL_BUDGET_S = 3600.0

WallBudget = Union[float, Callable[[TrialSpec], float], None]


@dataclass
class RunSummary:
    """What a call to :func:`run_trials` did.

    Attributes:
        requested: distinct specs asked for.
        skipped: specs already stored with a final status (not run).
        finished: trials stored by this run.
        statuses: status -> count of the trials stored by this run.
        wall_time: seconds the run took.
        interrupted: Ctrl-C / SIGTERM stopped the run (finished trials are stored).
        retried: trials run a second time because the worker holding them died (on Ray:
            trials whose retry by Ray died as well; Ray does not report a retry that worked).
        worker_deaths: worker processes that died while holding a trial.
        hung: trials killed for exceeding their wall-clock budget (stored as ``error``).
        rerun_errors: ``error`` rows from earlier runs that this run ran again.
        other_code: of the ``skipped`` trials, those whose stored row another terrabench code made
            (its ``info.host.code`` differs from :func:`~terrabench.benchmark.worker.code_fingerprint`
            here, or was not recorded): reused as stored, since a key names the spec, not the code.
        rerun_other_code: such trials this run ran again instead (``run_trials(rerun_other_code=True)``,
            ``terrabench run --rerun-other-code``).
        errors: reason -> count of this run's ``error`` rows (``"worker died: signal 9
            (SIGKILL)"``, ``"hung: ..."``, ``"ValueError: ..."``).

    :attr:`faults` (the number of ``error`` rows this run stored) is what a command line
    should turn into a non-zero exit status (1): the run finished, but some trials did not.
    :meth:`describe` gives the one-line summary to print.
    """

    requested: int
    skipped: int
    finished: int = 0
    statuses: dict[str, int] = field(default_factory=dict)
    wall_time: float = 0.0
    interrupted: bool = False
    retried: int = 0
    worker_deaths: int = 0
    hung: int = 0
    rerun_errors: int = 0
    other_code: int = 0
    rerun_other_code: int = 0
    errors: dict[str, int] = field(default_factory=dict)

    @property
    def faults(self) -> int:
        """Trials stored as ``error`` by this run (exceptions, dead or hung workers)."""
        return self.statuses.get("error", 0)

    def describe(self) -> str:
        """The one-line summary, e.g. ``"6 trials requested, 0 already stored, 6 run in 12.3 s;
        statuses {...}; 1 retried after a worker died; 1 error (worker died: signal 9 (SIGKILL))"``."""
        parts = [
            f"{self.requested} trials requested, {self.skipped} already stored, {self.finished} run "
            f"in {self.wall_time:.1f} s",
            f"statuses {self.statuses or '{}'}",
        ]
        if self.retried:
            parts.append(f"{self.retried} retried after a worker died")
        if self.hung:
            parts.append(f"{self.hung} hung past the wall budget")
        if self.faults:
            reasons = ", ".join(f"{n}x {r}" if n > 1 else r for r, n in self.errors.items())
            parts.append(f"{self.faults} error ({reasons})")
        if self.rerun_errors:
            parts.append(f"{self.rerun_errors} error rows from earlier runs retried")
        if self.other_code:
            parts.append(f"{self.other_code} of the stored trials were made by other terrabench code (another "
                         f"checkout or version) and are reused as stored; --rerun-other-code or a new --store "
                         f"runs them with this code")
        if self.rerun_other_code:
            parts.append(f"{self.rerun_other_code} stored trials made by other terrabench code run again")
        if self.interrupted:
            parts.append("interrupted")
        return "; ".join(parts)


# ------------------------------------------------------------------------------ wall budgets
def sim_timeout(spec: TrialSpec) -> float | None:
    """The simulated time limit (s) a spec's config sets, or ``None`` if it has none.

    Reads the system's ``timeout_key`` (``"protocol.timeout"`` for mrs-cwc) from
    ``spec.config``; an unknown system, a system without a time limit, a missing key or a
    non-positive value give ``None``.
    """
    from terrabench.catalog import system

    try:
        key = system(spec.system).timeout_key
    except ValueError:  # a system this process does not know
        return None
    if key is None:
        return None
    node: Any = spec.config
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    try:
        value = float(node)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) and value > 0 else None


def default_wall_budget(spec: TrialSpec) -> float:
    """Wall-clock seconds a trial may take before it counts as hung.

    ``BUDGET_OVERHEAD_S + BUDGET_SAFETY * timeout / rtf``, with ``rtf`` the system's measured
    :attr:`~terrabench.systems.base.System.realtime_factor` (MRS-CWC, 20x real time at its
    released 2.5 ms step: 370 s for the released 1000 s timeout; srwmr, 10x: 470 s for a 700 s
    task), or ``FALLBACK_WALL_BUDGET_S`` (1 h) when the spec's simulated timeout is unknown.
    """
    from terrabench.catalog import system

    t = sim_timeout(spec)
    if t is None:
        return FALLBACK_WALL_BUDGET_S
    return BUDGET_OVERHEAD_S + BUDGET_SAFETY * t / system(spec.system).realtime_factor


def _budget_fn(wall_budget: WallBudget) -> Callable[[TrialSpec], float]:
    if wall_budget is None:
        return default_wall_budget
    if callable(wall_budget):
        return wall_budget
    value = float(wall_budget)
    if not value > 0:
        raise ValueError(f"wall_budget must be positive seconds, got {wall_budget!r}")
    return lambda spec: value


# ------------------------------------------------------------------------------ run_trials
@contextlib.contextmanager
def _interrupts_deferred():
    """Hold SIGINT / SIGTERM while a result is written; they take effect once it is committed.

    DuckDB checks for signals while it executes and turns a ``KeyboardInterrupt`` raised by
    the handler into its own ``InterruptException`` (an ``Exception``), which code meant for
    other errors could swallow, losing the trial being written. Here the handlers only note
    the signal; the noted one is handed to the previous handler after the commit. (Blocking
    the signal would not do: DuckDB's threads would take it.)
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[signal.Signals] = []
    held = [sig for sig in (signal.SIGINT, signal.SIGTERM)]
    old = {sig: signal.signal(sig, lambda signum, frame: caught.append(signal.Signals(signum))) for sig in held}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        if caught:
            handler = old[caught[0]]
            if callable(handler):
                handler(caught[0], None)
            elif handler == signal.SIG_DFL:
                signal.raise_signal(caught[0])


def run_trials(
    specs: Sequence[TrialSpec],
    store: ResultsStore,
    *,
    backend: str = "local",
    workers: int | None = None,
    address: str | None = None,
    on_result: Callable[[TrialSpec, TrialResult], None] | None = None,
    on_start: Callable[[int], None] | None = None,
    wall_budget: WallBudget = None,
    in_process: bool | None = None,
    rerun_other_code: bool = False,
) -> RunSummary:
    """Run the specs not yet in ``store``; store each result as soon as it arrives.

    Stored rows with status ``error`` do not count as done: they are run again (and
    replaced); every other status is final.

    Args:
        specs: trials to run (duplicates by key are run once).
        store: where results go.
        backend: ``"local"`` (worker processes; see ``in_process``) or ``"ray"``.
        workers: parallel trials (default: the cores available).
        address: Ray cluster address (``None`` starts a local Ray instance). An address where
            nothing answers is refused with a ``ValueError`` within a few seconds.
        on_result: called after each stored result (progress bars hook in here).
        on_start: called once with the number of trials to run.
        wall_budget: wall-clock seconds a trial may take before it is killed and stored as
            ``error`` ("hung"): a number for every trial, a callable ``spec -> seconds``, or
            ``None`` for :func:`default_wall_budget` (derived from the spec's simulated timeout).
        in_process: run the trials in this process, one after the other. ``None`` (default)
            does so only when ``workers == 1`` and no ``wall_budget`` is given, as before; in
            this process a trial that hangs, segfaults or calls ``os._exit`` cannot be survived
            (a Python exception still becomes an ``error`` row). ``False`` always uses worker
            processes (fault-tolerant, also for one worker); ``True`` refuses a ``wall_budget``.
        rerun_other_code: run again (and replace) the stored trials another terrabench code made
            (:attr:`RunSummary.other_code`); by default they are reused as stored and counted.
    """
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if in_process and wall_budget is not None:
        raise ValueError("in_process=True cannot enforce a wall_budget; use worker processes (in_process=False)")
    budget_of = _budget_fn(wall_budget)
    unique = list({s.key: s for s in specs}.values())
    done = store.done_keys([s.key for s in unique], retry_errors=True)
    here = code_fingerprint()
    other = {k for k, code in store.code_of(done).items() if code != here} if done else set()
    if rerun_other_code:
        done -= other
    todo = [s for s in unique if s.key not in done]
    summary = RunSummary(requested=len(unique), skipped=len(unique) - len(todo))
    summary.rerun_errors = len(store.error_keys([s.key for s in todo])) if todo else 0
    if rerun_other_code:
        summary.rerun_other_code = len(other)
    else:
        summary.other_code = len(other)
    if on_start:
        on_start(len(todo))
    t0 = time.perf_counter()

    def land(spec: TrialSpec, result: TrialResult) -> None:
        with _interrupts_deferred():
            store.write(spec, result)
        summary.finished += 1
        summary.statuses[result.status] = summary.statuses.get(result.status, 0) + 1
        if result.status == "error":
            reason = str(result.info.get("error", "error")).splitlines()[0] if result.info else "error"
            reason = reason if len(reason) <= 80 else reason[:77] + "..."
            summary.errors[reason] = summary.errors.get(reason, 0) + 1
        if on_result:
            on_result(spec, result)

    n_workers = workers or default_workers()
    if in_process is None:
        in_process = backend == "local" and n_workers == 1 and wall_budget is None
    try:
        if not todo:
            pass
        elif backend == "ray":
            run_ray(todo, land, workers, address, budget_of, summary)
        elif in_process:
            for spec in todo:
                land(spec, execute(spec))
        else:
            run_pool(todo, land, n_workers, budget_of, summary)
    except KeyboardInterrupt:
        summary.interrupted = True
    summary.wall_time = time.perf_counter() - t0
    return summary
