"""OCTOPUS report: built from a store on the shared page layer, with the mode timelines."""

from pathlib import Path

import pytest

from terrabench.benchmark.store import ResultsStore
from terrabench.systems.octopus.scenarios import SYSTEM


def test_report_from_a_store(tmp_path: Path):
    pytest.importorskip("matplotlib")
    store = ResultsStore(tmp_path / "r.duckdb")
    specs = SYSTEM.plan(methods=["clm", "ccm"], instances=["step-400"], seeds=1, overrides={"protocol.timeout": 8.0})
    specs += SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1,
                         overrides={"protocol.timeout": 8.0, "clm.press": 0.01})
    for spec in specs:
        store.write(spec, SYSTEM.run_trial(spec))
    rows = store.rows(system="octopus")
    assert all(r["info"]["events"] for r in rows)      # transitions are stored with each trial
    ev = rows[0]["info"]["events"][0]
    assert len(ev) == 4 and isinstance(ev[0], float)   # [t, src, dst, reason]
    index = SYSTEM.report(store, tmp_path / "out")
    text = index.read_text()
    assert "modes_step-400_ccm.png" in text
    assert text.count("<img src='modes_step-400_clm_") == 2  # one mode timeline per CLM variant
    assert "clm.press=0.01" in text                   # the --set variant is its own labelled line
    assert (tmp_path / "out" / "tasks.csv").read_text().count("\n") == 4
