"""One contract test over every registered system (a new system gets these by registering).

plan -> run one short trial -> a row in a temporary store -> summarise -> report; the stored
config rebuilds the trial; same spec, same numbers; bad ids give a clear error.
"""

import numpy as np
import pytest
from rich.console import Console

from terrabench.benchmark.runner import execute, run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import STATUSES
from terrabench.catalog import populate, system

SYSTEM_IDS = populate().ids("system")


def test_every_system_declares_a_smoke_request():
    assert {"mrs-cwc", "beams"} <= set(SYSTEM_IDS)
    for sid in SYSTEM_IDS:
        assert system(sid).smoke, f"system {sid!r} has no smoke request"


@pytest.fixture(scope="module", params=SYSTEM_IDS)
def smoke_run(request, tmp_path_factory):
    sysdef = system(request.param)
    specs = sysdef.plan(**sysdef.smoke)
    tmp = tmp_path_factory.mktemp(request.param)
    with ResultsStore(tmp / "s.duckdb") as st:
        summary = run_trials(specs[:1], st, workers=1)
        rows = st.rows()
        series = st.timeseries(rows[0]["key"]) if rows else {}
        report = sysdef.report(st, tmp / "report")
    return sysdef, specs, summary, rows, series, report


def test_plan_run_store(smoke_run):
    sysdef, specs, summary, rows, series, _ = smoke_run
    assert specs and all(s.system == sysdef.id for s in specs)
    assert summary.finished == 1 and len(rows) == 1
    row = rows[0]
    assert row["status"] in STATUSES and row["status"] != "error", row["info"]
    assert row["key"] == specs[0].key and row["config"] == dict(specs[0].config)
    assert row["metrics"] and all(isinstance(v, float) or isinstance(v, int) for v in row["metrics"].values())


def test_stored_config_rebuilds_the_trial(smoke_run):
    sysdef, specs, *_ = smoke_run
    spec = specs[0]
    cfg = sysdef.load_config(spec.config)
    assert cfg is not None
    assert sysdef.trial_config(spec.method, spec.instance, cfg) == dict(spec.config)


def test_summarize_and_report(smoke_run):
    sysdef, _, _, rows, _, report = smoke_run
    Console(file=open("/dev/null", "w")).print(sysdef.summarize(rows))
    assert report.exists() and report.stat().st_size > 0


def test_same_spec_same_numbers(smoke_run):
    sysdef, specs, *_ = smoke_run
    a, b = execute(specs[0]), execute(specs[0])
    assert a.status == b.status
    assert a.metrics.keys() == b.metrics.keys()
    for k in a.metrics:
        assert (a.metrics[k] == b.metrics[k]) or (a.metrics[k] != a.metrics[k] and b.metrics[k] != b.metrics[k]), k
    for k in a.timeseries:
        np.testing.assert_array_equal(a.timeseries[k], b.timeseries[k])


@pytest.mark.parametrize("sid", SYSTEM_IDS)
def test_one_trials_spec_is_the_plans(sid):
    """System.trial_spec(method, instance, seed): the spec plan() gives that trial among its seeds,
    the same key (so the same stored row), and the plan's checks on a bad request."""
    sysdef = system(sid)
    first = sysdef.plan(**sysdef.smoke)[0]
    overrides = sysdef.smoke.get("overrides")
    specs = sysdef.plan(methods=[first.method], instances=[first.instance], seeds=3, overrides=overrides)
    for spec in specs:
        assert sysdef.trial_spec(first.method, first.instance, spec.seed, overrides).key == spec.key
    if len(specs) < 3:  # a deterministic trial: the seeds it is not run with are no trial
        with pytest.raises(ValueError, match="not seed 2"):
            sysdef.trial_spec(first.method, first.instance, 2, overrides)
    with pytest.raises(ValueError, match="nope"):
        sysdef.trial_spec(first.method, "nope")
    with pytest.raises(ValueError, match="seed must be"):
        sysdef.trial_spec(first.method, first.instance, -1)


@pytest.mark.parametrize("sid", SYSTEM_IDS)
def test_bad_request_names_the_value_and_the_choices(sid):
    sysdef = system(sid)
    with pytest.raises(ValueError, match="nope.*valid"):
        sysdef.plan(methods=["nope"])
    with pytest.raises(ValueError, match="nope"):
        sysdef.plan(instances=["nope"])
    with pytest.raises(ValueError, match="nope.*valid"):
        sysdef.plan(group="nope")
    with pytest.raises(ValueError, match="seeds"):
        sysdef.plan(seeds=0)
    with pytest.raises(ValueError, match="nope"):
        sysdef.plan(overrides={"nope.nope": 1})
