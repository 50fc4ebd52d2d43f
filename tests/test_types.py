"""The typed core passes mypy: the system contract (``systems/base.py``), the episode loop
(``sim/``), the benchmark machinery (``benchmark/``) and the reports (``report/``).

The checked paths and options are ``[tool.mypy]`` in pyproject.toml (``python -m mypy`` in the
checkout runs the same check). The cache lives in the temporary directory, so a second run is
incremental (seconds) and the checkout gets no ``.mypy_cache``.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_mypy_passes():
    if importlib.util.find_spec("mypy") is None:
        if os.environ.get("CI"):
            pytest.fail("mypy is not installed; it is in the test extras: pip install '.[test]'")
        pytest.skip("mypy is not installed (pip install '.[test]' brings it)")
    tag = hashlib.sha256(str(ROOT).encode()).hexdigest()[:12]
    cache = Path(tempfile.gettempdir()) / f"terrabench-mypy-cache-{tag}"
    res = subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(ROOT / "pyproject.toml"),
                          "--cache-dir", str(cache)], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, "mypy found type errors:\n" + res.stdout[-8000:] + res.stderr[-2000:]
