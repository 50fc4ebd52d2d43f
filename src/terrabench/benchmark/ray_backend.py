"""The Ray backend: the same trials as Ray tasks on a cluster (``--backend ray``).

Tasks have ``max_retries=1``: Ray reruns a task whose worker died once; a second death, a hang
past the budget, or a lost node give an ``error`` row. Needs the ``ray`` extra and, for
``--address auto``, a running cluster (``ray start --head``).
"""

from __future__ import annotations

import socket
import time
from collections import deque
from typing import Any

from terrabench import portable
from terrabench.benchmark.trial import TrialSpec
from terrabench.benchmark.worker import BudgetOf, FaultCounts, Land, default_workers, execute
from terrabench.benchmark.worker import fault_result as _fault_result

#: Ray task retries after a worker death (Ray's own mechanism).
RAY_MAX_RETRIES = 1
#: Seconds to wait for a TCP connection to a Ray cluster address before giving up.
RAY_CONNECT_TIMEOUT_S = 5.0


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


def run_ray(todo: list[TrialSpec], land: Land, workers: int | None, address: str | None, budget_of: BudgetOf,
             summary: FaultCounts) -> None:
    try:
        import ray
        from ray import exceptions as rex
    except ImportError:
        raise ValueError("backend 'ray' needs the ray extra: pip install 'terrabench[ray]'") from None
    started_here = not ray.is_initialized()
    if started_here:
        if address:
            _check_reachable(address)
        kwargs: dict[str, Any] = {"address": address} if address else {"num_cpus": workers or default_workers()}
        if portable.wanted():  # every node's workers start on the same CPU code paths
            kwargs["runtime_env"] = {"env_vars": portable.pins()}
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
