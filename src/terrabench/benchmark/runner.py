"""Run trial specs on local processes or a Ray cluster, writing each result as it lands.

The runner knows nothing about robots: it ships a :class:`TrialSpec` to a worker, the worker
looks the system up in the catalog and calls its ``run_trial(spec)`` (the contract in
:mod:`terrabench.systems.base`). Every finished trial
is written to the store at once, so an interrupted run loses only the trials in flight, and a
re-run skips the keys already stored. A trial that raises becomes a row with status
``error`` (and the traceback in ``info``), never a lost run.

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

import functools
import math
import os
import signal
import socket
import sys
import threading
import time
import traceback
from collections import deque
from dataclasses import dataclass, field
from multiprocessing import get_context
from multiprocessing.connection import wait as mp_wait
from typing import Any, Callable, Sequence, Union

from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialResult, TrialSpec

BACKENDS = ("local", "ray")

#: Simulated seconds per wall-clock second the slowest measured configuration reaches: the
#: MRS-CWC loop runs ~45x real time per core at a 5 ms step and ~20x at the released 2.5 ms
#: step with 2 processes sharing 2 cores (docs/performance.md). The default budget uses 20.
MEASURED_RTF = 20.0
#: The default budget allows this many times the measured-speed wall time ...
BUDGET_SAFETY = 5.0
#: ... plus this much for building the model, planning and logging (seconds).
BUDGET_OVERHEAD_S = 120.0
#: Budget when a spec's simulated timeout cannot be read from its config (one hour).
FALLBACK_WALL_BUDGET_S = 3600.0
#: A worker process that has not finished importing the systems by then is killed.
WORKER_START_BUDGET_S = 300.0
#: Consecutive worker processes that die (or stall) while starting before the run gives up.
MAX_START_FAILURES = 3
#: Ray task retries after a worker death (Ray's own mechanism).
RAY_MAX_RETRIES = 1
#: Seconds to wait for a TCP connection to a Ray cluster address before giving up.
RAY_CONNECT_TIMEOUT_S = 5.0

WallBudget = Union[float, Callable[[TrialSpec], float], None]


def execute(spec: TrialSpec) -> TrialResult:
    """Run one spec in this process; exceptions become an ``error`` result."""
    from terrabench.catalog import system

    t0 = time.perf_counter()
    try:
        result = system(spec.system).run_trial(spec)
    except Exception as exc:  # a bug in one trial must not end a 10,000-trial run
        result = TrialResult(
            status="error",
            info={"error": f"{type(exc).__name__}: {exc}", "traceback": traceback.format_exc(limit=8)},
        )
    if not result.wall_time:
        result.wall_time = time.perf_counter() - t0
    result.info["host"] = host_fingerprint()
    return result


@functools.lru_cache(maxsize=1)
def host_fingerprint() -> dict[str, Any]:
    """What besides the spec decides a trial's last bits: library versions and the CPU paths.

    A trial is a deterministic function of its spec *on one kind of machine*. numpy picks SIMD
    kernels at run time: on a CPU with AVX-512, ``np.arctan2`` (the chains' headings) differs
    from the scalar libm result in the last bit on ~7 % of inputs, and on a chaotic terrain a
    last-bit difference grows to metres within a minute (docs/performance.md). Stored with
    every row so that two stores can be compared knowing whether they can agree bitwise.
    """
    import platform

    import mujoco
    import numpy as np

    try:
        from numpy._core import _multiarray_umath as um  # numpy >= 2
    except ImportError:  # pragma: no cover - numpy 1.x
        from numpy.core import _multiarray_umath as um
    features = getattr(um, "__cpu_features__", {})
    simd = [f for f in getattr(um, "__cpu_dispatch__", []) if features.get(f)]
    return {"machine": platform.machine(), "python": platform.python_version(), "numpy": np.__version__,
            "mujoco": mujoco.__version__, "numpy_simd": simd}


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
        if self.interrupted:
            parts.append("interrupted")
        return "; ".join(parts)


def default_workers() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


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

    ``BUDGET_OVERHEAD_S + BUDGET_SAFETY * timeout / MEASURED_RTF`` (120 s + 5x the wall time at
    20x real time: 370 s for the released 1000 s timeout, 145 s for 50 s), or
    ``FALLBACK_WALL_BUDGET_S`` (1 h) when the spec's simulated timeout is unknown.
    """
    t = sim_timeout(spec)
    if t is None:
        return FALLBACK_WALL_BUDGET_S
    return BUDGET_OVERHEAD_S + BUDGET_SAFETY * t / MEASURED_RTF


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
    """
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if in_process and wall_budget is not None:
        raise ValueError("in_process=True cannot enforce a wall_budget; use worker processes (in_process=False)")
    budget_of = _budget_fn(wall_budget)
    unique = list({s.key: s for s in specs}.values())
    done = store.done_keys(retry_errors=True)
    todo = [s for s in unique if s.key not in done]
    summary = RunSummary(requested=len(unique), skipped=len(unique) - len(todo))
    summary.rerun_errors = len(store.error_keys([s.key for s in todo])) if todo else 0
    if on_start:
        on_start(len(todo))
    t0 = time.perf_counter()

    def land(spec: TrialSpec, result: TrialResult) -> None:
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
            _run_ray(todo, land, workers, address, budget_of, summary)
        elif in_process:
            for spec in todo:
                land(spec, execute(spec))
        else:
            _run_pool(todo, land, n_workers, budget_of, summary)
    except KeyboardInterrupt:
        summary.interrupted = True
    summary.wall_time = time.perf_counter() - t0
    return summary


def _fault_result(reason: str, kind: str, wall_time: float, **info: Any) -> TrialResult:
    return TrialResult(status="error", wall_time=wall_time, info={"error": reason, "fault": kind, **info})


def _exit_reason(exitcode: int | None) -> str:
    if exitcode is None:
        return "worker died: no exit status"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            return f"worker died: signal {-exitcode}"
        return f"worker died: signal {-exitcode} ({name})"
    return f"worker died: exit code {exitcode}"


# ------------------------------------------------------------------------------ local pool
def _worker_main(conn, systems: list[str], parent_pid: int) -> None:
    """Body of a pool worker: import the systems, say ready, then run one spec per message."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    _die_with_parent(parent_pid)
    try:
        from terrabench.catalog import system

        for name in systems:
            system(name)
    except Exception:
        pass  # execute() turns the same failure into an error row per trial
    conn.send(("ready", os.getpid()))
    while True:
        try:
            spec = conn.recv()
        except (EOFError, OSError):
            return
        if spec is None:
            return
        result = execute(spec)
        try:
            conn.send(("result", result))
        except (BrokenPipeError, EOFError, OSError):
            return
        except Exception as exc:  # a result that does not pickle
            conn.send(("result", TrialResult("error", wall_time=result.wall_time,
                                              info={"error": f"result could not be sent: {type(exc).__name__}: {exc}"})))


def _die_with_parent(parent_pid: int) -> None:
    """A worker whose parent is gone (killed with SIGKILL) ends too."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
        except Exception:
            pass

    def watch() -> None:
        while True:
            time.sleep(2.0)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, daemon=True).start()
    if os.getppid() != parent_pid:
        os._exit(1)


class _Slot:
    """One worker process and the spec it holds (if any)."""

    def __init__(self, ctx, systems: list[str]):
        parent_conn, child_conn = ctx.Pipe(duplex=True)
        self.proc = ctx.Process(target=_worker_main, args=(child_conn, systems, os.getpid()), daemon=True)
        self.proc.start()
        child_conn.close()  # so the parent sees EOF when the child dies
        self.conn = parent_conn
        self.ready = False
        self.spec: TrialSpec | None = None
        self.deaths = 0  # deaths the held spec already caused
        self.started = time.monotonic()
        self.budget = WORKER_START_BUDGET_S
        self.deadline: float | None = self.started + WORKER_START_BUDGET_S

    def give(self, spec: TrialSpec, deaths: int, budget: float) -> None:
        self.conn.send(spec)
        self.spec, self.deaths = spec, deaths
        self.started = time.monotonic()
        self.budget = budget
        self.deadline = self.started + budget

    def take(self) -> tuple[TrialSpec, int, float]:
        spec, deaths, elapsed = self.spec, self.deaths, time.monotonic() - self.started
        self.spec, self.deaths, self.deadline = None, 0, None
        return spec, deaths, elapsed

    def kill(self) -> None:
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join(5.0)
        self.conn.close()

    def stop(self) -> None:
        """Ask an idle worker to exit; kill it if it does not."""
        try:
            self.conn.send(None)
        except (BrokenPipeError, OSError):
            pass
        self.proc.join(2.0)
        self.kill()


def _run_pool(todo: list[TrialSpec], land, workers: int, budget_of, summary: RunSummary) -> None:
    # spawn: workers start clean (no inherited DuckDB handle or threads)
    ctx = get_context("spawn")
    systems = sorted({s.system for s in todo})
    queue: deque[tuple[TrialSpec, int]] = deque((s, 0) for s in todo)
    slots: list[_Slot] = []
    start_failures = 0
    clean = False
    try:
        for _ in range(min(workers, len(todo))):
            slots.append(_Slot(ctx, systems))

        def replace(slot: _Slot) -> None:
            slots.remove(slot)
            if queue and len(slots) < workers:
                slots.append(_Slot(ctx, systems))

        def died(slot: _Slot) -> None:
            nonlocal start_failures
            slot.proc.join(5.0)
            reason = _exit_reason(slot.proc.exitcode)
            slot.kill()
            if slot.spec is None:
                if not slot.ready:  # died while importing: not a trial's fault
                    start_failures += 1
                    if start_failures >= MAX_START_FAILURES:
                        raise ValueError(f"worker processes die while starting ({reason}); "
                                         f"{start_failures} in a row, giving up (check TERRABENCH_PLUGINS)")
            else:
                spec, deaths, elapsed = slot.take()
                summary.worker_deaths += 1
                if deaths == 0:
                    summary.retried += 1
                    queue.appendleft((spec, 1))  # first in line for the fresh worker
                else:
                    land(spec, _fault_result(reason, "worker_died", elapsed, attempts=deaths + 1))
            replace(slot)

        while queue or any(s.spec is not None for s in slots):
            for slot in slots:
                if slot.ready and slot.spec is None and queue:
                    spec, deaths = queue.popleft()
                    try:
                        slot.give(spec, deaths, budget_of(spec))
                    except (BrokenPipeError, OSError):
                        queue.appendleft((spec, deaths))  # it is dead; the wait below sees it
            if not slots:  # every slot retired but work is left (cannot happen; be safe)
                slots.append(_Slot(ctx, systems))
                continue
            now = time.monotonic()
            deadlines = [s.deadline for s in slots if s.deadline is not None]
            timeout = max(0.0, min(deadlines) - now) if deadlines else None
            ready = set(mp_wait([s.conn for s in slots] + [s.proc.sentinel for s in slots], timeout))
            for slot in list(slots):
                if slot.conn not in ready and slot.proc.sentinel not in ready:
                    continue
                alive = True
                try:
                    while slot.conn.poll():
                        msg = slot.conn.recv()
                        if msg[0] == "ready":
                            slot.ready, slot.deadline = True, None
                            start_failures = 0
                        elif msg[0] == "result" and slot.spec is not None:
                            spec, _, _ = slot.take()
                            land(spec, msg[1])
                except (EOFError, OSError):
                    alive = False
                except Exception:  # a message cut short by the death of its sender
                    alive = False
                if not alive or not slot.proc.is_alive():
                    died(slot)
            now = time.monotonic()
            for slot in list(slots):
                if slot.deadline is None or slot.deadline > now:
                    continue
                if slot.spec is None:  # stalled while starting
                    slot.kill()
                    start_failures += 1
                    if start_failures >= MAX_START_FAILURES:
                        raise ValueError(f"worker processes did not start within {WORKER_START_BUDGET_S:.0f} s, "
                                         f"{start_failures} in a row; giving up")
                    replace(slot)
                    continue
                spec, deaths, elapsed = slot.take()
                slot.kill()
                summary.hung += 1
                land(spec, _fault_result(f"hung: no result within the wall budget of {slot.budget:.1f} s",
                                         "hung", elapsed, wall_budget_s=slot.budget, attempts=deaths + 1))
                replace(slot)
        clean = True
    finally:
        # normal end: idle workers exit; interrupted or failed: the trials in flight are lost
        # anyway, so kill their workers now instead of waiting up to a whole trial for them
        for slot in slots:
            slot.stop() if clean else slot.kill()


# ------------------------------------------------------------------------------ Ray
def _check_reachable(address: str) -> None:
    """Refuse, within seconds, a Ray address where nothing listens (Ray itself retries for minutes)."""
    if address in ("auto", "local"):
        return
    hostport = address.split("://", 1)[-1].rstrip("/")
    host, sep, port = hostport.rpartition(":")
    if not sep or not port.isdigit():
        return  # let Ray judge an address in a form we do not know
    try:
        socket.create_connection((host.strip("[]") or "127.0.0.1", int(port)), timeout=RAY_CONNECT_TIMEOUT_S).close()
    except OSError as exc:
        raise ValueError(f"cannot reach a Ray cluster at {address!r}: {exc.strerror or exc} "
                         f"(nothing answered within {RAY_CONNECT_TIMEOUT_S:.0f} s)") from None


def _run_ray(todo: list[TrialSpec], land, workers: int | None, address: str | None, budget_of,
             summary: RunSummary) -> None:
    try:
        import ray
        from ray import exceptions as rex
    except ImportError:
        raise ValueError("backend 'ray' needs the ray extra: pip install 'terrabench[ray]'") from None
    started_here = not ray.is_initialized()
    if started_here:
        if address:
            _check_reachable(address)
        kwargs = {"address": address} if address else {"num_cpus": workers or default_workers()}
        try:
            ray.init(ignore_reinit_error=True, log_to_driver=False, include_dashboard=False, **kwargs)
        except (ConnectionError, TimeoutError, RuntimeError) as exc:
            msg = (str(exc).splitlines() or [type(exc).__name__])[0]
            raise ValueError(f"cannot connect to Ray at {address!r}: {msg}") from None
    remote = ray.remote(num_cpus=1, max_retries=RAY_MAX_RETRIES, retry_exceptions=False)(execute)
    # at most `window` tasks in flight, so a task's clock starts about when it starts running
    window = workers or max(1, int(ray.cluster_resources().get("CPU", 1)))
    attempts = RAY_MAX_RETRIES + 1
    pending = deque(todo)
    refs: dict[Any, tuple[TrialSpec, float, float]] = {}
    died = (rex.WorkerCrashedError, rex.NodeDiedError, getattr(rex, "OutOfMemoryError", rex.WorkerCrashedError),
            getattr(rex, "LocalRayletDiedError", rex.WorkerCrashedError))
    try:
        while pending or refs:
            while pending and len(refs) < window:
                spec = pending.popleft()
                # the budget covers Ray's retry too: one budget per attempt
                refs[remote.remote(spec)] = (spec, time.monotonic(), budget_of(spec) * attempts)
            now = time.monotonic()
            timeout = max(0.0, min(t0 + b for _, t0, b in refs.values()) - now)
            ready, _ = ray.wait(list(refs), num_returns=1, timeout=timeout)
            for ref in ready:
                spec, t0, _ = refs.pop(ref)
                try:
                    result = ray.get(ref)
                except died as exc:  # Ray retried once and the worker died again
                    summary.worker_deaths += attempts
                    summary.retried += RAY_MAX_RETRIES
                    first = (str(exc).strip().splitlines() or [""])[0]
                    result = _fault_result(f"worker died: ray {type(exc).__name__}", "worker_died",
                                           time.monotonic() - t0, attempts=attempts, detail=first[:500])
                except Exception as exc:  # anything else Ray raises for this task
                    result = _fault_result(f"ray: {type(exc).__name__}: {(str(exc).splitlines() or [''])[0][:200]}",
                                           "ray", time.monotonic() - t0)
                land(spec, result)
            now = time.monotonic()
            for ref, (spec, t0, budget) in list(refs.items()):
                if now - t0 < budget:
                    continue
                del refs[ref]
                ray.cancel(ref, force=True)  # kills the worker process running it
                summary.hung += 1
                land(spec, _fault_result(f"hung: no result within the wall budget of {budget:.1f} s", "hung",
                                         now - t0, wall_budget_s=budget))
    except BaseException:
        for ref in refs:
            ray.cancel(ref, force=True)
        raise
    finally:
        if started_here:
            ray.shutdown()
