"""The code passes the project's ruff configuration (pyproject.toml, [tool.ruff])."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _ruff() -> list[str] | None:
    try:
        import ruff  # noqa: F401 - the wheel ships the binary
    except ImportError:
        exe = shutil.which("ruff")
        return [exe] if exe else None
    return [sys.executable, "-m", "ruff"]


def test_ruff_passes():
    cmd = _ruff()
    if cmd is None:
        if os.environ.get("CI"):
            pytest.fail("ruff is not installed; it is in the test extras: pip install '.[test]'")
        pytest.skip("ruff is not installed (pip install '.[test]' brings it)")
    if not (ROOT / "pyproject.toml").is_file():
        pytest.skip("not run from a source checkout")
    res = subprocess.run([*cmd, "check", "--no-cache", "src", "tests", "benchmarks", "tools"], cwd=ROOT,
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stdout[-4000:] + res.stderr[-2000:]
