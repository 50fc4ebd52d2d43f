"""The README and docs say only what is true of this checkout: one version, links and file
references that resolve, the layout lists every script, the plugin example works as written, the
group descriptions match the terrains' measured slopes."""

from __future__ import annotations

import importlib.metadata
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import terrabench
from terrabench._version import __version__

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
PKG = ROOT / "src" / "terrabench"
#: top-level folders of the repository and sub-packages of src/terrabench a doc may name a file in
TOP = ("docs", "src", "benchmarks", "tools", "tests", "shared")
SUBPACKAGES = tuple(p.name for p in PKG.iterdir() if p.is_dir() and not p.name.startswith("_"))


def test_one_version_everywhere():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())
    project = meta["project"]
    assert "version" not in project and "version" in project.get("dynamic", []), \
        "pyproject.toml must read the version from terrabench._version, not repeat it"
    assert meta["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "terrabench._version.__version__"}
    assert terrabench.__version__ == __version__
    installed = importlib.metadata.version("terrabench")
    assert installed == __version__, f"installed metadata says {installed}: reinstall (pip install -e .)"
    out = subprocess.run([sys.executable, "-m", "terrabench.cli", "--version"], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    assert out.strip() == f"terrabench {__version__}"


def _links(text: str) -> list[str]:
    return [m.group(1) for m in re.finditer(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", text)]


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.name)
def test_every_relative_link_resolves(doc):
    bad = []
    for target in _links(doc.read_text()):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue
        if not (doc.parent / target.split("#")[0]).exists():
            bad.append(target)
    assert not bad, f"{doc.name}: broken links {bad}"


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.name)
def test_every_named_repository_file_exists(doc):
    """A `path/to/file.ext` in backticks that starts with a repository folder (docs/, src/,
    benchmarks/, tools/, tests/) or a sub-package of src/terrabench (soil/, systems/, ...) exists
    in this checkout (shared/ is the project workspace, not part of the repository: not cited)."""
    bad = []
    for m in re.finditer(r"`([A-Za-z0-9_.*/-]+/[A-Za-z0-9_.*-]+\.(?:md|py|csv|json|html|toml|txt))`", doc.read_text()):
        p = m.group(1)
        first = p.split("/")[0]
        if first in TOP:
            base = ROOT
        elif first in SUBPACKAGES:
            base = PKG
        else:
            continue
        if not (any(base.glob(p)) if "*" in p else (base / p).exists()):
            bad.append(p)
    assert not bad, f"{doc.name}: names files this checkout does not have: {bad}"


def test_readme_layout_lists_every_tool_and_benchmark_script():
    readme = (ROOT / "README.md").read_text()
    layout = readme[readme.index("## Layout"):]
    missing = [p.name for folder in ("tools", "benchmarks") for p in sorted((ROOT / folder).glob("*.py"))
               if p.name not in layout]
    assert not missing, f"README layout does not list {missing}"


def test_readme_plugin_example_works_as_written(tmp_path):
    """The README's my_law.py, saved as the README says, named the way the README's command names
    it: the method is listed and planned (nothing is run)."""
    readme = (ROOT / "README.md").read_text()
    block = re.search(r"```python\n(\s*# my_law\.py\n.*?)```", readme, re.S)
    assert block, "README has no my_law.py example"
    code = "\n".join(line[2:] if line.startswith("  ") else line for line in block.group(1).splitlines())
    command = re.search(r"`(TERRABENCH_PLUGINS=(\S+) terrabench run mrs-cwc [^`]*)`", readme)
    assert command, "README has no TERRABENCH_PLUGINS command"
    plugin = command.group(2)
    (tmp_path / "my_law.py").write_text(code)
    env = {"TERRABENCH_PLUGINS": plugin, "PATH": "", "HOME": str(tmp_path), "MPLBACKEND": "Agg"}
    script = Path(sys.executable).parent / "terrabench"  # the console script, as the README runs it
    if not script.exists():
        pytest.skip(f"no terrabench console script beside {sys.executable}")
    res = subprocess.run([str(script), "list", "mrs-cwc"], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "stiff-tdt" in res.stdout


def test_mrs_cwc_group_descriptions_state_the_measured_slopes():
    from terrabench.catalog import system
    from terrabench.terrain import dataset

    groups = system("mrs-cwc").groups
    for g in ("A", "B"):
        slopes = [t.stats()["mean_axis_slope_deg"] for t in dataset.select(None, g)]
        stated = f"{min(slopes):.1f}-{max(slopes):.1f} deg"
        assert stated in groups[g], (g, stated, groups[g])
