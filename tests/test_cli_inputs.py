"""Bad input on the command line ends with one line naming the value and what is valid, exit 2,
before any simulation and with the store unchanged; the discovery commands show what is valid."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from terrabench import catalog
from terrabench.benchmark.trial import STATUSES
from terrabench.cli import app
from terrabench.config import fields_info

SYSTEMS = catalog.populate().ids("system")
ENV = {"COLUMNS": "400", "NO_COLOR": "1"}


def invoke(*args, env=None):
    return CliRunner().invoke(app, list(args), env={**ENV, **(env or {})})


def one_error_line(res, *needles):
    """exit 2, exactly one non-empty output line starting 'error:', naming every needle."""
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:"), res.output
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


@pytest.mark.parametrize("sid", SYSTEMS)
def test_config_lists_every_set_key_with_its_range(sid):
    res = invoke("config", sid)
    assert res.exit_code == 0, res.output
    for info in fields_info(catalog.system(sid).base_config()):
        assert info.key in res.output, (sid, info.key)


@pytest.mark.parametrize("sid", SYSTEMS)
def test_list_system_shows_methods_groups_sizes_and_ids(sid):
    sysobj = catalog.system(sid)
    res = invoke("list", sid)
    assert res.exit_code == 0, res.output
    for m in sysobj.methods():
        assert m in res.output
    for g in sysobj.groups:
        assert g in res.output
    assert "instance ids" in res.output


def test_list_statuses_explains_every_status():
    res = invoke("list", "--statuses")
    assert res.exit_code == 0, res.output
    for s in STATUSES:
        assert s in res.output


def test_list_unknown_system_is_one_line():
    one_error_line(invoke("list", "nope"), "'nope'", "mrs-cwc")


@pytest.mark.parametrize("setting", ["chain.n_units=0", "chain.body_mass=0", "chain.wheel_radius=-0.05",
                                     "chain.wheel_friction=-1", "physics.iterations=-1",
                                     "chain.body_inertia_per_kg=[1,2]", "stiffness.ema=2"])
def test_run_with_a_meaningless_config_value_stores_nothing(tmp_path, setting):
    store = tmp_path / "r.duckdb"
    key, _, value = setting.partition("=")
    res = invoke("run", "mrs-cwc", "--terrains", "A-01", "--methods", "cwc-tdt", "--set", setting,
                 "--store", str(store))
    one_error_line(res, key, value.strip("[]").split(",")[0])
    assert not store.exists()
