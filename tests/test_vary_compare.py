"""`terrabench run --vary` (every value of a setting, one variant each) and `terrabench compare`
(stored variants side by side): the planning contract, bad input, and a tiny run read back."""

import csv
import json

import pytest
from typer.testing import CliRunner

from terrabench.benchmark.plan import plan_variations
from terrabench.catalog import system as get_system
from terrabench.cli import app
from terrabench.config import parse_variations

runner = CliRunner()


def invoke(*args):
    r = runner.invoke(app, list(args))
    r.text = " ".join(r.output.split())
    return r


def test_variations_parse_commas_or_a_list_and_keep_list_values_whole():
    assert parse_variations(["chain.k_pitch=10,20"]) == {"chain.k_pitch": [10, 20]}
    assert parse_variations(["chain.k_pitch=[10, 20]"]) == {"chain.k_pitch": [10, 20]}
    assert parse_variations(["protocol.target_xy=[[9, -9], [8, -8]]"]) == {"protocol.target_xy": [[9, -9], [8, -8]]}


@pytest.mark.parametrize("items, needle", [
    (["chain.k_pitch=10"], "needs at least two"),
    (["chain.k_pitch=10,10"], "lists the value 10 twice"),
    (["chain.k_pitch=10,20", "chain.k_pitch=30,40"], "given twice"),
    (["chain.k_pitch"], "expected KEY=V1,V2"),
    (["chain.k_pitch=[10, 20"], "does not parse"),
])
def test_bad_variations_are_one_line_naming_them(items, needle):
    with pytest.raises(ValueError, match=needle):
        parse_variations(items)


def test_every_combination_is_planned_once_and_every_value_checked_before_running():
    mrs = get_system("mrs-cwc")
    specs = plan_variations(mrs, vary={"chain.k_pitch": [10.0, 20.0], "chain.k_roll": [30.0, 40.0]},
                            instances=["A-01"], methods=["cwc-tdt"], seeds=2)
    assert len(specs) == 8 and len({s.key for s in specs}) == 8
    assert [s.seed for s in specs] == [0, 0, 0, 0, 1, 1, 1, 1]  # seed-major: an interrupted run has every variant
    got = {(s.config["chain"]["k_pitch"], s.config["chain"]["k_roll"]) for s in specs}
    assert got == {(10.0, 30.0), (10.0, 40.0), (20.0, 30.0), (20.0, 40.0)}
    with pytest.raises(ValueError, match=r"with chain.k_pitch=-1.*k_pitch"):
        plan_variations(mrs, vary={"chain.k_pitch": [10.0, -1.0]}, instances=["A-01"], methods=["cwc-tdt"])
    with pytest.raises(ValueError, match="both set .* and varied"):
        plan_variations(mrs, vary={"chain.k_pitch": [10.0, 20.0]}, overrides={"chain.k_pitch": 5.0},
                        instances=["A-01"], methods=["cwc-tdt"])


def test_a_method_that_does_not_read_the_varied_setting_is_planned_once():
    mrs = get_system("mrs-cwc")  # its trials store only the sections their method reads
    specs = plan_variations(mrs, vary={"follow.speed_gain": [4.0, 5.0]}, instances=["A-01"],
                               methods=["cwc-tdt", "d-tdt"])
    assert sorted(s.method for s in specs) == ["cwc-tdt", "d-tdt", "d-tdt"]


def test_a_varied_run_stores_each_variant_and_compare_puts_them_side_by_side(tmp_path):
    store = str(tmp_path / "s.duckdb")
    r = invoke("run", "mrs-cwc", "--terrains", "A-01", "--timeout", "1", "--workers", "1", "--store", store,
               "--vary", "chain.k_pitch=20,5,15,10", "--quiet")
    assert r.exit_code == 0, r.output
    assert "4 trials requested" in r.text and "variants side by side" in r.text
    assert "cwc-tdt A-01 chain.k_pitch=5.0 seed 0" in r.text  # each trial's line names its value
    out = tmp_path / "cmp" / "k.csv"
    png = tmp_path / "cmp" / "k.png"
    r = invoke("compare", "mrs-cwc", "--store", store, "--metrics", "sim_time,d_min", "--out", str(out),
               "--plot", str(png))
    assert r.exit_code == 0, r.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.DictReader(open(out)))
    # in the values' order (as numbers: 5 before 10; the default 15 in its place), not as given nor by hash
    assert [x["variant"] for x in rows] == [f"cwc-tdt (chain.k_pitch={k})" for k in (5.0, 10.0, 15.0, 20.0)]
    assert [json.loads(x["settings"]).get("chain.k_pitch") for x in rows] == [5.0, 10.0, None, 20.0]
    assert all(x["n"] == "1" and float(x["sim_time_median"]) == pytest.approx(1.0, abs=0.05) for x in rows)
    # the springs differ, so the trials do: not one trial read twice
    assert len({x["d_min_median"] for x in rows}) == 4


