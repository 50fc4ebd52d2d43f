"""Results store and runner contracts: atomic rows, resume, errors, version checks, Ray."""

import duckdb
import numpy as np
import pytest

from terrabench.benchmark import runner
from terrabench.benchmark.runner import execute, run_trials
from terrabench.benchmark.store import ResultsStore, StoreError
from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.systems.mrs_cwc.scenarios import SYSTEM


def quick_specs(terrains=("A-01", "B-02"), timeout=1.0, method="cwc-tdt"):
    return SYSTEM.plan(methods=[method], instances=list(terrains), overrides={"protocol.timeout": timeout})


def test_key_covers_every_part_of_the_trial():
    a = TrialSpec("s", "sc", "m", "i", 0, {"x": 1})
    assert a.key == TrialSpec("s", "sc", "m", "i", 0, {"x": 1}).key
    for other in (TrialSpec("s", "sc", "m", "i", 1, {"x": 1}), TrialSpec("s", "sc", "m", "j", 0, {"x": 1}),
                  TrialSpec("s", "sc", "m", "i", 0, {"x": 2}), TrialSpec("s", "sc", "n", "i", 0, {"x": 1})):
        assert other.key != a.key


def test_result_rejects_unknown_status_and_ragged_series():
    with pytest.raises(ValueError, match="unknown trial status"):
        TrialResult("won")
    with pytest.raises(ValueError, match="differ in length"):
        TrialResult("done", timeseries={"t": np.zeros(3), "x": np.zeros(2)})


def test_roundtrip_row_config_and_series(tmp_path):
    spec = TrialSpec("mrs-cwc", "sc", "m", "A-01", 0, {"a": {"b": 1.5}})
    res = TrialResult("timeout", {"NCR": 0.5, "NEC": float("nan")},
                      {"t": np.arange(3.0), "x": np.array([1.0, np.nan, 3.0])}, 2.0, {"why": "x"})
    with ResultsStore(tmp_path / "r.duckdb") as st:
        st.write(spec, res)
        st.write(spec, res)  # same key twice: still one row
        rows = st.rows()
        assert len(rows) == 1
        r = rows[0]
        assert r["status"] == "timeout" and r["config"] == {"a": {"b": 1.5}} and r["info"] == {"why": "x"}
        assert r["metrics"]["NCR"] == 0.5 and np.isnan(r["metrics"]["NEC"])
        ts = st.timeseries(spec.key)
        assert list(ts) == ["t", "x"] and np.isnan(ts["x"][1]) and ts["x"][2] == 3.0


def test_rerun_skips_finished_trials(tmp_path):
    specs = quick_specs()
    with ResultsStore(tmp_path / "r.duckdb") as st:
        first = run_trials(specs, st, workers=1)
        again = run_trials(specs, st, workers=1)
        assert first.finished == 2 and again.finished == 0 and again.skipped == 2
        assert len(st.rows()) == 2


def test_a_rerun_says_which_stored_rows_other_code_made(tmp_path):
    """A key names the spec, not the code: a re-run reuses a stored row whatever made it, and says
    how many of those another terrabench (a different package digest, or none recorded) made."""
    from terrabench.benchmark.worker import code_fingerprint

    a, b, c = quick_specs(("A-01", "A-02", "B-02"))
    with ResultsStore(tmp_path / "r.duckdb") as st:
        first = run_trials([a], st, workers=1)
        assert first.finished == 1 and st.rows()[0]["info"]["host"]["code"] == code_fingerprint()
        st.write(b, TrialResult("timeout", info={"host": {"code": "0123456789abcdef"}}))  # another checkout
        st.write(c, TrialResult("timeout"))  # stored before the digest was recorded
        assert st.code_of([a.key, b.key, c.key]) == {a.key: code_fingerprint(), b.key: "0123456789abcdef",
                                                     c.key: None}
        again = run_trials([a, b, c], st, workers=1)
        assert (again.skipped, again.finished, again.other_code) == (3, 0, 2)
        assert "2 of the stored trials were made by other terrabench code" in again.describe()
        assert run_trials([a], st, workers=1).other_code == 0
        redone = run_trials([a, b, c], st, workers=1, rerun_other_code=True)
        assert (redone.skipped, redone.finished, redone.rerun_other_code, redone.other_code) == (1, 2, 2, 0)
        assert "2 stored trials made by other terrabench code run again" in redone.describe()
        assert set(st.code_of([a.key, b.key, c.key]).values()) == {code_fingerprint()}  # rows replaced
        assert run_trials([a, b, c], st, workers=1).other_code == 0
    assert len(code_fingerprint()) == 16 and code_fingerprint() == code_fingerprint()


def test_a_failing_trial_becomes_an_error_row(tmp_path, monkeypatch):
    bad = TrialSpec("mrs-cwc", "mrs-cwc/benchmark-v1", "cwc-tdt", "A-01", 0, {"physics": {"nonsense": 1}})
    res = execute(bad)
    assert res.status == "error" and "nonsense" in res.info["error"]
    with ResultsStore(tmp_path / "r.duckdb") as st:
        s = run_trials([bad] + quick_specs(("A-02",)), st, workers=1)
        assert s.statuses == {"error": 1, "timeout": 1}


