"""The constraint-saturated IK at work (issue 27 piece 5, group ``ik``): the QP changes the nominal
command in most periods of an ``ik`` instance and keeps the constrained ratio at kappa where the
nominal command (its ``-noqp`` twin) exceeds it; the additions leave every other plan untouched."""

import numpy as np
import pytest
from fake_rover import Obs, controller

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.ik import IKLimits, IKState, build_qp
from terrabench.systems.srwmr.ik_cases import CASES, HALT_TOL, IK_INSTANCES, TARGET_CASES, case_of, variant_of
from terrabench.systems.srwmr.layouts import instance_ids, layout
from terrabench.systems.srwmr.modes import Step
from terrabench.systems.srwmr.qp_trace import ROW_OF, predicted, row_norms
from terrabench.systems.srwmr.robot import RobotConfig
from terrabench.systems.srwmr.scenarios import SYSTEM

CFG = RobotConfig()
SC = mc.Scales()
TOL = 1e-6


def test_group_ik_is_registered_with_a_twin_per_case_and_the_other_groups_unchanged():
    assert instance_ids("ik") == list(IK_INSTANCES)
    assert {case_of(i) for i in IK_INSTANCES} == set(CASES)
    assert not set(IK_INSTANCES) & set(instance_ids("tasks") + instance_ids("slopes"))
    assert {i for i in IK_INSTANCES if variant_of(i) == "target"} == {f"{c}-target" for c in TARGET_CASES}
    for i in IK_INSTANCES:
        plan = layout(i, "rclm", CFG).plan
        var = variant_of(i)
        assert all(s.trace and s.qp == (var != "noqp") and s.qp_about_target == (var == "target") for s in plan)
        # the variants differ in the QP switches only
        twin = layout(case_of(i), "rclm", CFG).plan
        assert [s.__class__(**{**s.__dict__, "qp": True, "qp_about_target": False}) for s in plan] == list(twin)
    # every plan of the other groups keeps the defaults: QP on, no trace, halting at kappa
    for i in instance_ids("tasks") + instance_ids("slopes"):
        for m in ("wrm", "wcm", "rclm", "rcm", "swlm", "dwlm"):
            if SYSTEM.applies(m, i):
                assert all(s.qp and not s.trace and not s.qp_about_target and s.halt_tol == 0
                           and s.clearance_r is None and s.hold_s is None for s in layout(i, m, CFG).plan)


def test_a_plan_without_trace_keeps_no_trace_and_its_info_keys():
    c = controller([Step("RCLM", v=0.0, clearance=0.33)])
    for k in range(5):
        c(Obs(0.01 * k))
    assert c.trace is None and "qp_trace" not in c.info()


def test_predicted_ratio_of_a_command_on_a_row_boundary_is_its_kappa():
    kappa = mc.qp_thresholds("RCLM")
    u_prev = np.array([0.01, 0.0, 0.004, 0.0, 0.0])
    G, h, lb, ub = build_qp(CFG, IKState(np.array([0.3, 0.1]), u_prev), kappa, SC, IKLimits(), 0.01)
    norms = row_norms(u_prev, SC, CFG.track / 2)
    rng = np.random.default_rng(3)
    for i in range(16):
        u = rng.normal(0, 0.01, 5)
        g = G[i]
        u = u + (h[i] - g @ u) * g / (g @ g)  # onto row i's boundary
        p = predicted(G, h, u, kappa, norms)
        c = ROW_OF[i]
        assert p[c] >= kappa[mc.CONSTRAINTS[c + 1].ratio] - 1e-9  # the max over the constraint's rows
        one = kappa[mc.CONSTRAINTS[c + 1].ratio] + (G[i] @ u - h[i]) / norms[i]
        assert one == pytest.approx(kappa[mc.CONSTRAINTS[c + 1].ratio], abs=1e-9)


