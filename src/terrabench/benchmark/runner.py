"""Run trial specs on local processes or a Ray cluster, writing each result as it lands.

The runner knows nothing about robots: it ships a :class:`TrialSpec` to a worker, the worker
looks the system up in the catalog and calls its ``run_trial(spec)`` (the contract in
:mod:`terrabench.systems.base`). Every finished trial
is written to the store at once, so an interrupted run loses only the trials in flight, and a
re-run skips the keys already stored. A trial that raises becomes a row with status
``error`` (and the traceback in ``info``), never a lost run.
"""

from __future__ import annotations

import os
import time
import traceback
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass, field
from multiprocessing import get_context
from typing import Callable, Sequence

from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialResult, TrialSpec

BACKENDS = ("local", "ray")


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
    return result


@dataclass
class RunSummary:
    """What a call to :func:`run_trials` did."""

    requested: int
    skipped: int
    finished: int = 0
    statuses: dict[str, int] = field(default_factory=dict)
    wall_time: float = 0.0
    interrupted: bool = False


def default_workers() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


def run_trials(
    specs: Sequence[TrialSpec],
    store: ResultsStore,
    *,
    backend: str = "local",
    workers: int | None = None,
    address: str | None = None,
    on_result: Callable[[TrialSpec, TrialResult], None] | None = None,
    on_start: Callable[[int], None] | None = None,
) -> RunSummary:
    """Run the specs not yet in ``store``; store each result as soon as it arrives.

    Args:
        specs: trials to run (duplicates by key are run once).
        store: where results go.
        backend: ``"local"`` (process pool; ``workers=1`` runs in this process) or ``"ray"``.
        workers: parallel trials (default: the cores available).
        address: Ray cluster address (``None`` starts a local Ray instance).
        on_result: called after each stored result (progress bars hook in here).
        on_start: called once with the number of trials to run.
    """
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    unique = list({s.key: s for s in specs}.values())
    done = store.done_keys()
    todo = [s for s in unique if s.key not in done]
    summary = RunSummary(requested=len(unique), skipped=len(unique) - len(todo))
    if on_start:
        on_start(len(todo))
    t0 = time.perf_counter()

    def land(spec: TrialSpec, result: TrialResult) -> None:
        store.write(spec, result)
        summary.finished += 1
        summary.statuses[result.status] = summary.statuses.get(result.status, 0) + 1
        if on_result:
            on_result(spec, result)

    try:
        if not todo:
            pass
        elif backend == "ray":
            _run_ray(todo, land, workers, address)
        elif (workers or default_workers()) == 1 or len(todo) == 1:
            for spec in todo:
                land(spec, execute(spec))
        else:
            _run_pool(todo, land, workers or default_workers())
    except KeyboardInterrupt:
        summary.interrupted = True
    summary.wall_time = time.perf_counter() - t0
    return summary


def _run_pool(todo: list[TrialSpec], land, workers: int) -> None:
    # spawn: workers start clean (no inherited DuckDB handle or threads)
    with ProcessPoolExecutor(max_workers=min(workers, len(todo)), mp_context=get_context("spawn")) as pool:
        pending = {pool.submit(execute, s): s for s in todo}
        try:
            while pending:
                finished, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in finished:
                    spec = pending.pop(fut)
                    land(spec, fut.result())
        except BaseException:
            # interrupted: the trials in flight are lost anyway, so stop their workers now
            # instead of waiting up to a whole trial for them
            for proc in list((getattr(pool, "_processes", None) or {}).values()):
                proc.terminate()
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def _run_ray(todo: list[TrialSpec], land, workers: int | None, address: str | None) -> None:
    try:
        import ray
    except ImportError:
        raise ValueError("backend 'ray' needs the ray extra: pip install 'terrabench[ray]'") from None
    started_here = not ray.is_initialized()
    if started_here:
        kwargs = {"address": address} if address else {"num_cpus": workers or default_workers()}
        ray.init(ignore_reinit_error=True, log_to_driver=False, include_dashboard=False, **kwargs)
    remote = ray.remote(num_cpus=1)(execute)
    try:
        refs = {remote.remote(s): s for s in todo}
        while refs:
            ready, _ = ray.wait(list(refs), num_returns=1)
            for ref in ready:
                spec = refs.pop(ref)
                try:
                    result = ray.get(ref)
                except Exception as exc:  # a worker that died
                    result = TrialResult(status="error", info={"error": f"ray: {type(exc).__name__}: {exc}"})
                land(spec, result)
    except BaseException:
        for ref in refs:
            ray.cancel(ref, force=True)
        raise
    finally:
        if started_here:
            ray.shutdown()


