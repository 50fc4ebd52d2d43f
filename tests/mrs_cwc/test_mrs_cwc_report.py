"""The MRS-CWC report: built from a few real short trials, every number beside its source."""

import csv
import re

import pytest

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.systems.mrs_cwc.report import OUTPUTS, find_variants, write_report
from terrabench.systems.mrs_cwc.scenarios import SYSTEM


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """(index.html path, stored rows) of a report on 2 methods x 2 terrains, 2 s each."""
    tmp = tmp_path_factory.mktemp("report")
    specs = SYSTEM.plan(methods=["cwc-tdt", "d-tdt"], instances=["A-01", "B-01"], overrides={"protocol.timeout": 2.0})
    with ResultsStore(tmp / "r.duckdb") as st:
        run_trials(specs, st, workers=1)
        return write_report(st, tmp / "out"), st.rows()


def _csv(path):
    with path.open() as f:
        return list(csv.DictReader(f))


def test_every_output_is_written_and_the_page_shows_every_png(report):
    index, _ = report
    out = index.parent
    # both waypoint sources are needed for astar_sources.csv; this store has no A* runs
    assert {p.name for p in out.iterdir() if not p.name.startswith(".")} == set(OUTPUTS) - {"astar_sources.csv"}
    page = index.read_text()
    for png in out.glob("*.png"):
        assert f"src='{png.name}'" in page
    for name in ("table_A.csv", "table_B.csv", "outcomes.csv", "astar_paths.csv", "statuses.csv"):
        assert f"href='{name}'" in page
    assert not re.search(r"(src|href)=['\"](https?:)?//", page), "the page must not load anything external"
    assert "<details id='cfg-" in page


def test_tables_put_the_papers_numbers_beside_ours(report):
    index, rows = report
    a = {r["method"]: r for r in _csv(index.parent / "table_A.csv")}
    b = {r["method"]: r for r in _csv(index.parent / "table_B.csv")}
    assert list(a) == ["cwc-tdt", "d-tdt"] and list(b) == ["cwc-tdt", "d-tdt"]  # METHODS order
    assert float(a["cwc-tdt"]["NSR_paper"]) == 96.0 and float(a["d-tdt"]["NCR_paper"]) == 79.1
    assert float(b["cwc-tdt"]["NEC_paper"]) == 754.5 and float(b["d-tdt"]["NSR_paper"]) == 0.0
    for line in (*a.values(), *b.values()):
        assert line["n"] == "1" and line["n_paper"] == "50"
        assert 0.0 <= float(line["NSR_lo"]) <= float(line["NSR"]) <= float(line["NSR_hi"]) <= 100.0
    ours = {(r["method"], r["instance"]): r for r in rows}
    assert float(a["cwc-tdt"]["NCR"]) == pytest.approx(100 * ours[("cwc-tdt", "A-01")]["metrics"]["NCR"], abs=1e-4)


def test_outcome_and_status_csvs_name_the_stored_trials(report):
    index, rows = report
    outcomes = _csv(index.parent / "outcomes.csv")
    assert sorted(o["key"] for o in outcomes) == sorted(r["key"] for r in rows)
    total = _csv(index.parent / "statuses.csv")[-1]
    assert total["group"] == "all" and int(total["n"]) == len(rows)
    assert sum(int(total[s]) for s in ("success", "timeout", "fell", "stuck", "diverged", "error")) == len(rows)


def test_a_method_run_with_two_waypoint_sources_gives_two_labelled_rows():
    cfg = {"protocol": {"timeout": 2.0}, "waypoint_source": "released"}
    rows = [
        {"method": "cwc-astar", "config_hash": "a" * 16, "config": cfg},
        {"method": "cwc-astar", "config_hash": "b" * 16, "config": {**cfg, "waypoint_source": "planner"}},
        {"method": "cwc-tdt", "config_hash": "a" * 16, "config": cfg},
    ]
    labels = [v.label for v in find_variants(rows)]
    assert labels == ["MRS-CWC + TDT", "MRS-CWC + A* (released waypoints)", "MRS-CWC + A* (our planner)"]


def test_an_empty_store_says_what_to_run(tmp_path):
    with ResultsStore(tmp_path / "empty.duckdb") as st:
        with pytest.raises(ValueError, match="no mrs-cwc trials in .*terrabench run mrs-cwc"):
            write_report(st, tmp_path / "out")


def test_seed_summary_pools_seeds_and_counts_flips():
    from terrabench.systems.mrs_cwc.summary import seed_summary

    def row(t, seed, ok):
        return {"method": "cwc-tdt", "instance": t, "seed": seed, "status": "success" if ok else "timeout"}

    outcomes = {"B-01": (1, 1), "B-02": (1, 0), "B-03": (0, 0), "B-04": (0, 1)}
    rows = [row(t, k, ok) for t, oks in outcomes.items() for k, ok in enumerate(oks)]
    rows.append(row("B-05", 0, 1))  # run with one seed only: left out
    s = seed_summary(rows)[("cwc-tdt", "B")]
    assert s["n_terrains"] == 4 and s["n_seeds"] == 2
    assert s["NSR"] == 50.0 and s["flip_share"] == 50.0
    assert 0.0 <= s["NSR_lo"] <= 50.0 <= s["NSR_hi"] <= 100.0
    assert seed_summary(rows) == seed_summary(rows)  # deterministic bootstrap
