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


def test_the_task_table_holds_the_papers_tasks_only():
    """The slope sweep and the ``ik`` cases have their own sections: the task table (and the
    per-mode snapshots and clips, which prefer task rows) read the registry's group ``tasks``."""
    from terrabench.systems.srwmr.layouts import instance_ids
    from terrabench.systems.srwmr.report import _in_tasks

    assert all(_in_tasks({"instance": i}) for i in instance_ids("tasks"))
    assert not any(_in_tasks({"instance": i}) for i in instance_ids("ik") + instance_ids("slopes"))
    assert _in_tasks({"instance": "t99-retired"})  # a stored row of an instance no longer registered
