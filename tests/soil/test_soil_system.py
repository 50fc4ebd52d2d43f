"""The soil system: the single-wheel rig through the episode loop, the CMU group, the report."""

import numpy as np
import pytest
from typer.testing import CliRunner

from terrabench.benchmark.runner import execute
from terrabench.cli import app
from terrabench.systems.soil import cmu
from terrabench.systems.soil.scenarios import SYSTEM, parse_instance

FAST = {"rig.settle_s": 1.0, "rig.average_s": 0.3}


@pytest.mark.parametrize("iid", ["mars_soft/W100/s0.40", "mars_loose/W370/s0.30", "mars_very_loose/W370/s-0.50",
                                 "dry_sand/W150/s-1.00"])
def test_the_rig_in_the_episode_loop_matches_the_steady_state_equations(iid):
    # Tolerances: DP and T/r within 1.5 % of the load (the table's own interpolation tolerance,
    # tests/soil/test_soil_table.py), sinkage within 2 %, slip within 0.01 (the rig's servos hold
    # the commanded slip; the hook runs every physics step, every=1).
    load = parse_instance(iid)[1]
    specs = SYSTEM.plan(methods=["rig", "analytic"], instances=[iid], overrides=FAST)
    rig, ana = (execute(s) for s in specs)
    assert rig.status == ana.status == "done"
    assert rig.metrics["DP_N"] == pytest.approx(ana.metrics["DP_N"], abs=0.015 * load)
    assert rig.metrics["torque_Nm"] == pytest.approx(ana.metrics["torque_Nm"], abs=0.015 * load * 0.15)
    assert rig.metrics["sinkage_m"] == pytest.approx(ana.metrics["sinkage_m"], rel=0.02)
    assert rig.metrics["slip_measured"] == pytest.approx(parse_instance(iid)[2], abs=0.01)
    assert rig.info["physics_steps"] == 1300  # 1.3 s at 1 ms: one hook call per physics step


def test_soil_and_load_are_stored_with_the_trial():
    (a,) = SYSTEM.plan(methods=["analytic"], instances=["dry_sand/W100/s0.2"])
    (b,) = SYSTEM.plan(methods=["analytic"], instances=["lunar_regolith/W100/s0.2"])
    assert a.config["soil"]["name"] == "dry_sand" and a.config["soil"]["phi_deg"] == 28.0
    assert a.key != b.key


@pytest.mark.parametrize("iid, needle", [
    ("mars_soft/W100/s1.5", "outside the documented range"),
    ("clay/W100/s0.2", "valid: dry_sand, lunar_regolith, mars_loose, mars_soft, mars_very_loose, custom"),
    ("mars_soft/W10/s0.2", "must exceed the wheel's weight"),
    ("mars_soft-100-0.2", "must look like"),
    ("cmu/b30/t999", "out of range"),
    ("cmu/b45/t000", "not 45"),
    ("cmu/30/1", "must look like cmu/b"),
])
def test_bad_instances_name_the_value(iid, needle):
    with pytest.raises(ValueError, match=needle):
        SYSTEM.plan(methods=["analytic"], instances=[iid])


@pytest.mark.parametrize("setting, needle", [
    ("custom_soil.phi_deg=95", "phi_deg"),
    ("custom_soil.k_phi=0", "k_phi"),
    ("custom_soil.form=clay", "form"),
    ("wheel.radius=-0.1", "radius"),
])
def test_bad_soil_and_wheel_parameters_give_one_line(setting, needle, tmp_path):
    r = CliRunner().invoke(app, ["run", "soil", "--terrains", "custom/W100/s0.2", "--set", setting,
                                 "--store", str(tmp_path / "s.duckdb")])
    assert r.exit_code == 2, r.output
    assert needle in r.output and "Traceback" not in r.output
    assert not (tmp_path / "s.duckdb").exists()


def test_parse_instance():
    assert parse_instance("mars_soft/W100/s-0.20") == ("mars_soft", 100.0, -0.2)
    assert parse_instance("mars_soft/W100/s-1.00") == ("mars_soft", 100.0, -1.0)


