"""The single-wheel testbed as a system: soil forces through the episode loop's substep hook."""

import pytest
from typer.testing import CliRunner

from terrabench.benchmark.runner import execute
from terrabench.cli import app
from terrabench.systems.soil.scenarios import SYSTEM, parse_instance


def test_the_rig_in_the_episode_loop_matches_the_steady_state_equations():
    specs = SYSTEM.plan(methods=["rig", "analytic"], instances=["mars_soft/W100/s0.40"],
                        overrides={"rig.settle_s": 1.0, "rig.average_s": 0.3})
    rig, ana = (execute(s) for s in specs)
    assert rig.status == ana.status == "done"
    # the hook ran every physics step: the rig holds the analytic drawbar pull and torque
    assert rig.metrics["DP_N"] == pytest.approx(ana.metrics["DP_N"], abs=0.01 * 100)
    assert rig.metrics["torque_Nm"] == pytest.approx(ana.metrics["torque_Nm"], rel=0.02)
    assert rig.metrics["sinkage_m"] == pytest.approx(ana.metrics["sinkage_m"], rel=0.02)
    assert rig.metrics["slip_measured"] == pytest.approx(0.40, abs=0.01)
    assert rig.info["physics_steps"] == 1300  # 1.3 s at 1 ms: one hook call per physics step


def test_soil_and_load_are_stored_with_the_trial():
    (a,) = SYSTEM.plan(methods=["analytic"], instances=["dry_sand/W100/s0.2"])
    (b,) = SYSTEM.plan(methods=["analytic"], instances=["lunar_regolith/W100/s0.2"])
    assert a.config["soil"]["name"] == "dry_sand" and a.config["soil"]["phi_deg"] == 28.0
    assert a.key != b.key


@pytest.mark.parametrize("iid, needle", [
    ("mars_soft/W100/s1.5", "outside the documented range"),
    ("clay/W100/s0.2", "valid: dry_sand, lunar_regolith, mars_soft, custom"),
    ("mars_soft/W10/s0.2", "must exceed the wheel's weight"),
    ("mars_soft-100-0.2", "must look like"),
])
def test_bad_instances_name_the_value(iid, needle):
    with pytest.raises(ValueError, match=needle):
        SYSTEM.plan(methods=["analytic"], instances=[iid])


@pytest.mark.parametrize("setting, needle", [
    ("custom_soil.phi_deg=95", "phi_deg"),
    ("custom_soil.k_phi=0", "k_phi"),
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
