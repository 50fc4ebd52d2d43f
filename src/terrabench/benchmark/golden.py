"""Golden trials: short trials per system whose stored bits are pinned, to prove that a result
does not depend on the CPU that computed it.

Each registered system names a few plan requests in :attr:`terrabench.systems.base.System.golden`
(seconds of simulated time each). :func:`run_golden` runs them in this process and returns one
digest per trial: a SHA-256 over everything a trial stores that physics decides (status,
metrics, the time series' bytes, the controller's events), not its wall time or host.
``tests/test_portable_bits.py`` re-runs them in subprocesses under other numpy SIMD dispatch,
OpenBLAS kernels and numba targets (:data:`VARIANTS`) and requires the pinned digests bit for bit.

    python -m terrabench.benchmark.golden                 # digests of every system, as JSON
    python -m terrabench.benchmark.golden --system srwmr  # one system
    python -m terrabench.benchmark.golden --write tests/golden_digests.json   # re-pin (deliberate)
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from typing import Any, Mapping

import numpy as np

from terrabench import portable
from terrabench.benchmark.trial import TrialResult, TrialSpec, canonical_json

#: Environment settings that change which CPU code paths compute a trial on this one machine,
#: each standing in for a kind of CPU a user may have. A trial's bits must not change under any
#: of them. numpy: ``NPY_DISABLE_CPU_FEATURES`` switches its run-time SIMD dispatch down to the
#: baseline (``X86_V3`` = AVX2/FMA, what an older CPU gets; ``X86_V4`` = AVX-512, what a CPU
#: without it gets). OpenBLAS: ``OPENBLAS_CORETYPE`` picks another kernel set than the CPU's own
#: (``Prescott``: SSE3 kernels, ``Haswell``/``SkylakeX``: AVX2/AVX-512 kernels). numba:
#: ``NUMBA_CPU_NAME`` compiles for another target than terrabench's ``generic`` (``host``: this
#: CPU, with its features).
VARIANTS: dict[str, dict[str, str]] = {
    "default": {},
    "numpy-no-avx2": {"NPY_DISABLE_CPU_FEATURES": "X86_V3 X86_V4 AVX512_ICL AVX512_SPR"},
    "openblas-prescott": {"OPENBLAS_CORETYPE": "Prescott"},
    "openblas-haswell": {"OPENBLAS_CORETYPE": "Haswell"},
    "numba-host": {"NUMBA_CPU_NAME": "host"},
}


def result_digest(result: TrialResult) -> str:
    """SHA-256 (hex, 16 chars) of what physics decided in ``result``: status, metrics (exact
    float bits), every time-series column's bytes and the controller's events."""
    h = hashlib.sha256()
    metrics = {k: (float(v).hex() if isinstance(v, (float, np.floating)) else v) for k, v in result.metrics.items()}
    h.update(canonical_json({"status": result.status, "metrics": metrics}).encode())
    for name in sorted(result.timeseries):
        col = np.ascontiguousarray(result.timeseries[name])
        h.update(name.encode())
        h.update(str(col.dtype).encode())
        h.update(col.tobytes())
    events = result.info.get("events")
    if events is not None:
        h.update(canonical_json(events).encode())
    return h.hexdigest()[:16]


def golden_specs(system_id: str) -> list[TrialSpec]:
    """The trial specs of ``system_id``'s golden requests."""
    from terrabench.catalog import system

    sysobj = system(system_id)
    specs: list[TrialSpec] = []
    for request in sysobj.golden:
        specs.extend(sysobj.plan(**dict(request)))
    return specs


def golden_name(spec: TrialSpec) -> str:
    return f"{spec.system}:{spec.method}:{spec.instance}:{spec.seed}"


def run_golden(system_ids: list[str] | None = None) -> dict[str, str]:
    """``{"system:method:instance:seed": digest}`` for the golden trials of ``system_ids``
    (default: every registered system), run one after the other in this process."""
    from terrabench.catalog import populate, system

    out: dict[str, str] = {}
    for sid in system_ids or populate().ids("system"):
        sysobj = system(sid)
        for spec in golden_specs(sid):
            result = sysobj.run_trial(spec)
            out[golden_name(spec)] = result_digest(result)
    return out


def dispatch() -> dict[str, Any]:
    """The CPU code paths this process uses (what :data:`VARIANTS` change)."""
    from terrabench.benchmark.worker import host_fingerprint

    return host_fingerprint()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m terrabench.benchmark.golden", description=__doc__.split("\n\n")[0])
    ap.add_argument("--system", action="append", help="a system id (repeatable); default: all")
    ap.add_argument("--write", help="write the digests to this JSON file (re-pinning is a deliberate act)")
    args = ap.parse_args(argv)
    portable.reexec_pinned()
    digests = run_golden(args.system)
    payload: Mapping[str, Any] = {"digests": digests, "dispatch": dispatch()}
    text = json.dumps(payload, indent=1, sort_keys=True)
    if args.write:
        with open(args.write, "w") as fh:
            fh.write(json.dumps(digests, indent=1, sort_keys=True) + "\n")
    sys.stdout.write(text + "\n")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
