"""The srwmr report: tables from stored rows and a snapshot strip of each mode's first trial."""

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.catalog import system


def test_report_shows_each_modes_snapshots(tmp_path):
    sysobj = system("srwmr")
    specs = sysobj.plan(methods=["wrm"], instances=["t1-loose"], overrides={"protocol.timeout": 2.0})
    with ResultsStore(tmp_path / "s.duckdb") as st:
        run_trials(specs, st, workers=1)
        index = sysobj.report(st, tmp_path / "out")
    text = index.read_text()
    assert "href='tasks.csv'" in text and "src='timeline.png'" in text
    assert "src='snap_wrm.png'" in text and (tmp_path / "out" / "snap_wrm.png").stat().st_size > 0
