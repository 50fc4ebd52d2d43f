"""The shared report layer: page, tables, pruning, variants, timelines."""

from __future__ import annotations

import csv
import json

import pytest

from terrabench.paths import check_out_dir
from terrabench.report.page import MANIFEST, Page, provenance_html, table_html
from terrabench.report.timeline import segments
from terrabench.report.variants import find_variants, settings_diff, tag_rows


def _row(method, instance, cfg, h, seed=0):
    return {"method": method, "instance": instance, "config": cfg, "config_hash": h, "seed": seed,
            "metrics": {"sim_time": 1.0}, "wall_time": 0.5, "status": "done"}


def test_page_writes_links_and_prunes_what_an_earlier_report_wrote(tmp_path):
    lines = [{"a": 1.23456, "b": float("nan")}, {"a": 2, "b": "x"}]
    page = Page(tmp_path, "T")
    page.table(lines, ["a", "b"], csv_name="t.csv")
    (tmp_path / "old.png").write_text("stale")
    page.keep("old.png")
    index = page.finish()
    text = index.read_text()
    assert "href='t.csv'" in text and "<td>1.2346</td>" in text and "<td></td>" in text
    assert list(csv.reader((tmp_path / "t.csv").open())) == [["a", "b"], ["1.2346", ""], ["2", "x"]]
    assert json.loads((tmp_path / MANIFEST).read_text())["files"] == ["index.html", "old.png", "t.csv"]
    (tmp_path / "mine.txt").write_text("a user's file")
    Page(tmp_path, "T").finish()  # writes neither t.csv nor old.png
    assert not (tmp_path / "t.csv").exists() and not (tmp_path / "old.png").exists()
    assert (tmp_path / "mine.txt").exists()  # never written by a report: never removed


def test_out_dir_that_is_a_file_is_bad_input(tmp_path):
    f = tmp_path / "f"
    f.write_text("")
    with pytest.raises(ValueError, match="is an existing file"):
        check_out_dir(f)
    with pytest.raises(ValueError, match="cannot be created"):
        check_out_dir(f / "sub")


def test_table_highlights_and_escapes():
    html = table_html([{"x": "<b>", "y": 1.0}], ["x", "y"], far=lambda ln, c: c == "y")
    assert "&lt;b&gt;" in html and "<td class=far>1.0</td>" in html


def test_a_set_variant_is_its_own_labelled_line_and_instances_do_not_split_a_method():
    def defaults(method, instance):  # the instance fixes 'case.k'; the default speed is 1
        return {"case": {"k": {"stiff": 0.25, "flimsy": 0.01}[instance]}, "speed": 1.0}

    rows = [_row("m", "stiff", {"case": {"k": 0.25}, "speed": 1.0}, "h1"),
            _row("m", "flimsy", {"case": {"k": 0.01}, "speed": 1.0}, "h2"),
            _row("m", "stiff", {"case": {"k": 0.25}, "speed": 2.0}, "h3"),
            _row("m", "flimsy", {"case": {"k": 0.01}, "speed": 2.0}, "h4"),
            _row("n", "stiff", {"case": {"k": 0.25}, "speed": 1.0}, "h5")]
    vs = find_variants(rows, default_config=defaults, order=["n", "m"], label=str.upper)
    assert [(v.method, v.label, v.hashes) for v in vs] == [
        ("n", "N", ("h5",)), ("m", "M (speed=1.0)", ("h1", "h2")), ("m", "M (speed=2.0)", ("h3", "h4"))]
    assert vs[1].is_default and vs[2].diff == {"speed": 2.0}
    assert vs[0].id == "n" and vs[1].id != vs[2].id and vs[2].id.startswith("m@")
    tagged = tag_rows(rows, vs)
    assert [r["label"] for r in tagged] == ["M (speed=1.0)", "M (speed=1.0)", "M (speed=2.0)", "M (speed=2.0)", "N"]
    assert len(vs[2].rows_of(rows)) == 2