def test_interrupt_keeps_finished_trials_and_resume_completes(tmp_path, monkeypatch):
    specs = quick_specs(("A-01", "A-02", "A-03"))
    calls = {"n": 0}
    real = runner.execute

    def flaky(spec):
        calls["n"] += 1
        if calls["n"] == 2:
            raise KeyboardInterrupt
        return real(spec)

    monkeypatch.setattr(runner, "execute", flaky)
    with ResultsStore(tmp_path / "r.duckdb") as st:
        s = run_trials(specs, st, workers=1)
        assert s.interrupted and len(st.rows()) == 1
        monkeypatch.setattr(runner, "execute", real)
        s = run_trials(specs, st, workers=1)
        assert s.finished == 2 and len(st.rows()) == 3


def test_process_pool_matches_in_process(tmp_path):
    specs = quick_specs(("A-04", "B-05"), timeout=2.0)
    with ResultsStore(tmp_path / "a.duckdb") as a, ResultsStore(tmp_path / "b.duckdb") as b:
        run_trials(specs, a, workers=1)
        run_trials(specs, b, workers=2)
        ra = {r["key"]: r["metrics"] for r in a.rows()}
        rb = {r["key"]: r["metrics"] for r in b.rows()}
        assert len(ra) == 2
        np.testing.assert_equal(ra, rb)  # NaN == NaN here
        # every row says what it ran on: the versions and numpy's SIMD paths decide last bits
        import mujoco

        for r in b.rows():
            host = r["info"]["host"]
            assert host["numpy"] == np.__version__ and host["mujoco"] == mujoco.__version__
            assert isinstance(host["numpy_simd"], list)


def test_incompatible_store_is_refused_and_left_untouched(tmp_path):
    path = tmp_path / "old.duckdb"
    with ResultsStore(path):
        pass
    con = duckdb.connect(str(path))
    con.execute("UPDATE meta SET value = '0' WHERE name = 'schema_version'")
    con.close()
    before = path.read_bytes()
    with pytest.raises(StoreError, match="schema version 0"):
        ResultsStore(path)
    assert path.read_bytes() == before


def test_foreign_duckdb_file_is_refused(tmp_path):
    path = tmp_path / "other.duckdb"
    con = duckdb.connect(str(path))
    con.execute("CREATE TABLE t (x INT)")
    con.close()
    with pytest.raises(StoreError, match="not a terrabench results store"):
        ResultsStore(path)


def test_unknown_backend_is_refused(tmp_path):
    with ResultsStore(tmp_path / "r.duckdb") as st, pytest.raises(ValueError, match="valid: local, ray"):
        run_trials(quick_specs(), st, backend="slurm")


def test_ray_backend_gives_identical_results(tmp_path):
    pytest.importorskip("ray")
    specs = quick_specs(("A-06", "B-07"), timeout=1.0)
    with ResultsStore(tmp_path / "local.duckdb") as a, ResultsStore(tmp_path / "ray.duckdb") as b:
        run_trials(specs, a, workers=1)
        s = run_trials(specs, b, backend="ray", workers=2)
        assert s.finished == 2
        ra = {r["key"]: (r["status"], r["metrics"]) for r in a.rows()}
        rb = {r["key"]: (r["status"], r["metrics"]) for r in b.rows()}
        np.testing.assert_equal(ra, rb)
        for r in list(a.rows()) + list(b.rows()):  # both backends ran on the pinned CPU paths
            host = r["info"]["host"]
            assert host["pinned"] is True and host["numpy_simd"] == [] and host["numba_cpu_name"] == "generic"
        for key in ra:
            ta, tb = a.timeseries(key), b.timeseries(key)
            for col in ta:
                np.testing.assert_array_equal(ta[col], tb[col])


def test_a_method_is_keyed_by_the_config_sections_it_reads():
    base = {s.method: s for s in SYSTEM.plan(methods=["all"], instances=["A-01"])}
    assert "stiffness" not in base["d-tdt"].config and "follow" in base["d-tdt"].config
    assert "planner" not in base["cwc-astar"].config  # released waypoints: the planner is unused
    changed = {s.method: s
               for s in SYSTEM.plan(methods=["all"], instances=["A-01"], overrides={"follow.speed_gain": 4.0})}
    moved = sorted(m for m in base if base[m].key != changed[m].key)
    assert moved == ["d-astar", "d-tdt"]
    planner = SYSTEM.plan(methods=["cwc-astar"], instances=["A-01"], overrides={"waypoint_source": "planner"})[0]
    assert "planner" in planner.config


def test_rekey_moves_rows_and_series_to_the_new_key_and_keeps_results(tmp_path):
    new = SYSTEM.plan(methods=["mj-tdt"], instances=["A-01"])[0]
    old = TrialSpec(new.system, new.scenario, new.method, new.instance, 0, {**new.config, "legacy": {"x": 1}})
    res = TrialResult("timeout", {"NCR": 0.25}, {"t": np.arange(3.0)}, 1.0, {})
    with ResultsStore(tmp_path / "r.duckdb") as st:
        st.write(old, res)
        assert st.done_keys([new.key]) == set()
        strip = lambda s: TrialSpec(s.system, s.scenario, s.method, s.instance, s.seed,  # noqa: E731
                                    {k: v for k, v in s.config.items() if k != "legacy"})
        assert st.rekey("mrs-cwc", strip) == 1
        assert st.rekey("mrs-cwc", strip) == 0  # idempotent
        assert st.done_keys([new.key]) == {new.key}
        row = st.rows(keys=[new.key])[0]
        assert row["metrics"]["NCR"] == 0.25 and row["config_hash"] == new.config_hash
        assert list(st.timeseries(new.key)["t"]) == [0.0, 1.0, 2.0] and not st.timeseries(old.key)
