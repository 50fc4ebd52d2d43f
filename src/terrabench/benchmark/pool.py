"""The local backend: a small pool of spawned worker processes, one spec each at a time.

One process per slot, fed one spec at a time over a pipe, so the parent always knows which spec
a worker holds: a worker that dies mid-trial costs only that trial (run once more in a fresh
worker, then stored as ``error``), and a trial past its wall budget is killed with its worker.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from collections import deque
from multiprocessing import get_context
from multiprocessing.connection import Connection
from multiprocessing.connection import wait as mp_wait
from multiprocessing.context import SpawnContext

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.benchmark.worker import BudgetOf, FaultCounts, Land, execute
from terrabench.benchmark.worker import exit_reason as _exit_reason
from terrabench.benchmark.worker import fault_result as _fault_result

#: A worker process that has not finished importing the systems by then is killed.
WORKER_START_BUDGET_S = 300.0
#: Consecutive worker processes that die (or stall) while starting before the run gives up.
MAX_START_FAILURES = 3


def _worker_main(conn: Connection, systems: list[str], parent_pid: int) -> None:
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
            error = f"result could not be sent: {type(exc).__name__}: {exc}"
            conn.send(("result", TrialResult("error", wall_time=result.wall_time, info={"error": error})))


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

    def __init__(self, ctx: SpawnContext, systems: list[str]) -> None:
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
        assert spec is not None, "take() of a slot that holds no spec"  # callers test slot.spec first
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


def run_pool(todo: list[TrialSpec], land: Land, workers: int, budget_of: BudgetOf, summary: FaultCounts) -> None:
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
                alive, results = True, []
                try:
                    while slot.conn.poll():
                        msg = slot.conn.recv()
                        if msg[0] == "ready":
                            slot.ready, slot.deadline = True, None
                            start_failures = 0
                        elif msg[0] == "result" and slot.spec is not None:
                            results.append((slot.take()[0], msg[1]))
                except (EOFError, OSError):
                    alive = False
                except Exception:  # a message cut short by the death of its sender
                    alive = False
                for spec, result in results:  # outside the try: a store error is not a dead worker
                    land(spec, result)
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
