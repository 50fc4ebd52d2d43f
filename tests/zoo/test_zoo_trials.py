"""One short real trial per robot on its easiest family: a plausible outcome, stored like any
other system's trial, and the stored config re-runs to the same bits."""

from __future__ import annotations

import math

import pytest

from terrabench.benchmark.golden import result_digest
from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialSpec
from terrabench.catalog import system
from terrabench.zoo.adapter import adapters

ZOO = system("zoo")


def _store_and_rerun(spec, tmp_path):
    """Run ``spec`` through the runner into a store, then re-run the stored row's own config."""
    with ResultsStore(tmp_path / "zoo.duckdb") as st:
        summary = run_trials([spec], st, workers=1)
        (row,) = st.rows(system="zoo")
    assert summary.finished == 1 and row["key"] == spec.key and row["config"] == dict(spec.config)
    again = TrialSpec(row["system"], row["scenario"], row["method"], row["instance"], row["seed"], row["config"])
    assert again.key == spec.key
    return row, ZOO.run_trial(again), ZOO.run_trial(spec)


@pytest.mark.parametrize("method", ["octopus.ccm", "mrs-cwc.cwc-tdt"])
def test_rigid_robot_climbs_the_lowest_step_and_reruns_to_the_same_bits(method, tmp_path):
    (spec,) = ZOO.plan(methods=[method], instances=["step-up@0.05"])
    fp = adapters()[method.partition(".")[0]].footprint()
    row, a, b = _store_and_rerun(spec, tmp_path)
    assert row["status"] == "success", row["info"]["reason"]
    m = row["metrics"]
    # the rearmost point travelled the whole course: run-up, the goal margin and the robot's length
    assert m["progress"] == pytest.approx(0.4 + 0.3 + fp.length, abs=0.05)
    assert 0.3 * fp.speed < m["speed"] < 2.0 * fp.speed
    assert m["time"] < spec.config["protocol"]["timeout"] and m["goal_left"] <= 0.0
    assert 0.0 < m["energy_per_m_kg"] < 50.0 and m["energy"] > 0
    assert 0.02 < m["max_pitch"] < 1.2 and m["max_roll"] < 0.2  # it tilted over the step, not sideways
    assert row["info"]["family"] == "step-up" and row["info"]["goal_x"] == pytest.approx(0.3)
    assert result_digest(a) == result_digest(b)
    assert a.status == row["status"] and a.metrics == pytest.approx(row["metrics"], nan_ok=True)


def test_rover_drives_on_loose_soil_and_reruns_to_the_same_bits(tmp_path):
    (spec,) = ZOO.plan(methods=["srwmr.wrm"], instances=["soft-flat@loose"], overrides={"protocol.timeout": 8.0})
    row, a, b = _store_and_rerun(spec, tmp_path)
    m = row["metrics"]
    assert row["status"] == "timeout" and m["sim_time"] == pytest.approx(8.0)
    # it moves forward at a fraction of its 25 mm/s plan (start-up, slip), sinks, stays level
    assert 0.05 < m["progress"] < 0.25 and 0.0 < m["speed"] < 0.03
    assert m["energy"] > 0 and m["max_pitch"] < 0.1 and m["max_roll"] < 0.05
    assert row["info"]["soil"] == "loose" and row["info"]["family"] == "soft-flat"
    assert 0.005 < m["robot_sinkage"] < 0.1  # m: the wheels sink into the loose soil
    assert row["info"]["goal_x"] == pytest.approx(2.3) and row["info"]["goal_chassis"] > 2.3
    assert result_digest(a) == result_digest(b) and math.isclose(a.metrics["progress"], m["progress"])


@pytest.mark.slow
def test_rover_crosses_loose_flat_soil():
    (spec,) = ZOO.plan(methods=["srwmr.wrm"], instances=["soft-flat@loose"])
    r = ZOO.run_trial(spec)
    assert r.status == "success", r.info["reason"]


def test_an_unsupported_pair_is_refused_by_the_task_too():
    (spec,) = ZOO.plan(methods=["octopus.ccm"], instances=["step-up@0.05"])
    bad = TrialSpec("zoo", spec.scenario, "octopus.ccm", "soft-flat@loose", 0, spec.config)
    with pytest.raises(ValueError, match="terramechanics"):
        ZOO.run_trial(bad)
