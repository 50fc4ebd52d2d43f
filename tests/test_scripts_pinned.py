"""Every study and probe script that runs trials pins its process first (terrabench.portable).

A script started with plain ``python`` runs numpy, libm, OpenBLAS and numba on this CPU's native
code paths; its trials then differ from the stored rows in the last bits, and a chaotic trial's
outcome with them (an unpinned T4 RCM halted at 66 s where the stored row halts at 107 s). So a
script that runs or replays trials re-executes itself pinned, as the ``terrabench`` command does.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: names whose use means the script runs or replays a trial
RUNS = {"run_trials", "run_trial", "trial_parts", "make_task", "run_episode", "run_spec"}


def _scripts() -> list[Path]:
    return sorted(p for folder in ("benchmarks", "tools") for p in (ROOT / folder).glob("*.py"))


def _names(tree: ast.AST) -> set[str]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            out.add(node.id)
        elif isinstance(node, ast.Attribute):
            out.add(node.attr)
        elif isinstance(node, ast.alias):
            out.add(node.name.rsplit(".", 1)[-1])
    return out


def _runners() -> list[Path]:
    return [p for p in _scripts() if RUNS & _names(ast.parse(p.read_text()))]


def test_the_scan_finds_trial_running_scripts():
    names = {p.name for p in _runners()}
    assert {"start_sensitivity_study.py", "rcm_rim_study.py", "probe_octopus_loads.py"} <= names


@pytest.mark.parametrize("path", _runners(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_a_script_that_runs_trials_pins_itself(path: Path):
    names = _names(ast.parse(path.read_text()))
    assert "reexec_pinned" in names, (
        f"{path.relative_to(ROOT)} runs trials ({sorted(RUNS & names)}) but never calls "
        "terrabench.portable.reexec_pinned(): its rows would not be the stored rows' bits")