@pytest.mark.parametrize("qp", [True, False])
def test_controller_a_fast_lift_is_held_at_mc6_by_the_qp_and_exceeds_it_without(qp):
    """Standing, a 10 mm/s lift: the nominal closing rate drives the front wheels at ~9.5 mm/s, 1.2x
    MC#6's side-speed floor (8 mm/s; RCLM kappa 0.9); the QP cuts it to kappa in every period."""
    c = controller([Step("RCLM", v=0.0, vz=0.01, clearance=0.40, trace=True, qp=qp)])
    for k in range(50):
        cmd = c(Obs(0.01 * k))
    tr = c.info()["qp_trace"]
    k6 = mc.thresholds("RCLM")[4]
    assert tr["periods"] >= 45 and tr["changed"] >= 0.9 * tr["periods"]
    assert tr["active_rows"]["MC6"] == tr["changed"] and tr["violated_rows"]["MC6"] >= tr["changed"]
    assert tr["max_predicted_nominal"]["MC6"] > 1.25 * k6
    if qp:
        assert tr["max_measured"]["MC6"] <= k6 + TOL and cmd.ratios[4] == pytest.approx(k6, abs=TOL)
        assert c.info()["qp_limited_share"] >= 0.9
    else:
        assert tr["bypassed"] and tr["max_measured"]["MC6"] > 1.25 * k6 and cmd.ratios[4] > 1.25 * k6


def _trial(inst, timeout):
    spec = SYSTEM.plan(methods=["rclm"], instances=[inst], overrides={"protocol.timeout": timeout})[0]
    return SYSTEM.run_trial(spec)


def test_sim_mc6_fast_lift_qp_active_and_ratio_at_kappa_where_the_nominal_exceeds_it():
    """A short run of ik-mc6-fastlift and its twin (4 s of simulated time each)."""
    k6 = mc.thresholds("RCLM")[4]
    r = _trial("ik-mc6-fastlift", 4.0)
    tr = r.info["qp_trace"]
    assert tr["changed"] / tr["periods"] > 0.9 and tr["active_rows"]["MC6"] / tr["periods"] > 0.9
    assert tr["max_measured"]["MC6"] <= k6 + TOL and tr["max_predicted_nominal"]["MC6"] > 1.25 * k6
    assert r.metrics["max_eta_MC6"] <= k6 + TOL
    n = _trial("ik-mc6-fastlift-noqp", 4.0)
    assert n.info["qp_trace"]["max_measured"]["MC6"] > 1.25 * k6 and n.metrics["max_eta_MC6"] > 1.25 * k6


def test_sim_mc5_one_side_lift_qp_holds_mc9_and_mc5_without_a_halt_the_twin_halts():
    """(12 s of simulated time, three trials, ~15 s.) ik-mc5-asym: with the rows about the servo
    targets (-target) the QP holds MC#9 (roll rate) then MC#5 (wheelbase asymmetry) at kappa, no
    halt; the nominal command (-noqp) exceeds MC#9 and the supervisor halts on MC#5; with the rows
    about the measured angles (the IK of every trial) the servo's lag carries MC#5 past kappa and
    the QP turns infeasible (a halt)."""
    kap = mc.thresholds("RCLM")
    r = _trial("ik-mc5-asym-target", 12.0)
    tr = r.info["qp_trace"]
    assert tr["changed"] / tr["periods"] > 0.9
    assert tr["max_measured"]["MC9"] <= kap[7] * 1.01 and tr["max_measured"]["MC5"] <= kap[3] * (1 + HALT_TOL)
    assert tr["active_rows"]["MC5"] > 0.3 * tr["periods"] and not r.info["reminders"]
    n = _trial("ik-mc5-asym-noqp", 12.0)
    assert n.info["qp_trace"]["max_measured"]["MC9"] > 1.5 * kap[7]
    assert n.info["reminders"] and any("MC5" in e[3] for e in n.info["events"])
    m = _trial("ik-mc5-asym", 12.0)
    assert m.info["qp_trace"]["max_measured"]["MC9"] <= kap[7] + TOL
    assert any("IK infeasible" in e[3] for e in m.info["events"])


