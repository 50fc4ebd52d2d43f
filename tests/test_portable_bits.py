"""The same trial gives the same bits on every x86-64 CPU (``terrabench.portable``).

The golden trials of every registered system (``System.golden``) are pinned in
``tests/golden_digests.json`` and re-run here in subprocesses whose environment asks for other
CPU code paths (numpy's AVX2 loops, another OpenBLAS kernel set, numba for this host, another
glibc tunable): the pins must win and give the pinned bits. A deliberate change of results is
re-pinned with ``python -m terrabench.benchmark.golden --write tests/golden_digests.json``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from terrabench.benchmark.golden import golden_name, golden_specs
from terrabench.catalog import populate

PINNED = json.loads((Path(__file__).parent / "golden_digests.json").read_text())

#: Environments a user's shell may carry, each asking for other code paths than the pins'.
ADVERSE = {
    "native-asks": {"NPY_DISABLE_CPU_FEATURES": "", "OPENBLAS_CORETYPE": "Haswell", "NUMBA_CPU_NAME": "host",
                    "GLIBC_TUNABLES": "glibc.malloc.check=0"},
    "old-cpu-asks": {"NPY_DISABLE_CPU_FEATURES": "X86_V3", "OPENBLAS_CORETYPE": "Katmai",
                     "OPENBLAS_NUM_THREADS": "2", "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2"},
}

PROBE = r"""
import hashlib, json, math
import numpy as np, numba
from terrabench import portable
from terrabench.benchmark.worker import host_fingerprint

@numba.njit(cache=False)
def axpy(a, x, y):
    out = np.empty_like(x)
    for i in range(x.size):
        out[i] = a * x[i] + y[i] * math.sin(x[i])
    return out

rng = np.random.default_rng(3)
x = rng.uniform(-10, 10, 20000)
y = rng.uniform(-10, 10, 20000)
m = rng.standard_normal((64, 64))
parts = {"libm": [math.sin(v) + math.exp(v / 10) for v in x[:5000]], "np_tanh": np.tanh(x),
         "np_arctan2": np.arctan2(x, y), "np_exp": np.exp(x / 10), "blas": m @ m, "numba": axpy(1.5, x, y)}
out = {k: hashlib.sha256(np.asarray(v).tobytes()).hexdigest()[:12] for k, v in parts.items()}
print(json.dumps({"probe": out, "host": host_fingerprint()}))
"""


def _env(extra: dict[str, str], *, native: bool = False) -> dict[str, str]:
    """This process's environment without the pins (the suite itself runs pinned), plus ``extra``."""
    from terrabench import portable

    env = {k: v for k, v in os.environ.items() if k not in portable.pins() and k != portable.NATIVE_ENV}
    env.update(extra)
    if native:
        env["TERRABENCH_NATIVE_CPU"] = "1"
    return env


def _probe(extra: dict[str, str], *, native: bool = False) -> dict:
    from terrabench import portable

    env = _env(extra, native=native)
    if not native:
        env = portable.pinned_environ(env)  # what `terrabench run` re-executes under
    out = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_every_registered_system_has_pinned_golden_trials():
    for sid in populate().ids("system"):
        names = {golden_name(s) for s in golden_specs(sid)}
        assert names, f"system {sid!r} declares no golden trials (System.golden)"
        pinned = {k for k in PINNED if k.startswith(f"{sid}:")}
        assert names == pinned, f"{sid}: golden trials {sorted(names)} vs pinned {sorted(pinned)}"


@pytest.mark.parametrize("variant", sorted(ADVERSE))
def test_pins_win_over_the_environment_and_fix_every_library(variant):
    """Pinned, a process gives one set of bits whatever its environment asked for; the host
    fingerprint says which paths it ran (numpy without SIMD dispatch, numba generic...)."""
    clean, adverse = _probe({}), _probe(ADVERSE[variant])
    assert adverse["probe"] == clean["probe"]
    host = adverse["host"]
    assert host["pinned"] is True and host["numpy_simd"] == [] and host["numba_cpu"] == "generic"
    assert host["openblas_coretype"] == "Sandybridge" and host["openblas_num_threads"] == "1"
    assert "glibc.cpu.hwcaps=-AVX2,-FMA" in host["glibc_tunables"]


def test_unpinned_the_same_variants_do_change_bits():
    """The variants reach the code: without pins, another OpenBLAS kernel set changes a 64x64
    matmul and (on a CPU with FMA) glibc's non-FMA libm changes sin/exp: the pins are needed."""
    native = _probe({}, native=True)
    katmai = _probe({"OPENBLAS_CORETYPE": "Katmai"}, native=True)
    assert native["host"]["pinned"] is False
    assert katmai["probe"]["blas"] != native["probe"]["blas"]
    if "fma" in Path("/proc/cpuinfo").read_text().split():
        nofma = _probe({"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"}, native=True)
        assert nofma["probe"]["libm"] != native["probe"]["libm"]


def test_golden_trials_give_the_pinned_bits_under_other_cpu_paths():
    """Every system's golden trials, run by the golden tool (which pins itself like the CLI) in
    two subprocesses at once: one with a clean environment, one asking for other paths."""
    cmd = [sys.executable, "-m", "terrabench.benchmark.golden"]
    procs = {name: subprocess.Popen(cmd, env=_env(extra), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for name, extra in (("clean", {}), ("asks-native", ADVERSE["native-asks"]))}
    for name, proc in procs.items():
        out, err = proc.communicate(timeout=900)
        assert proc.returncode == 0, f"{name}: {err[-2000:]}"
        got = json.loads(out)
        assert got["dispatch"]["pinned"] is True
        diff = {k: (got["digests"].get(k), v) for k, v in PINNED.items() if got["digests"].get(k) != v}
        assert not diff, f"{name}: golden trials changed bits (got, pinned): {diff}"


def test_an_unpinned_process_is_warned_once_and_a_pinned_one_not(monkeypatch):
    """A notebook or learner that builds an env in a process started without the pins gets one
    warning naming the fix; a pinned process, or one that asked for native paths, gets none."""
    import warnings

    from terrabench import portable

    monkeypatch.setattr(portable, "_WARNED", set())
    monkeypatch.setattr(portable, "_glibc_linux", lambda: True)
    for k in (portable._MARK, portable.NATIVE_ENV):
        monkeypatch.delenv(k, raising=False)
    with pytest.warns(portable.UnpinnedWarning, match="terrabench pins"):
        assert portable.warn_if_unpinned("here")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not portable.warn_if_unpinned("here")  # once per place
        monkeypatch.setenv(portable._MARK, "1")
        assert not portable.warn_if_unpinned("pinned")
        monkeypatch.delenv(portable._MARK)
        monkeypatch.setenv(portable.NATIVE_ENV, "1")
        assert not portable.warn_if_unpinned("native")


def test_an_env_built_unpinned_says_so(monkeypatch):
    import gymnasium

    import terrabench.envs  # noqa: F401  (registers the ids)
    from terrabench import portable

    monkeypatch.setattr(portable, "_WARNED", set())
    monkeypatch.setattr(portable, "_glibc_linux", lambda: True)
    for k in (portable._MARK, portable.NATIVE_ENV):
        monkeypatch.delenv(k, raising=False)
    with pytest.warns(portable.UnpinnedWarning, match="gymnasium env over 'mrs-cwc'"):
        gymnasium.make("terrabench/MRSCWC-v1", method="cwc-tdt", instance="A-01").close()