def test_cmu_group_has_every_measured_trial_once_per_parameter_set():
    specs = SYSTEM.plan(group="cmu-smooth")
    assert len(specs) == 2 * 189
    assert {s.method for s in specs} == {"cmu-authors", "cmu-fit-b0"}
    assert len({s.instance for s in specs}) == 189
    # the rig and the equations do not run on measured trials (and vice versa)
    assert not SYSTEM.plan(methods=["rig"], group="cmu-smooth")
    p = cmu.points()
    assert len(p["trial"]) == 189 and set(p["beta_deg"]) == set(cmu.BETAS)
    assert np.all(p["slip"] >= -1) and np.all(p["slip"] <= 0.91)


def test_a_cmu_trial_stores_measured_and_model_values():
    (spec,) = SYSTEM.plan(methods=["cmu-fit-b0"], instances=["cmu/b0/t" + _trial(0, -1.0)])
    r = execute(spec)
    m = r.metrics
    assert r.status == "done" and m["fitted"] == 1.0 and m["slip"] == -1.0
    assert m["DP_meas_N"] < -30 and m["sinkage_meas_m"] > 0.045  # the locked wheel, as measured
    (spec,) = SYSTEM.plan(methods=["cmu-fit-b0"], instances=["cmu/b45/t" + _trial(45, 0.5)])
    assert execute(spec).metrics["fitted"] == 0.0


def _trial(beta, slip):
    p = cmu.points()
    i = int(np.flatnonzero((p["beta_deg"] == beta) & (np.abs(p["slip"] - slip) < 0.01))[0])
    return f"{i:03d}"


def test_the_fit_on_slip_angle_zero_meets_the_targets_on_its_own_points():
    # The stored fit (fit_beta0.json) against the 27 slip-angle-0 trials it was fitted on:
    # calibration quality, not validation. Measured: DP 2.8 % (driving) / 3.0 % (all) of the
    # load, sinkage 3.1 mm; the lateral force there is measurement noise (+-1.5 N, model 0).
    p = cmu.points()
    idx = np.flatnonzero(p["beta_deg"] == 0)
    m = cmu.evaluate("cmu-fit-b0", idx)
    e = cmu.rms_table({k: v[idx] for k, v in p.items()}, m, np.ones(len(idx), bool))
    assert e["DP_drive"] <= cmu.TARGETS["DP_drive"]
    assert e["DP_all"] <= cmu.TARGETS["DP_all"]
    assert e["sinkage"] <= cmu.TARGETS["sinkage"]
    assert set(cmu.fitted()["fitted_trials"]) == set(int(i) for i in p["trial"][idx])


def test_report_separates_config_variants_and_shows_cmu_rms(tmp_path):
    store = str(tmp_path / "s.duckdb")
    runner = CliRunner()
    cmu_ids = ",".join(f"cmu/b{b}/t{_trial(b, s)}" for b in (0, 30) for s in (-1.0, 0.5))
    for args in (["--terrains", "custom/W100/s0.2,custom/W100/s0.4", "--methods", "analytic"],
                 ["--terrains", "custom/W100/s0.2,custom/W100/s0.4", "--methods", "analytic",
                  "--set", "custom_soil.phi_deg=33"],
                 ["--terrains", cmu_ids, "--methods", "cmu-authors,cmu-fit-b0"]):
        r = runner.invoke(app, ["run", "soil", *args, "--store", store])
        assert r.exit_code == 0, r.output
    out = tmp_path / "rep"
    r = runner.invoke(app, ["report", "soil", "--store", store, "--out", str(out)])
    assert r.exit_code == 0, r.output
    html = (out / "index.html").read_text()
    # two --set variants of one method: two labelled lines
    assert "analytic (custom_soil.phi_deg=33" in html and "analytic (custom_soil.phi_deg=30" in html
    assert "target 3" in html and "fitted" in html and "predicted" in html
    assert (out / "cmu_smooth.png").stat().st_size > 10_000
    rms = (out / "cmu_rms.csv").read_text()
    assert "cmu-fit-b0" in rms and "cmu-authors" in rms


@pytest.mark.slow
def test_the_stored_fit_is_what_the_fit_gives():
    # fit_beta0.json is the output of cmu.fit() (python -m terrabench.systems.soil.cmu --fit);
    # rerunning it from the authors' values lands on the same parameters
    r = cmu.fit()
    np.testing.assert_allclose(r["x"], cmu.fitted()["x"], rtol=1e-3, atol=1e-4)
    assert r["fitted_trials"] == cmu.fitted()["fitted_trials"]