def test_sim_mc4_on_a_cross_slope_the_qp_holds_the_levelling_at_kappa_the_twin_halts():
    """(30 + 25 s of simulated time, ~9 s.) ik-mc4-cross: on a 10 deg cross slope the rover starts
    on the slope's plane (rolled 10 deg, loads within MC#11 from the first period), lowers to 150
    mm and is commanded to level the chassis by raising its downhill side ~230 mm. MC#4 (left-right
    hinge-height asymmetry) is the row that binds: with the rows about the servo targets the QP
    holds it at kappa without a halt and the chassis keeps most of the slope's roll (50 of ~230 mm
    levelled); the nominal command (-noqp) crosses kappa and the supervisor halts on MC#4."""
    import math

    from terrabench.systems.srwmr.ik_cases import CROSS_DEG

    kap = mc.thresholds("RCLM")
    r = _trial("ik-mc4-cross-target", 30.0)
    ts, tr = r.timeseries, r.info["qp_trace"]
    cross = math.radians(CROSS_DEG)
    assert r.info["cross_deg"] == CROSS_DEG
    assert abs(ts["roll"][0] - cross) < 1e-9 and abs(ts["roll"][5] - cross) < 0.02
    assert np.nanmax(ts["eta_MC11"][ts["t"] < 2.0]) < kap[9]
    assert tr["max_measured"]["MC4"] <= kap[2] * (1 + HALT_TOL) and tr["active_rows"]["MC4"] > 0.2 * tr["periods"]
    assert not r.info["reminders"]
    # the right (downhill) side raised as far as MC#4 lets it: the roll falls by 50 mm over the
    # 1.304 m track at most, nowhere near level
    drop = ts["roll"][5] - ts["roll"][-1]
    assert 0.02 < drop < math.atan(0.06 / CFG.track)
    n = _trial("ik-mc4-cross-noqp", 25.0)
    assert any("MC4" in e[3] for e in n.info["events"] if e[2] == "HALT")


def test_report_section_tables_every_ik_trial_and_draws_one_figure_per_case():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.systems.srwmr.report_qp import add_section, qp_lines

    rows = []
    for inst, qp in (("ik-mc6-fastlift", True), ("ik-mc6-fastlift-noqp", False)):
        c = controller([Step("RCLM", v=0.0, vz=0.01, clearance=0.40, trace=True, qp=qp)])
        for k in range(30):
            c(Obs(0.01 * k))
        rows.append({"instance": inst, "method": "rclm", "seed": 0, "status": "timeout",
                     "metrics": {"sim_time": 0.3}, "info": c.info()})
    rows.append({"instance": "t1-loose", "method": "wrm", "seed": 0, "status": "success", "metrics": {}, "info": {}})

    class Page:
        def __init__(self):
            self.tables, self.figures = [], []

        def h2(self, text):
            pass

        def p(self, text):
            pass

        def table(self, lines, cols, csv_name):
            self.tables.append((csv_name, lines))

        def figure(self, fig, name, caption):
            self.figures.append(name)

    page = Page()
    add_section(page, rows, "", plt)
    (name, lines), = page.tables
    assert name == "qp_ik.csv" and [ln["instance"] for ln in lines] == ["ik-mc6-fastlift", "ik-mc6-fastlift-noqp"]
    assert lines[0]["QP changed %"] > 90 and lines[0]["active MC6 %"] > 90
    assert lines[0]["max eta / kappa (saturated MC)"] == pytest.approx(1.0, abs=1e-6)
    assert lines[1]["max eta / kappa (saturated MC)"] > 1.25
    assert page.figures == ["qp_ik-mc6-fastlift.png"]
    assert qp_lines(rows[2:]) == []
