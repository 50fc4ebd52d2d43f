"""The srwmr report: tables from stored rows and a snapshot strip of each mode's first trial."""

import re

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
    # a run under --set is its own settings group: its files carry the group's slug
    assert re.search(r"href='tasks(_v[0-9a-f]{8})?\.csv'", text)
    assert re.search(r"src='timeline(_v[0-9a-f]{8})?\.png'", text)
    snap = re.search(r"src='(snap_wrm(_v[0-9a-f]{8})?\.png)'", text)
    assert snap and (tmp_path / "out" / snap.group(1)).stat().st_size > 0
