"""The command line: listings, bad input handling, terrain commands, a tiny run."""

import pytest
from typer.testing import CliRunner

from terrabench.cli import app

runner = CliRunner()


def invoke(*args):
    r = runner.invoke(app, list(args))
    r.text = " ".join(r.output.split())  # rich wraps long lines at the terminal width
    return r


def test_list_shows_systems_scenarios_and_every_method():
    r = invoke("list")
    assert r.exit_code == 0
    for word in ("mrs-cwc", "mrs-cwc/benchmark-v1", "cwc-tdt", "d-astar"):
        assert word in r.output


@pytest.mark.parametrize(
    "args, needle",
    [
        (["run", "mrs-cwc", "--terrains", "C-99"], "unknown terrain id 'C-99'"),
        (["run", "mrs-cwc", "--group", "Q"], "valid: A, B, all"),
        (["run", "mrs-cwc", "--methods", "cwc-magic"], "valid: cwc-tdt"),
        (["run", "mrs-cwc", "--backend", "slurm"], "valid: local, ray"),
        (["run", "mrs-cwc", "--timeout", "0"], "--timeout must be a positive finite number"),
        (["run", "mrs-cwc", "--timeout", "-5"], "--timeout must be a positive finite number"),
        (["run", "mrs-cwc", "--timeout", "inf"], "--timeout must be a positive finite number"),
        (["run", "mrs-cwc", "--terrains", ""], "--terrains was given an empty list"),
        (["run", "mrs-cwc", "--terrains", ","], "--terrains was given an empty list"),
        (["run", "mrs-cwc", "--group", ""], "--group was given an empty value"),
        (["run", "mrs-cwc", "--seeds", "0"], "--seeds must be at least 1"),
        (["run", "mrs-cwc", "--set", "physics=1"], "'physics' is a section"),
        (["run", "mrs-cwc", "--set", "physics.timestep=abc"], "expects a number"),
        (["run", "mrs-cwc", "--address", "127.0.0.1:9"], "needs --backend ray"),
        (["run", "beams", "--group", "open-loop", "--set", "k1=abc"], "k1"),
        (["run", "nosuch"], "unknown system 'nosuch'; valid: beams, mrs-cwc, octopus, soil"),
        (["run", "mrs-cwc", "--set", "physics.nope=1"], "unknown config key 'physics.nope'"),
        (["terrain", "show", "Z-1"], "unknown terrain id"),
        (["report", "mrs-cwc", "--store", "/nonexistent/x.duckdb"], "results file not found"),
    ],
)
def test_bad_input_gives_one_clear_line_and_exit_2(args, needle, tmp_path):
    r = invoke(*args, *(["--store", str(tmp_path / "s.duckdb")] if args[0] == "run" else []))
    assert r.exit_code == 2, r.output
    assert needle in r.text
    assert "Traceback" not in r.output


def test_version_is_printed():
    from terrabench import __version__

    r = invoke("--version")
    assert r.exit_code == 0 and __version__ in r.output


def test_bad_store_version_is_refused_without_touching_it(tmp_path):
    import duckdb

    from terrabench.benchmark.store import ResultsStore

    path = tmp_path / "s.duckdb"
    ResultsStore(path).close()
    con = duckdb.connect(str(path))
    con.execute("UPDATE meta SET value='99' WHERE name='schema_version'")
    con.close()
    before = path.read_bytes()
    r = invoke("run", "mrs-cwc", "--terrains", "A-01", "--timeout", "1", "--store", str(path))
    assert r.exit_code == 2 and "schema version 99" in r.text
    assert path.read_bytes() == before


def test_terrain_stats_and_show(tmp_path):
    r = invoke("terrain", "stats", "--group", "B")
    assert r.exit_code == 0 and "B-50" in r.output and "A-01" not in r.output
    out = tmp_path / "b07.png"
    r = invoke("terrain", "show", "B-07", "--out", str(out), "--store", str(tmp_path / "none.duckdb"))
    assert r.exit_code == 0 and out.stat().st_size > 10_000


def test_a_tiny_run_prints_trials_and_the_paper_row_then_resumes(tmp_path):
    store = str(tmp_path / "s.duckdb")
    args = ["run", "mrs-cwc", "--terrains", "A-01,B-01", "--timeout", "1", "--workers", "1", "--store", store]
    r = invoke(*args)
    assert r.exit_code == 0, r.output
    assert "A-01" in r.output and "(96.0)" in r.output and "(74.0)" in r.output
    r = invoke(*args)
    assert "2 already stored, 0 run" in r.text and "other terrabench code" not in r.text
    import duckdb  # the rows as another checkout would have left them: a different code digest

    with duckdb.connect(store) as con:
        con.execute("UPDATE trials SET info = json_merge_patch(info, '{\"host\": {\"code\": \"another\"}}')")
    r = invoke(*args)
    assert "2 of the stored trials were made by other terrabench code" in " ".join(r.text.split())
    r = invoke(*args, "--rerun-other-code")
    assert "0 already stored, 2 run" in r.text and "2 stored trials made by other terrabench code run again" in (
        " ".join(r.text.split()))
    out = tmp_path / "a01.png"
    r = invoke("terrain", "show", "A-01", "--out", str(out), "--store", store)
    assert r.exit_code == 0 and "1 stored path" in r.text


def test_perf_reports_both_throughputs_and_their_ratio():
    r = invoke("perf", "mrs-cwc", "--terrains", "B-05", "--seconds", "0.5")
    assert r.exit_code == 0, r.output
    assert "loop/raw" in r.text and "B-05" in r.text
    r = invoke("perf", "mrs-cwc", "--seconds", "-1")
    assert r.exit_code == 2 and "seconds must be a positive" in r.text
    r = invoke("perf", "mrs-cwc", "--terrains", "B-05", "--seconds", "0.5", "--repeats", "1", "--parts")
    assert r.exit_code == 0, r.output
    assert "where the loop's time goes" in r.text and "controller" in r.text and "mj_step" in r.text


def test_generate_then_stats_round_trips_and_a_bad_csv_is_refused(tmp_path):
    out = tmp_path / "new.csv"
    r = invoke("terrain", "generate", "--n", "2", "--band", "30,45", "--seed", "3", "--out", str(out))
    assert r.exit_code == 0, r.output
    r = invoke("terrain", "stats", "--csv", str(out))
    assert r.exit_code == 0 and "row-2" in r.text
    bad = tmp_path / "bad.csv"
    bad.write_text("Size,Height\n0.05,0.1\n")
    r = invoke("terrain", "stats", "--csv", str(bad))
    assert r.exit_code == 2 and "missing column(s) XY Proportion" in r.text and "Traceback" not in r.output
    r = invoke("terrain", "generate", "--band", "45")
    assert r.exit_code == 2 and "--band must be LOW,HIGH" in r.text
