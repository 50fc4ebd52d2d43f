"""The contracts the house pass introduced: which pairs apply, the mode machine, shared stop
rules, instances registered where they are built and time limits resolved at planning."""

from __future__ import annotations

import pytest

from terrabench.benchmark.runner import FALLBACK_WALL_BUDGET_S, default_wall_budget, sim_timeout
from terrabench.catalog import populate, system
from terrabench.describe import instances_of, methods_for
from terrabench.sim.checks import DONE, HALT, StopRequest, past_goal, requested_stop
from terrabench.systems.base import ModeMachine

SYSTEMS = populate().ids("system")
assert SYSTEMS, "no system registered"


@pytest.mark.parametrize("sid", SYSTEMS)
def test_every_group_has_methods_that_apply_and_plans_only_those(sid):
    sysobj = system(sid)
    for group in sysobj.groups:
        valid = methods_for(sysobj, group)
        assert valid, f"{sid}: no method applies to group {group!r}"
        ids = set(instances_of(sysobj, group))
        for spec in sysobj.plan(methods=valid, group=group, seeds=1):
            assert spec.instance in ids
            assert sysobj.applies(spec.method, spec.instance), (sid, spec.method, spec.instance)


def test_a_request_in_which_nothing_applies_names_the_methods_that_do():
    sysobj = system("srwmr")
    with pytest.raises(ValueError, match="rcm applies to t2-wall; methods that apply there: wcm"):
        sysobj.plan(methods=["rcm"], instances=["t2-wall"])
    # a request mixing both keeps the pairs that apply, no error
    specs = sysobj.plan(methods=["wrm", "wcm"], instances=["t1-loose", "t2-wall"])
    assert sorted((s.method, s.instance) for s in specs) == [("wcm", "t2-wall"), ("wrm", "t1-loose")]


def test_check_trial_refuses_a_lift_mc1_forbids_before_any_simulation():
    with pytest.raises(ValueError, match=r"scene.lift='c1\+c2'"):
        system("srwmr").plan(methods=["swlm"], instances=["t12-lift100"], overrides={"scene.lift": "c1+c2"})
    # t6 does not read scene.lift: its plan is its own
    assert system("srwmr").plan(methods=["swlm"], instances=["t6-bricks"], overrides={"scene.lift": "c1"})


def test_srwmr_time_limit_is_the_instance_s_own_written_into_the_stored_config():
    from terrabench.systems.srwmr.layouts import entry

    sysobj = system("srwmr")
    for inst, method in (("t1-loose", "wrm"), ("t14-obstacle", "wrm"), ("t14-obstacle", "swlm"),
                         ("slope-10-loose", "rcm")):
        spec = sysobj.plan(methods=[method], instances=[inst])[0]
        assert spec.config["protocol"]["timeout"] == entry(inst, method).timeout > 0
        assert sim_timeout(spec) == entry(inst, method).timeout
        assert default_wall_budget(spec) < FALLBACK_WALL_BUDGET_S  # the hang budget follows the limit
    # a user's limit wins
    spec = sysobj.plan(methods=["wrm"], instances=["t1-loose"], overrides={"protocol.timeout": 12.0})[0]
    assert spec.config["protocol"]["timeout"] == 12.0
    with pytest.raises(ValueError, match="protocol.timeout"):
        sysobj.plan(methods=["wrm"], instances=["t1-loose"], overrides={"protocol.timeout": 0.0})


def test_an_instance_registered_twice_for_a_method_is_refused():
    from terrabench.systems.srwmr.layouts import REGISTRY as ROVER
    from terrabench.systems.srwmr.layouts import instance

    with pytest.raises(ValueError, match="already has a layout for wrm"):
        instance("t1-loose", group="tasks", methods=("wrm",), timeout=1.0)(lambda b: None)
    with pytest.raises(ValueError, match="is in group 'tasks', not 'slopes'"):
        instance("t2-wall", group="slopes", methods=("wrm",), timeout=1.0)(lambda b: None)
    assert [e.methods for e in ROVER["t1-loose"]] == [("wrm",)]
    assert [e.methods for e in ROVER["t2-wall"]] == [("wcm",)]


def test_mode_machine_records_every_change_and_only_changes():
    m = ModeMachine(0, {0: "walk", 1: "climb"})
    assert not m.go(1.0, 0, "already walking")
    assert m.go(2.0, 1, "up-step")
    m.note(2.5, "LF.support", "LF.transfer", "its turn")
    assert m.state == 1 and m.name() == "climb"
    assert m.info() == {"events": [[2.0, "walk", "climb", "up-step"], [2.5, "LF.support", "LF.transfer", "its turn"]]}


def test_shared_stop_rules():
    assert past_goal(1.0, None) is None
    assert past_goal(0.99, 1.0) is None
    assert past_goal(1.0, 1.0)[0] == "success"
    assert requested_stop(None, 0.0, 1.0, 0.05) is None
    assert requested_stop(StopRequest(HALT, "health halt: body slip 0.97 >= 0.96"), 5.0, 1.0, 0.05) == \
        ("stuck", "health halt: body slip 0.97 >= 0.96")
    assert requested_stop(StopRequest(DONE, "plan complete"), 0.96, 1.0, 0.05) == ("success", "plan complete")
    status, why = requested_stop(StopRequest(DONE, "plan complete"), 0.5, 1.0, 0.05)
    assert status == "stuck" and "short of the goal" in why
    assert requested_stop(StopRequest(DONE, "plan complete"), -3.0, None, 0.05)[0] == "success"
    with pytest.raises(ValueError, match="kind 'stop'"):
        StopRequest("stop", "x")
