"""The same trial gives the same bits on every x86-64 CPU: the code paths a trial process pins.

A trial's bits depend on which machine code computes it wherever a library picks that code at run
time from the CPU's features. Measured on the golden trials (``docs/performance.md``, "Bitwise
across CPUs"), four libraries do it on the stepping path:

- **glibc's libm** (``sin``, ``cos``, ``exp``, ``atan2``, ``pow`` ...) chooses an FMA variant on
  CPUs with FMA and AVX2 and an SSE2/AVX one elsewhere, and the two differ in the last bit.
  MuJoCo itself calls libm (``libmujoco`` has ~800 call sites, AVX code but no FMA and no
  ``cpuid``), as do Python's ``math``, numba's kernels and numpy's scalar paths.
  ``GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4`` makes every CPU take the non-FMA variant
  (MuJoCo's wheel needs AVX, so every machine that runs it can).
- **numpy** dispatches ufunc loops to AVX2 / AVX-512 kernels (``np.arctan2``, ``np.tanh``,
  ``np.exp`` ... differ from the baseline in the last bit on a few % of inputs).
  ``NPY_DISABLE_CPU_FEATURES`` set to every dispatch target of the installed numpy makes every
  CPU run the baseline (x86-64-v2) loops compiled into the wheel.
- **OpenBLAS** (``DYNAMIC_ARCH``) picks a kernel set per CPU for ``matmul`` / ``dot`` / LAPACK,
  and a thread split per core count. ``OPENBLAS_CORETYPE=Sandybridge`` (AVX, no FMA) and one
  thread fix both.
- **numba** compiles for the host CPU. ``NUMBA_CPU_NAME=generic`` compiles for plain x86-64.

These are environment variables read when a process starts (the loader reads ``GLIBC_TUNABLES``
before any code runs; numpy, OpenBLAS and numba read theirs on import), so they are applied where
trial processes start: the ``terrabench`` command re-executes itself once with them
(:func:`reexec_pinned`), its spawned workers inherit them, and Ray workers get them through their
``runtime_env`` (:func:`pinned_environ`). The study and probe scripts under ``benchmarks/`` and
``tools/`` that run trials re-execute themselves the same way (``tests/test_scripts_pinned.py``).
A library user (a notebook, a learner around ``gymnasium.make``) gets the same bits as the
stored rows by starting Python with the same variables (``eval "$(terrabench pins)"`` exports
them); :func:`state` says whether this process is pinned and every stored row carries it
(``info.host.pinned``). ``TERRABENCH_NATIVE_CPU=1`` turns the pins off (for timing the native
paths side by side: ``terrabench perf``).
"""

from __future__ import annotations

import os
import sys
from typing import Any, Mapping

#: The glibc tunable that makes libm take its non-FMA variant on every CPU (names of glibc >= 2.33
#: and, for older ones, the ``*_Usable`` spelling; unknown names are ignored by the loader).
GLIBC_HWCAPS = "glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4,-AVX2_Usable,-FMA_Usable,-FMA4_Usable"
#: Opt-out: set to 1 to run with the CPU's native code paths (not reproducible across CPUs).
NATIVE_ENV = "TERRABENCH_NATIVE_CPU"
#: Set in a process that :func:`reexec_pinned` started, so it never re-executes twice.
_MARK = "TERRABENCH_PINNED"


def _numpy_dispatch_targets() -> str:
    """Every run-time SIMD target of the installed numpy (without importing numpy if it is not
    yet imported: the value must be known before numpy reads it)."""
    import subprocess

    if "numpy" in sys.modules:
        return " ".join(_dispatch_list())
    out = subprocess.run([sys.executable, "-c", "from terrabench.portable import _dispatch_list;"
                          "print(' '.join(_dispatch_list()))"], capture_output=True, text=True,
                         env={**os.environ, "NPY_DISABLE_CPU_FEATURES": ""})
    return out.stdout.strip()