@pytest.mark.parametrize("args, needle", [
    (["--metrics", "nope"], "no stored trial has the metric(s) 'nope'; valid:"),
    (["--methods", "magic"], "unknown mrs-cwc method(s) 'magic'"),
    (["--group", "Q"], "unknown mrs-cwc group 'Q'"),
    (["--terrains", "B-01"], "no mrs-cwc trials in"),
    (["--terrains", "Z-99"], "unknown terrain id"),
    (["--terrains", "A-01", "--group", "A"], "give either instances (--terrains) or --group, not both"),
    (["--out", "x.txt"], "unknown suffix"),
    (["--plot", "x.pdf"], "unknown suffix"),
])
def test_compare_refuses_bad_input_in_one_line(args, needle, tmp_path):
    store = str(tmp_path / "s.duckdb")
    assert invoke("run", "mrs-cwc", "--terrains", "A-01", "--timeout", "0.5", "--workers", "1", "--store", store,
                  "--quiet").exit_code == 0
    r = invoke("compare", "mrs-cwc", "--store", store, *args)
    assert r.exit_code == 2, r.output
    assert needle in r.text and "Traceback" not in r.output


def test_compare_without_a_store_says_how_to_make_one(tmp_path):
    r = invoke("compare", "mrs-cwc", "--store", str(tmp_path / "none.duckdb"))
    assert r.exit_code == 2 and "does not exist" in r.text


def test_compare_shows_a_few_metrics_of_a_system_without_headline_ones(tmp_path):
    """beams names no headline metrics: the terminal gets the first few and says how many more
    (the CSV has every one), instead of a table too wide to read."""
    from terrabench.report.compare import SHOWN_DEFAULT as COMPARE_COLUMNS

    store = str(tmp_path / "b.duckdb")
    r = invoke("run", "beams", "--group", "traversal", "--methods", "avoid", "--vary", "robot.mass=0.2,0.25",
               "--store", store, "--quiet", "--workers", "1")
    assert r.exit_code == 0, r.output
    out = tmp_path / "b.csv"
    r = invoke("compare", "beams", "--store", store, "--out", str(out))
    assert r.exit_code == 0, r.output
    n_all = (len(next(csv.reader(open(out)))) - 7) // 3
    assert n_all > COMPARE_COLUMNS and f"{n_all - COMPARE_COLUMNS} more metrics" in r.text


def test_the_plot_puts_methods_with_the_same_settings_on_one_tick(tmp_path):
    """Two methods swept over the same values share the x ticks (one per setting), each its own
    series, instead of following one another along x."""
    from terrabench.report.compare import Line, _short, plot

    lines = [Line("t", m, f"{m} (k={v})", {"k": v}, 1, {"success": 1}, {"x": (v, v, v)})
             for m in ("a", "b") for v in (1.0, 2.0)]
    assert len({_short(ln.label) for ln in lines}) == 2
    out = tmp_path / "p.png"
    plot(lines, ["x"], out)
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_varying_a_setting_no_planned_method_reads_is_refused():
    """cwc-tdt stores no `follow` section: varying follow.speed_gain would run one trial twice."""
    with pytest.raises(ValueError, match="--vary follow.speed_gain: no planned trial reads it"):
        plan_variations(get_system("mrs-cwc"), vary={"follow.speed_gain": [4.0, 5.0]}, instances=["A-01"],
                        methods=["cwc-tdt"])
