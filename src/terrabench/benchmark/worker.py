"""Running one trial in the current process, and what a fault looks like as a result.

Shared by every backend (:mod:`terrabench.benchmark.pool`, :mod:`terrabench.benchmark.ray_backend`)
and by :func:`terrabench.benchmark.runner.run_trials`' in-process path.
"""

from __future__ import annotations

import functools
import os
import signal
import time
import traceback
from typing import Any, Callable, Protocol

from terrabench.benchmark.trial import TrialResult, TrialSpec

#: ``land(spec, result)``: store one finished trial (the runner's; every backend calls it once per spec)
Land = Callable[[TrialSpec, TrialResult], None]
#: ``budget_of(spec)``: the wall-clock seconds a trial may take before it counts as hung
BudgetOf = Callable[[TrialSpec], float]


class FaultCounts(Protocol):
    """The fault counters a backend adds to (those of :class:`terrabench.benchmark.runner.RunSummary`)."""

    retried: int
    worker_deaths: int
    hung: int


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

    numpy, OpenBLAS, numba and glibc's libm pick machine code by CPU feature at run time; a trial
    process started pinned (:mod:`terrabench.portable`: ``pinned`` true) runs the same code on
    every x86-64 CPU, so its rows agree bitwise with any other pinned host of the same library
    versions. Stored with every row, so two stores can be compared knowing whether they can.
    """
    import platform

    import mujoco
    import numpy as np

    from terrabench import portable

    try:
        # numpy >= 2; a private C module that numpy's stubs do not declare
        from numpy._core import _multiarray_umath as um  # type: ignore[attr-defined]
    except ImportError:  # pragma: no cover - numpy 1.x
        from numpy.core import _multiarray_umath as um
    features = getattr(um, "__cpu_features__", {})
    simd = [f for f in getattr(um, "__cpu_dispatch__", []) if features.get(f)]
    return {"machine": platform.machine(), "python": platform.python_version(), "numpy": np.__version__,
            "mujoco": mujoco.__version__, "libc": "-".join(platform.libc_ver()), "numpy_simd": simd,
            "code": code_fingerprint(), **cpu_model(), **portable.state()}


@functools.lru_cache(maxsize=1)
def cpu_model() -> dict[str, Any]:
    """The CPU by name and whether it has AVX-512 (``/proc/cpuinfo``; empty where there is none):
    which machine made a row, for the cross-CPU record (docs/performance.md). Read once per process
    (every row's ``info.host`` spreads it; do not mutate the returned dict)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            text = f.read(65536)
    except OSError:
        return {}
    fields = dict(line.split(":", 1) for line in text.splitlines() if ":" in line)
    fields = {k.strip(): v.strip() for k, v in fields.items()}
    return {"cpu": fields.get("model name", ""), "avx512": "avx512f" in fields.get("flags", "").split()}


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """SHA-256 (hex, 16 chars) of the terrabench package that runs here: every file of the package
    (sources and the data copied into it), by path relative to the package, compiled caches left
    out. The package version names a release, not a working tree; this names the code, so a store
    can tell the rows another checkout or an older install left in it (``RunSummary.other_code``)."""
    import hashlib
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    files = (p for p in root.rglob("*") if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc")
    for path in sorted(files, key=lambda p: p.relative_to(root).as_posix()):
        h.update(path.relative_to(root).as_posix().encode())
        h.update(b"\0")
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def default_workers() -> int:
    """The cores this process may run on."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


def fault_result(reason: str, kind: str, wall_time: float, **info: Any) -> TrialResult:
    """An ``error`` row for a fault of the machinery (a dead worker, a hang), not of the physics."""
    return TrialResult(status="error", wall_time=wall_time, info={"error": reason, "fault": kind, **info})


def exit_reason(exitcode: int | None) -> str:
    """``"worker died: signal 9 (SIGKILL)"`` / ``"exit code 3"`` from a process exit code."""
    if exitcode is None:
        return "worker died: no exit status"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            return f"worker died: signal {-exitcode}"
        return f"worker died: signal {-exitcode} ({name})"
    return f"worker died: exit code {exitcode}"
