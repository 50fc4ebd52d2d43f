"""Bad input on the command line ends with one line naming the value and what is valid, exit 2,
before any simulation and with the store unchanged; the discovery commands show what is valid."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from terrabench import catalog
from terrabench.benchmark.trial import STATUSES
from terrabench.cli import app
from terrabench.config import fields_info

SYSTEMS = catalog.populate().ids("system")
ENV = {"COLUMNS": "400", "NO_COLOR": "1"}


def invoke(*args, env=None):
    return CliRunner().invoke(app, list(args), env={**ENV, **(env or {})})


def one_error_line(res, *needles):
    """exit 2, exactly one non-empty output line starting 'error:', naming every needle."""
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:"), res.output
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


@pytest.mark.parametrize("sid", SYSTEMS)
def test_config_lists_every_set_key_with_its_range(sid):
    res = invoke("config", sid)
    assert res.exit_code == 0, res.output
    for info in fields_info(catalog.system(sid).base_config()):
        assert info.key in res.output, (sid, info.key)


@pytest.mark.parametrize("sid", SYSTEMS)
def test_list_system_shows_methods_groups_sizes_and_ids(sid):
    sysobj = catalog.system(sid)
    res = invoke("list", sid)
    assert res.exit_code == 0, res.output
    for m in sysobj.methods():
        assert m in res.output
    for g in sysobj.groups:
        assert g in res.output
    assert "instance ids" in res.output


def test_list_statuses_explains_every_status():
    res = invoke("list", "--statuses")
    assert res.exit_code == 0, res.output
    for s in STATUSES:
        assert s in res.output
    assert "protocol.turn_over" in res.output and "protocol.fall_z" in res.output  # the systems' own notes


def test_list_unknown_system_is_one_line():
    one_error_line(invoke("list", "nope"), "'nope'", "mrs-cwc")


@pytest.mark.parametrize("setting", ["chain.n_units=0", "chain.body_mass=0", "chain.wheel_radius=-0.05",
                                     "chain.wheel_friction=-1", "physics.iterations=-1",
                                     "chain.body_inertia_per_kg=[1,2]", "stiffness.ema=2"])
def test_run_with_a_meaningless_config_value_stores_nothing(tmp_path, setting):
    store = tmp_path / "r.duckdb"
    key, _, value = setting.partition("=")
    res = invoke("run", "mrs-cwc", "--terrains", "A-01", "--methods", "cwc-tdt", "--set", setting,
                 "--store", str(store))
    one_error_line(res, key, value.strip("[]").split(",")[0])
    assert not store.exists()


# ----------------------------------------------------------------------------- output paths
#: the arguments each command with an output path needs besides it (a new command with a path
#: option must be added here: the test below checks the list is complete)
PATH_COMMANDS = {
    ("report",): ["mrs-cwc"],
    ("compare",): ["mrs-cwc"],
    ("render",): ["mrs-cwc", "--terrain", "A-01", "--timeout", "0.1"],
    ("terrain", "show"): ["B-07"],
    ("terrain", "generate"): ["--n", "1"],
}


def _commands_with_out():
    import typer.main

    root = typer.main.get_command(app)
    found = set()

    def walk(cmd, path):
        for name, sub in getattr(cmd, "commands", {}).items():
            walk(sub, path + (name,))
        if any("--out" in getattr(p, "opts", []) for p in getattr(cmd, "params", [])):
            found.add(path)
    walk(root, ())
    return found


def test_every_out_option_is_listed():
    assert _commands_with_out() == set(PATH_COMMANDS)


@pytest.mark.parametrize("command", sorted(PATH_COMMANDS))
@pytest.mark.parametrize("where", ["unwritable", "under-a-file"])
def test_every_out_path_is_checked_before_any_work(tmp_path, command, where):
    afile = tmp_path / "afile"
    afile.write_text("x")
    csv_out = command in (("terrain", "generate"), ("compare",))
    name = "x.mp4" if command == ("render",) else "x.csv" if csv_out else "x.png"
    bad = f"/proc/terrabench-no/{name}" if where == "unwritable" else str(afile / name)
    store = tmp_path / "r.duckdb"
    extra = ["--store", str(store)] if command in (("report",), ("terrain", "show"), ("compare",)) else []
    res = invoke(*command, *PATH_COMMANDS[command], *extra, "--out", bad)
    one_error_line(res, repr(bad))
    assert not store.exists()


@pytest.mark.parametrize("where", ["a-folder", "under-a-file", "unwritable"])
def test_run_store_path_is_checked_before_planning(tmp_path, where):
    afile = tmp_path / "afile"
    afile.write_text("x")
    bad = {"a-folder": str(tmp_path), "under-a-file": str(afile / "r.duckdb"),
           "unwritable": "/proc/terrabench-no/r.duckdb"}[where]
    one_error_line(invoke("run", "mrs-cwc", "--terrains", "A-01", "--store", bad), "--store", repr(bad))
    assert afile.read_text() == "x"


def test_report_out_an_existing_file(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    one_error_line(invoke("report", "mrs-cwc", "--out", str(afile)), "existing file")
    assert afile.read_text() == "x"


@pytest.mark.parametrize("sid", SYSTEMS)
def test_report_on_a_store_without_the_systems_rows(tmp_path, sid):
    from terrabench.benchmark.store import ResultsStore

    store = tmp_path / "empty.duckdb"
    ResultsStore(store).close()
    one_error_line(invoke("report", sid, "--store", str(store), "--out", str(tmp_path / "rep")), f"no {sid} trials")
    assert not (tmp_path / "rep").exists()


def test_a_method_that_does_not_apply_to_the_group_names_those_that_do(tmp_path):
    store = tmp_path / "r.duckdb"
    res = invoke("run", "beams", "--methods", "interact", "--group", "estimation", "--store", str(store))
    line = one_error_line(res,
                          "'interact'", "'estimation'", "estimate-4")
    assert "estimate-2" in line
    assert not store.exists()


def test_render_refusals_come_before_any_episode(tmp_path):
    out = str(tmp_path / "x.png")
    one_error_line(invoke("render", "mrs-cwc", "--terrain", "A-01", "--seed", "-1", "--out", out), "--seed", "-1")
    one_error_line(invoke("render", "beams", "--terrain", "stiff", "--out", out), "'beams'", "episode loop")
    one_error_line(invoke("render", "mrs-cwc", "--terrain", "A-01", "--out", str(tmp_path / "x.avi")), "'.avi'", ".mp4")
    one_error_line(invoke("render", "mrs-cwc", "--terrain", "A-01", "--width", "641", "--height", "481", "--out",
                          str(tmp_path / "x.mp4")), "641x481", "even", "642x482")
    assert not (tmp_path / "x.mp4").exists()
    one_error_line(invoke("render", "mrs-cwc", "--terrain", "A-01", "--out", out, env={"MUJOCO_GL": "nope"}),
                   "MUJOCO_GL", "'nope'", "egl")
    assert not (tmp_path / "x.png").exists()


def test_an_impossible_frame_size_is_one_line_before_the_episode(tmp_path):
    from terrabench.report.render import GLUnavailable, check_frame_fits

    try:
        check_frame_fits(64, 48)
    except GLUnavailable as exc:
        pytest.skip(str(exc))
    res = invoke("render", "mrs-cwc", "--terrain", "A-01", "--width", "100000", "--out", str(tmp_path / "w.png"))
    one_error_line(res, "100000x480")  # one line: no progress bar was started


def test_an_impossible_frame_size_is_one_line():
    import mujoco

    from terrabench.report.render import GLUnavailable, SceneRenderer

    model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom size='1' type='sphere'/></worldbody></mujoco>")
    try:
        with pytest.raises(ValueError, match="100000x480 frame") as err:
            SceneRenderer(model, 100000, 480)
    except GLUnavailable as exc:  # no headless GL on this machine: nothing to check
        pytest.skip(str(exc))
    assert "\n" not in str(err.value)


def test_ray_backend_without_ray_installed_is_checked_before_the_store(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "ray" else real(name, *a))
    store = tmp_path / "r.duckdb"
    line = one_error_line(invoke("run", "mrs-cwc", "--terrains", "A-01", "--backend", "ray", "--store", str(store)),
                          "pip install 'terrabench[ray]'")
    assert "[ray]" in line
    assert not store.exists()


def _main(monkeypatch, capsys, *args, env=None):
    """The console script itself (typer's parse errors are formatted there, not in the app)."""
    import sys

    from terrabench import cli

    monkeypatch.setattr(sys, "argv", ["terrabench", *args])
    for k, v in (env or {}).items():
        monkeypatch.setenv(k, v)
    with pytest.raises(SystemExit) as ex:
        cli.main()
    cap = capsys.readouterr()
    return ex.value.code, cap.out + cap.err


@pytest.mark.parametrize("args, needles", [
    (["run", "mrs-cwc", "--seeds", "abc"], ["--seeds 'abc'", "integer"]),
    (["run", "mrs-cwc", "--seeds=1.5"], ["--seeds '1.5'"]),
    (["render", "mrs-cwc", "--terrain", "A-01", "--width", "big"], ["--width 'big'"]),
    (["perf", "mrs-cwc", "--seconds", "x"], ["--seconds 'x'", "number"]),
])
def test_parse_errors_show_the_value(monkeypatch, capsys, args, needles):
    code, text = _main(monkeypatch, capsys, *args)
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert code == 2 and len(lines) == 1, text
    for n in needles:
        assert n in lines[0]


def test_a_bad_mujoco_gl_is_one_line_for_every_command(monkeypatch, capsys):
    code, text = _main(monkeypatch, capsys, "list", env={"MUJOCO_GL": "bogus"})
    assert code == 2 and "MUJOCO_GL='bogus'" in text and len(text.strip().splitlines()) == 1


@pytest.mark.parametrize("sid", SYSTEMS)
def test_methods_all_means_every_method_for_every_system(sid):
    """`--methods all` (what `run --help` promises) plans trials for every system."""
    sysobj = catalog.system(sid)
    specs = sysobj.plan(methods=["all"], seeds=1)
    assert specs
    with pytest.raises(ValueError, match="nope"):
        sysobj.plan(methods=["nope"], seeds=1)


#: bad inputs found beyond the issue's examples (one line naming the value, exit 2, no store each)
BAD_INPUTS = [
    ("run mrs-cwc --terrains A-01 --set chain.spacing=-0.3", "'chain.spacing' = -0.3"),
    ("run mrs-cwc --terrains A-01 --set physics.timestep=1e-9x", "'1e-9x'"),
    ("run mrs-cwc --terrains A-01 --set physics.integrator=verlet", "'verlet'"),
    ("run mrs-cwc --terrains A-01 --set chain.drive_solimp=[0.9,0.9]", "has 2 entries"),
    ("run mrs-cwc --terrains A-01 --set protocol.start_xy=[0]", "has 1 entries"),
    ("run mrs-cwc --terrains A-01 --set protocol.control_period=0.0123", "whole number of physics steps"),
    ("run mrs-cwc --terrains A-01 --set stiffness.window=0", "'stiffness.window' = 0"),
    ("run mrs-cwc --terrains A-01 --set head_following.delay_steps=0", "'head_following.delay_steps' = 0"),
    ("run mrs-cwc --terrains A-01 --set planner.max_slope_deg=95", "(0, 90]"),
    ("run mrs-cwc --terrains A-01 --set chain.k_pitch=true", "'chain.k_pitch'"),
    ("run mrs-cwc --terrains A-01 --set waypoint_source=magic", "'magic'"),
    ("run mrs-cwc --terrains A-01 --timeout nan", "nan"),
    ("run octopus --terrains step-400 --set robot.chassis_mass=0", "'robot.chassis_mass' = 0.0"),
    ("run octopus --terrains step-400 --set scene.friction=-0.1", "'scene.friction' = -0.1"),
    ("run octopus --terrains step-400 --set protocol.turn_over=4", "(0, pi]"),
    ("run octopus --terrains step-400 --set clm.settle_ticks=0", "'clm.settle_ticks' = 0"),
    ("run octopus --terrains step-400 --set ccm.retries=-1", "'ccm.retries' = -1"),
    ("run octopus --terrains step-400 --set robot.flipper_range=[1]", "has 1 entries"),
    ("run soil --terrains mars_soft/W100/s0.2 --set rig.omega=0", "'rig.omega' = 0.0"),
    ("run soil --terrains mars_soft/W100/s0.2 --set rig.timestep=0", "'rig.timestep' = 0.0"),
    ("run soil --terrains mars_soft/W100/s0.2 --set custom_soil.phi_deg=95", "(0, 90)"),
    ("run soil --terrains mars_soft/W100/s0.2 --set custom_soil.a1=0.9", "0 <= a0 + a1 <= 1"),
    ("run beams --group traversal --set robot.mass=0", "'robot.mass' = 0.0"),
    ("run beams --group traversal --set sensing.sigma=-0.1", "'sensing.sigma' = -0.1"),
    ("run beams --group traversal --set estimator.n_unknowns=5", "valid: 4, 3, 2"),
    ("run beams --group traversal --set landscape.x_max=-1", "x_min"),
    ("run beams --group traversal --set physics.damping=[1,2]", "has 2 entries"),
    ("run beams --group traversal --set protocol.roll_deg=120", "[-90, 90]"),
    ("run beams --methods estimate-4 --group traversal", "interact, avoid"),
    ("perf mrs-cwc --set chain.n_units=1", "'chain.n_units' = 1"),
    ("render mrs-cwc --terrain A-01 --set chain.wheel_mass=0", "'chain.wheel_mass' = 0.0"),
]


@pytest.mark.parametrize("command, needle", BAD_INPUTS, ids=[c for c, _ in BAD_INPUTS])
def test_bad_inputs_found_beyond_the_issue(tmp_path, command, needle):
    import shlex

    store = tmp_path / "r.duckdb"
    args = shlex.split(command)
    if args[0] == "run":
        args += ["--store", str(store)]
    one_error_line(invoke(*args), needle)
    assert not store.exists()


@pytest.mark.parametrize("args, needles", [
    (["run", "mrs-cwc", "--quiet=maybe"], ["'--quiet' does not take a value"]),
    (["run"], ["Missing argument 'system'", "terrabench run --help"]),
    (["run", "mrs-cwc", "--bogus"], ["--bogus"]),
])
def test_usage_errors_are_one_line(monkeypatch, capsys, args, needles):
    code, text = _main(monkeypatch, capsys, *args)
    lines = [ln for ln in text.splitlines() if ln.strip()]
    assert code == 2 and len(lines) == 1 and lines[0].startswith("error:"), text
    for n in needles:
        assert n in lines[0]


def test_a_single_unit_chain_is_refused_for_spring_methods_only(tmp_path):
    """chain.n_units = 1 builds a leader alone (MJ and D run it); the spring-linked CWC/CS laws
    read the first yaw joint, so planning them on one unit is an error before any trial."""
    sysobj = catalog.system("mrs-cwc")
    for m in ("mj-tdt", "d-tdt"):
        assert sysobj.plan(methods=[m], instances=["A-01"], overrides={"chain.n_units": 1})
    store = tmp_path / "r.duckdb"
    one_error_line(invoke("run", "mrs-cwc", "--terrains", "A-01", "--methods", "cwc-tdt", "--set", "chain.n_units=1",
                          "--store", str(store)), "'chain.n_units' = 1", "cwc-tdt")
    assert not store.exists()


def test_the_mrs_cwc_report_says_in_words_when_the_protocol_is_not_the_papers():
    from terrabench.report.variants import Variant
    from terrabench.systems.mrs_cwc.report import protocol_note

    default = Variant("cwc-tdt", "cwc-tdt", "MRS-CWC + TDT", {}, "h0", {})
    short = Variant("cwc-tdt@1", "cwc-tdt", "MRS-CWC + TDT", {"protocol.timeout": 300.0}, "h1", {})
    near = Variant("mj-tdt@2", "mj-tdt", "MRS-MJ + TDT", {"protocol.success_threshold": 0.25}, "h2", {})
    assert protocol_note([default]) == ""
    text = protocol_note([default, short, near])
    assert "not comparable" in text and "cwc-tdt@1: protocol.timeout = 300.0 s (paper 1000 s)" in text
    assert "mj-tdt@2: protocol.success_threshold = 0.25 m (paper 0.5 m)" in text
    assert "cwc-tdt:" not in text
