"""A damaged results file (truncated, junk over some blocks, not DuckDB at all) is one line naming
the file and what failed, exit 2, from both ``run`` and ``report``, and the file is left byte for
byte as it was; a run that fails before storing anything leaves no new store behind."""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest
from typer.testing import CliRunner

from terrabench.benchmark.store import ResultsStore, StoreError
from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.cli import app

ENV = {"COLUMNS": "400", "NO_COLOR": "1"}


@pytest.fixture(scope="module")
def good_store(tmp_path_factory):
    """A store of 40 mrs-cwc rows with incompressible series (a few MB, many blocks)."""
    path = tmp_path_factory.mktemp("store") / "good.duckdb"
    rng = np.random.default_rng(0)
    with ResultsStore(path) as st:
        for k in range(40):
            spec = TrialSpec("mrs-cwc", "mrs-cwc/benchmark-v1", "cwc-tdt", f"A-{k + 1:02d}", 0, {"k": k})
            series = {name: rng.standard_normal(2000) for name in ("t", "x", "y", "z")}
            st.write(spec, TrialResult("timeout", {"NCR": float(k)}, series, 1.0, {"why": "test"}))
    return path


def _damaged(good, tmp_path, kind):
    path = tmp_path / f"{kind}.duckdb"
    shutil.copy(good, path)
    size = path.stat().st_size
    if kind == "truncated":
        os.truncate(path, size // 2)
    elif kind == "junk-blocks":  # the middle fifth overwritten: data blocks, not the header
        with open(path, "r+b") as f:
            f.seek(int(size * 0.4))
            f.write(np.random.default_rng(1).bytes(int(size * 0.2)))
    elif kind == "not-duckdb":
        path.write_bytes(b"trial,status\nA-01,success\n" * 100)
    return path


DAMAGE = ["truncated", "junk-blocks", "not-duckdb"]


def test_the_good_store_reads(good_store):
    with ResultsStore(good_store, read_only=True) as st:
        assert st.trial_count() == 40


@pytest.mark.parametrize("kind", DAMAGE)
def test_opening_a_damaged_store_is_a_store_error_and_changes_nothing(good_store, tmp_path, kind):
    path = _damaged(good_store, tmp_path, kind)
    before = path.read_bytes()
    for read_only in (True, False):
        with pytest.raises(StoreError, match=str(path.name)):
            ResultsStore(path, read_only=read_only)
        assert path.read_bytes() == before
    assert not path.with_name(path.name + ".wal").exists()


@pytest.mark.parametrize("kind", DAMAGE)
@pytest.mark.parametrize("command", [["report", "mrs-cwc"],
                                     ["run", "mrs-cwc", "--terrains", "A-01", "--methods", "cwc-tdt"]])
def test_cli_on_a_damaged_store_is_one_line_exit_2(good_store, tmp_path, kind, command):
    path = _damaged(good_store, tmp_path, kind)
    before = path.read_bytes()
    extra = ["--out", str(tmp_path / "rep")] if command[0] == "report" else []
    res = CliRunner().invoke(app, command + ["--store", str(path)] + extra, env=ENV)
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and path.name in lines[0], res.output
    assert ("damaged" in lines[0]) if kind != "not-duckdb" else ("not a valid DuckDB" in lines[0])
    assert path.read_bytes() == before
    assert not (tmp_path / "rep").exists()


def test_a_run_that_fails_before_any_row_leaves_no_new_store(tmp_path, monkeypatch):
    """e.g. ``--backend ray`` with no cluster: the error, and no empty store file."""
    from terrabench.benchmark import runner

    def no_cluster(*args, **kwargs):
        raise ValueError("cannot reach a Ray cluster at '127.0.0.1:1': Connection refused")

    monkeypatch.setattr(runner, "run_trials", no_cluster)
    store = tmp_path / "new.duckdb"
    res = CliRunner().invoke(app, ["run", "mrs-cwc", "--terrains", "A-01", "--methods", "cwc-tdt",
                                   "--store", str(store)], env=ENV)
    assert res.exit_code == 2 and "cannot reach a Ray cluster" in res.output, res.output
    assert not store.exists() and not store.with_name("new.duckdb.wal").exists()


def test_a_failing_run_keeps_an_existing_store(good_store, tmp_path, monkeypatch):
    from terrabench.benchmark import runner

    path = tmp_path / "kept.duckdb"
    shutil.copy(good_store, path)

    def no_cluster(*args, **kwargs):
        raise ValueError("cannot reach a Ray cluster")

    monkeypatch.setattr(runner, "run_trials", no_cluster)
    res = CliRunner().invoke(app, ["run", "mrs-cwc", "--terrains", "A-01", "--methods", "cwc-tdt",
                                   "--store", str(path)], env=ENV)
    assert res.exit_code == 2, res.output
    with ResultsStore(path, read_only=True) as st:
        assert st.trial_count() == 40
