"""System discovery through the ``terrabench.systems`` entry-point group (as Gymnasium loads env plugins)."""

from __future__ import annotations

import sys
import textwrap

import pytest

from terrabench.catalog import ENTRY_POINT_GROUP, SystemImportError, populate, system_entry_points
from terrabench.registry import Registry

EXTERNAL = textwrap.dedent('''
    """A third-party system: one method, one instance, no MuJoCo."""
    from dataclasses import dataclass

    from terrabench.benchmark.trial import TrialResult
    from terrabench.systems.base import MethodInfo, System


    @dataclass(frozen=True)
    class ToyConfig:
        speed: float = 1.0


    class Toy(System):
        id = "toy"
        summary = "a third-party toy system"
        config_cls = ToyConfig

        def methods(self):
            return {"idle": MethodInfo("idle", "does nothing")}

        def instances(self, group):
            return ["flat"]

        def scenario(self, method, instance):
            return "toy/flat-v1"

        def run_trial(self, spec, *, on_step=None):
            return TrialResult("done", {"x": 1.0}, {}, 0.0, {})


    SYSTEM = Toy()


    def register(registry):
        SYSTEM.register(registry, "toy_terrabench_ext:SYSTEM")
''')


def _install(tmp_path, monkeypatch, name: str, module: str, target: str) -> None:
    """A minimal installed distribution on ``sys.path``: a module and a dist-info with one entry point."""
    source = EXTERNAL if module == "toy_terrabench_ext" else "raise ImportError('boom')\n"
    (tmp_path / f"{module}.py").write_text(source)
    info = tmp_path / f"{module}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {module}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(f"[{ENTRY_POINT_GROUP}]\n{name} = {target}\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, module, raising=False)


def test_built_in_systems_come_from_entry_points():
    names = {ep.name for ep in system_entry_points()}
    assert {"mrs-cwc", "beams", "octopus", "soil"} <= names
    assert set(populate.__wrapped__(Registry()).ids("system")) == names


def test_an_external_package_registers_its_system(tmp_path, monkeypatch):
    _install(tmp_path, monkeypatch, "toy", "toy_terrabench_ext", "toy_terrabench_ext:register")
    reg = populate.__wrapped__(Registry())
    assert "toy" in reg.ids("system") and "idle" in reg.ids("method", "toy")
    toy = reg.get("system", "toy").load()
    (spec,) = toy.plan(methods=["idle"], instances=["flat"])
    assert toy.run_trial(spec).status == "done"


def test_a_system_that_fails_to_import_is_an_error_not_silence(tmp_path, monkeypatch):
    from terrabench import catalog

    _install(tmp_path, monkeypatch, "broken", "broken_terrabench_ext", "broken_terrabench_ext:register")
    reg = populate.__wrapped__(Registry())
    assert "mrs-cwc" in reg.ids("system") and "broken" not in reg.ids("system")  # the others still load
    (err,) = catalog._FAILURES[id(reg)].values()
    assert isinstance(err, SystemImportError) and "system 'broken'" in str(err) and "ImportError: boom" in str(err)
    assert isinstance(err.__cause__, ImportError)  # the traceback --debug prints
    monkeypatch.setattr(catalog, "populate", lambda registry=None: reg)
    with pytest.raises(SystemImportError, match="failed to load"):
        catalog.system("broken")


def test_cli_prints_one_line_and_the_traceback_with_debug(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from terrabench import catalog
    from terrabench.cli import app

    _install(tmp_path, monkeypatch, "broken", "broken_terrabench_ext", "broken_terrabench_ext:register")
    reg = populate.__wrapped__(Registry())
    monkeypatch.setattr(catalog, "populate", lambda registry=None: reg)
    res = CliRunner().invoke(app, ["list"])
    assert res.exit_code == 2 and "failed to load" in res.output and "Traceback" not in res.output
    assert "mrs-cwc" in res.output  # the systems that load are listed first
    res = CliRunner().invoke(app, ["--debug", "list"])
    assert res.exit_code == 2 and "Traceback" in res.output
    res = CliRunner().invoke(app, ["run", "broken", "--store", str(tmp_path / "s.duckdb")])
    assert res.exit_code == 2 and "system 'broken'" in res.output and "failed to load" in res.output


def test_plugin_given_as_a_file_path(tmp_path, monkeypatch):
    path = tmp_path / "my_law_file.py"
    path.write_text("LOADED = True\n")
    monkeypatch.setenv("TERRABENCH_PLUGINS", str(path))
    populate.__wrapped__(Registry())
    assert sys.modules["my_law_file"].LOADED
    monkeypatch.setenv("TERRABENCH_PLUGINS", str(tmp_path / "missing.py"))
    with pytest.raises(SystemImportError, match="missing.py"):
        populate.__wrapped__(Registry())