def _dispatch_list() -> list[str]:
    try:
        from numpy._core import _multiarray_umath as um  # numpy >= 2
    except ImportError:  # pragma: no cover - numpy 1.x
        from numpy.core import _multiarray_umath as um
    return list(getattr(um, "__cpu_dispatch__", []))


def pins(base: Mapping[str, str] | None = None) -> dict[str, str]:
    """The environment variables that pin every library's code path (``base``: the environment
    whose other glibc tunables are kept; default this process's)."""
    env = os.environ if base is None else base
    tunables = [t for t in env.get("GLIBC_TUNABLES", "").split(":") if t and not t.startswith("glibc.cpu.hwcaps=")]
    return {"GLIBC_TUNABLES": ":".join(tunables + [GLIBC_HWCAPS]),
            "NPY_DISABLE_CPU_FEATURES": _numpy_dispatch_targets(),
            "OPENBLAS_CORETYPE": "Sandybridge", "OPENBLAS_NUM_THREADS": "1",
            "NUMBA_CPU_NAME": "generic", "NUMBA_CPU_FEATURES": "", _MARK: "1"}


def pinned_environ(base: Mapping[str, str] | None = None) -> dict[str, str]:
    """``base`` (default: this process's environment) with :func:`pins` set."""
    env = dict(os.environ if base is None else base)
    env.update(pins(env))
    return env


def wanted() -> bool:
    """Whether pins are asked for (everywhere, unless ``TERRABENCH_NATIVE_CPU=1``)."""
    return os.environ.get(NATIVE_ENV, "").strip() not in ("1", "true", "yes")


def reexec_pinned(argv: list[str] | None = None) -> None:
    """Re-execute this program once under :func:`pinned_environ` (Linux with glibc), so the
    process that plans, the trials it runs in-process and every worker it spawns are pinned.
    Returns without doing anything when already pinned, not wanted, or not on glibc Linux."""
    if os.environ.get(_MARK) == "1" or not wanted() or not _glibc_linux():
        return
    args = [sys.executable] + (sys.orig_argv[1:] if argv is None and hasattr(sys, "orig_argv") else (argv or []))
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(sys.executable, args, pinned_environ())


def _glibc_linux() -> bool:
    import platform

    return sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"


def state() -> dict[str, Any]:
    """The code paths this process runs, as stored in each row's ``info.host``: whether it was
    started pinned, and the value of each library's setting."""
    keys = ("GLIBC_TUNABLES", "NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS",
            "NUMBA_CPU_NAME")
    out: dict[str, Any] = {"pinned": os.environ.get(_MARK) == "1"}
    out.update({k.lower(): os.environ.get(k) for k in keys})
    numba = sys.modules.get("numba")
    if numba is not None:
        out["numba_cpu"] = numba.config.CPU_NAME or "host"
    return out


class UnpinnedWarning(UserWarning):
    """Trials run in this process take the CPU's own code paths (:func:`warn_if_unpinned`)."""


_WARNED: set[str] = set()


def warn_if_unpinned(where: str) -> bool:
    """Warn once per process (and ``where``) when trials run here would take the CPU's native code
    paths: glibc Linux, pins wanted, but the process was not started with them (a notebook or a
    learner that imports terrabench, where the ``terrabench`` command would have re-executed
    itself). Its trials are then not bitwise the stored rows on another CPU. Returns whether it
    warned."""
    import warnings

    if os.environ.get(_MARK) == "1" or not wanted() or not _glibc_linux() or where in _WARNED:
        return False
    _WARNED.add(where)
    warnings.warn(f"{where}: this Python process was not started with terrabench's CPU pins, so its trials take "
                  "this CPU's native code paths and their bits may differ from the stored rows on another CPU; "
                  "start Python after `eval \"$(terrabench pins)\"` (or set TERRABENCH_NATIVE_CPU=1 to run "
                  "natively without this warning)", UnpinnedWarning, stacklevel=3)
    return True