def test_without_defaults_every_config_is_a_variant():
    rows = [_row("m", "a", {"x": 1}, "h1"), _row("m", "a", {"x": 2}, "h2")]
    vs = find_variants(rows)
    assert len(vs) == 2 and len({v.label for v in vs}) == 2


def test_settings_diff_counts_missing_keys():
    assert settings_diff({"a": 1, "s": {"b": 2}}, {"a": 1, "s": {"b": 3}, "c": 0}) == {"c": "<absent>", "s.b": 2}


def test_provenance_lists_each_config_with_its_difference(tmp_path):
    class S:
        path = tmp_path / "s.duckdb"

    rows = [_row("m", "a", {"x": 1}, "h1"), _row("m", "a", {"x": 2}, "h2")]
    html = provenance_html(S(), rows, system_id="toy", default_config=lambda m, i: {"x": 1})
    assert "<details id='cfg-h1'>" in html and "differs from this version&#x27;s defaults in: nothing" in html
    assert "x=2" in html and "toy trials stored: 2" in html


def test_provenance_says_which_code_and_machines_made_the_rows():
    from terrabench.benchmark.worker import code_fingerprint, cpu_model, host_fingerprint
    from terrabench.report.page import made_by

    host = host_fingerprint()
    assert host["code"] == code_fingerprint() and set(cpu_model()) <= {"cpu", "avx512"}
    rows = [{"info": {"host": host}}, {"info": {"host": {"code": "0123456789abcdef", "cpu": "Some CPU",
                                                          "avx512": False, "pinned": False}}}, {"info": {}}]
    line = made_by(rows)
    assert f"made by code {code_fingerprint()} (1), 0123456789abcdef (1), not recorded (1)" in line
    assert f"(this installation: {code_fingerprint()})" in line
    assert "Some CPU, unpinned (1)" in line and "a host not recorded (1)" in line


def test_timeline_segments_cover_the_trial():
    ev = [[1.0, "walk", "climb", "step"], [3.0, "climb", "walk", "done"]]
    assert segments(ev, 5.0) == [("walk", 0.0, 1.0), ("climb", 1.0, 3.0), ("walk", 3.0, 5.0)]
    assert segments([], 2.0, start="idle") == [("idle", 0.0, 2.0)]
    with pytest.raises(ValueError, match="time order"):
        segments([[2.0, "a", "b"], [1.0, "b", "a"]], 3.0)


def test_settings_groups_split_by_settings_not_by_method_or_instance():
    from terrabench.report.variants import settings_groups

    def defaults(method, instance):
        return {"k": {"a": 1, "b": 2}[instance], "speed": 1.0, "reading": "edge"}

    rows = [_row("m", "a", {"k": 1, "speed": 1.0, "reading": "edge"}, "h1"),
            _row("n", "b", {"k": 2, "speed": 1.0, "reading": "centre"}, "h2"),
            _row("m", "b", {"k": 2, "speed": 3.0, "reading": "edge"}, "h3")]
    gs = settings_groups(rows, defaults, ignore=("reading",))
    assert [(g.label, g.slug == "", len(g.rows)) for g in gs] == [("defaults", True, 2), ("speed=3.0", False, 1)]


def test_snapshots_of_a_trial_this_version_cannot_run_are_a_note(tmp_path):
    from terrabench.benchmark.trial import TrialSpec
    from terrabench.systems.mrs_cwc.scenarios import SYSTEM

    spec = SYSTEM.plan(methods=["cwc-tdt"], instances=["A-01"], overrides={"protocol.timeout": 0.5})[0]
    old = TrialSpec(spec.system, spec.scenario, spec.method, spec.instance, 0,
                    {**spec.config, "protocol": {**spec.config["protocol"], "removed_field": 1.0}})
    page = Page(tmp_path, "T")
    assert page.snapshots("s.png", "caption", SYSTEM, old, [0.0]) is False
    text = page.finish().read_text()
    assert "Snapshots skipped: the stored trial cannot be re-run" in text and "removed_field" in text
