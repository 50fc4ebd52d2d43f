"""Supervisor (halt / reply / reverse / health), the task's stop rules, sensing and bad input."""

import numpy as np
import pytest
from fake_rover import Obs, controller

from terrabench.sim.checks import HALT
from terrabench.systems.base import Transition
from terrabench.systems.srwmr.modes import Step
from terrabench.systems.srwmr.robot import RobotConfig
from terrabench.systems.srwmr.scenarios import SYSTEM

CFG = RobotConfig()


def test_load_threshold_halts_then_the_reply_ends_the_action():
    c = controller([Step("RCLM", v=0.0, clearance=0.33), Step("RCLM", v=0.0, clearance=0.25)], reply_s=1.0)
    bad = [0.0, 1400.0, 368, 368, 368, 368]  # W_diff 1400 N > 1300 N (MC#10)
    cmd = c(Obs(0.0, load=bad))
    assert c.mode == "HALT" and np.all(cmd.u == 0)
    assert any(e.dst == "HALT" and ("MC10" in e.reason or "MC11" in e.reason) for e in c.events)
    for k in range(1, 101):
        c(Obs(0.01 * k, load=bad if k < 50 else None))
    info = c.info()
    ev = [Transition.from_list(e) for e in info["events"]]
    assert any(e.reason == "operator replied: action ended" for e in ev)
    assert c.k == 1  # the next action of the plan runs


def test_a_plan_whose_step_the_operator_cut_short_is_no_success():
    """The reply to a reminder ends the action and the plan moves on; at the plan's end the step that
    was cut short is named and the trial stops as a halt (``stuck``), not as a completed plan: a
    plan without a goal line (T1, T3, T10, the ik group) would otherwise read ``success``."""
    c = controller([Step("RCLM", v=0.0, clearance=0.33)], reply_s=1.0)
    bad = [0.0, 1400.0, 368, 368, 368, 368]  # W_diff 1400 N > 1300 N (MC#10)
    for k in range(0, 101):
        c(Obs(0.01 * k, load=bad if k < 50 else None))
    assert c.mode == "DONE" and c.stop is not None and c.stop.kind == HALT
    assert "step 1 (RCLM" in c.stop.reason and ("MC10" in c.stop.reason or "MC11" in c.stop.reason)
    # a plan that ends on its own is a completed plan
    d = controller([Step("RCLM", v=0.0, clearance=0.25, hold_s=0.05)])
    for k in range(0, 200):
        d(Obs(0.01 * k))
        if d.stop is not None:
            break
    assert d.stop is not None and d.stop.kind != HALT and not d.abandoned


def test_no_reply_reverses_and_two_reminders_force_a_return():
    c = controller([Step("RCLM", v=0.0, clearance=0.33)], reply_s=None, wait_s=0.5)
    bad = [0.0, 1400.0, 368, 368, 368, 368]
    c(Obs(0.0, load=bad, delta=(0.1, 0.1)))
    c.step_start = (np.zeros(2), 0.0, np.array([0.0, 0.0]), 0.0)
    cmd = None
    for k in range(1, 80):
        cmd = c(Obs(0.01 * k, delta=(0.1, 0.1)))
    assert any(e.dst == "REVERSE" and "no reply" in e.reason for e in c.events)
    assert cmd.u[3] < 0 and cmd.u[4] < 0  # opening back towards the start angles
    c2 = controller([Step("RCLM", v=0.0, clearance=0.33)], reply_s=0.1)
    c2(Obs(0.0, load=bad))
    for k in range(1, 30):
        c2(Obs(0.01 * k, load=bad))
    assert c2.reminders.get("RCLM", 0) >= 1


def test_health_monitor_halts_wrm_at_slip_096():
    c = controller([Step("WRM", v=0.025, dist=5.0)], health_s=2.0, slip_tau=1.0)
    t = 0.0
    for k in range(3000):
        t = 0.01 * k
        cmd = c(Obs(t, v=0.0))
        if cmd.stop:
            break
    assert cmd.stop.kind == HALT and cmd.stop.reason.startswith("health halt")
    assert c.events[-1].dst == "HALT" and "0.96" in c.events[-1].reason
    assert t < 30.0


def test_unknown_mode_in_a_plan():
    with pytest.raises(ValueError, match="valid: WRM, WCM, RCLM, RCM, SWLM, DWLM"):
        controller([Step("LEGS")])
    with pytest.raises(ValueError, match="allowed lifts"):
        controller([Step("SWLM")])  # a legged step needs a lift set (MC#1)


@pytest.mark.parametrize(
    "kw,match",
    [
        ({"instances": ["t99"]}, "unknown srwmr instance"),
        ({"methods": ["walk"], "instances": ["t1-loose"]}, "walk"),
        ({"methods": ["rcm"], "instances": ["t1-loose"]}, "rcm applies to t1-loose; methods that apply there: wrm"),
        ({"instances": ["t1-loose"], "overrides": {"scene.clearance": 0.7}}, r"scene.clearance.*\[0.15, 0.55\]"),
        ({"instances": ["t1-loose"], "overrides": {"soil.preset": "mud"}}, "soil.preset.*very_loose"),
        ({"instances": ["t1-loose"], "overrides": {"robot.wheel_offset": 0.5}}, r"\[0, 0.3\]"),
    ],
)
def test_bad_requests_name_the_value_and_the_choices(kw, match):
    with pytest.raises(ValueError, match=match):
        SYSTEM.plan(**kw)


def test_groups_and_applicable_methods():
    specs = SYSTEM.plan(group="tasks")
    pairs = {(s.instance, s.method) for s in specs}
    assert ("t14-obstacle", "wcm") in pairs and ("t1-loose", "rcm") not in pairs
    assert len(SYSTEM.plan(group="slopes", methods=["wrm", "rcm"])) == 24


def test_short_episode_on_soil_senses_the_loads_and_moves():
    spec = SYSTEM.plan(methods=["wrm"], instances=["t1-loose"], overrides={"protocol.timeout": 4.0})[0]
    r = SYSTEM.run_trial(spec)
    assert r.status == "timeout"
    w = np.array([r.timeseries[f"W_{c}"][-1] for c in ("c1", "c2", "c3", "c4", "c5", "c6")])
    assert w.sum() == pytest.approx(225 * 9.81, rel=0.05)  # the soil carries the rover
    assert r.metrics["progress"] > 0.0
    assert r.info["events"][0][2] == "WRM"
    assert r.info["qp_n"] + r.info["qp_inside"] == r.info["control_steps"]  # one IK step per period
