"""The mobility map's page: the >= 80 % rule, severities in the robot's own size, the curves'
points and the choice of contrasts, on synthetic stored rows."""

from __future__ import annotations

import math

import pytest

from terrabench.zoo import report
from terrabench.zoo.adapter import split_method


def _row(method: str, instance: str, seed: int, status: str, speed: float = 0.05, e_kg: float = 10.0):
    ok = status == "success"
    return {"method": method, "instance": instance, "seed": seed, "status": status, "wall_time": 1.0,
            "scenario": "zoo", "config": {},
            "metrics": {"success": 1.0 if ok else 0.0, "speed": speed, "energy_per_m": e_kg * 50.0,
                        "energy_per_m_kg": e_kg, "sim_time": 30.0}}


def _starts(method: str, instance: str, n_ok: int, n: int = 5, **kw):
    return [_row(method, instance, s, "success" if s < n_ok else "stuck", **kw) for s in range(n)]


def test_a_severity_counts_as_crossed_only_in_at_least_80_percent_of_its_starts():
    rows = (_starts("octopus.clm", "step-up@0.05", 5) + _starts("octopus.clm", "step-up@0.15", 4)
            + _starts("octopus.clm", "step-up@0.3", 3))
    (line,) = report.map_lines(rows)
    assert line["max_crossed"] == "0.15"  # 4/5 = 80 % counts, 3/5 does not
    assert (line["success"], line["trials"]) == (12, 15)
    assert line["first_failure"] == "stuck at 0.15"


def test_the_crossed_severity_is_also_given_in_the_robots_own_size():
    fp = split_method("octopus.clm")[0].footprint()
    text = report.relative_text("octopus.clm", "step-up", 0.3)
    assert text == f"{0.3 / fp.wheel_radius:.2g} wheel radii, {0.3 / fp.height:.2g} body heights"
    assert report.relative_text("octopus.clm", "rough-mrs", 7.0) == ""  # a family without a scale


def test_points_average_speed_and_energy_over_the_crossed_starts_only():
    rows = [_row("octopus.ccm", "gap@0.3", 0, "success", speed=0.08, e_kg=4.0),
            _row("octopus.ccm", "gap@0.3", 1, "success", speed=0.06, e_kg=6.0),
            _row("octopus.ccm", "gap@0.3", 2, "fell", speed=0.5, e_kg=100.0)]
    (p,) = report.point_lines(rows)
    assert (p["starts"], p["success"]) == (3, 2) and p["share"] == pytest.approx(2 / 3)
    assert p["speed"] == pytest.approx(0.07) and p["energy_per_m_kg"] == pytest.approx(5.0)
    assert p["statuses"] == "fell, success"
    (none,) = report.point_lines([_row("octopus.ccm", "gap@0.6", 0, "fell")])
    assert math.isnan(none["speed"])


def test_a_contrast_needs_two_robots_and_a_loser_that_crosses_something_easier():
    rows = (_starts("octopus.clm", "step-up@0.3", 1, n=1) + _starts("octopus.ccm", "step-up@0.3", 0, n=1)
            + _starts("mrs-cwc.cwc-tdt", "step-up@0.3", 0, n=1) + _starts("mrs-cwc.cwc-tdt", "step-up@0.05", 1, n=1)
            + _starts("mrs-cwc.d-tdt", "step-up@0.3", 0, n=1) + _starts("mrs-cwc.d-tdt", "step-up@0.05", 0, n=1))
    pairs = report.contrasts(report.point_lines(rows))
    # CCM is the same robot as CLM; D-TDT crosses no step at all: only the chain's CWC-TDT is a contrast
    assert [(a["method"], b["method"], a["token"]) for a, b in pairs] == [("octopus.clm", "mrs-cwc.cwc-tdt", "0.3")]


def test_contrasts_keep_the_hardest_severity_per_family_and_the_hardest_families_first():
    rows = []
    for fam, toks in (("step-up", ("0.05", "0.15", "0.3")), ("gap", ("0.1", "0.2"))):
        for t in toks:
            rows += _starts("octopus.clm", f"{fam}@{t}", 1, n=1)
            rows += _starts("mrs-cwc.cwc-tdt", f"{fam}@{t}", 1 if t in ("0.05", "0.1") else 0, n=1)
    pairs = report.contrasts(report.point_lines(rows), n=2)
    assert [f"{a['family']}@{a['token']}" for a, _ in pairs] == ["step-up@0.3", "gap@0.2"]
    assert len(report.contrasts(report.point_lines(rows), n=1)) == 1


def test_the_curves_have_a_panel_in_robot_units_where_the_family_has_a_scale():
    pts = report.point_lines(_starts("octopus.clm", "step-up@0.15", 5) + _starts("mrs-cwc.cwc-tdt", "step-up@0.15", 0))
    fig = report.curve_figure("step-up", pts)
    assert len(fig.axes) == len(report.PANELS) + 1
    assert "wheel radii" in fig.axes[-1].get_xlabel()
    fig2 = report.curve_figure("rough-mrs", report.point_lines(_starts("octopus.clm", "rough-mrs@A", 1, n=1)))
    assert len(fig2.axes) == len(report.PANELS)
