"""OCTOPUS climbs (issue 21): terrace by terrace, the riser stall, the block ride-over, CCM's abort."""

import math

import numpy as np
import pytest

from terrabench.benchmark.trial import TrialSpec
from terrabench.systems.octopus.ccm import tip_back_angle
from terrabench.systems.octopus.robot import RobotConfig
from terrabench.systems.octopus.scenarios import SYSTEM


def _run(method: str, instance: str, seed: int = 0, **overrides):
    spec = [s for s in SYSTEM.plan(methods=[method], instances=[instance], seeds=seed + 1, overrides=overrides)
            if s.seed == seed][0]
    return SYSTEM.run_trial(spec)


def _events(r) -> list[tuple[float, str, str, str]]:
    """The stored transitions as (t, src, dst, reason)."""
    return [tuple(e) for e in r.info["events"]]


def _mode_events(r, dst: str) -> list[tuple[float, str, str, str]]:
    return [e for e in _events(r) if e[2] == dst]


def test_tip_back_angle_puts_the_cog_over_the_pivot():
    """At the returned pitch the COG is over the centre of the lowest rear pulley (static tip-back);
    rear flippers pushed down move the pivot back and down, so the robot tips back earlier than on
    its track pulley, and later with the flippers flat."""
    rc, zc = RobotConfig(), 0.07
    for q in (-0.9, -0.5, 0.0):
        p = tip_back_angle(q, 0.9, rc, zc)
        L, px = rc.flipper_len, rc.pulley_x
        cands = [(-px - L * math.cos(q), L * math.sin(q), rc.flipper_tip_r), (-px, 0.0, rc.pulley_r)]
        low = min(cands, key=lambda c: c[0] * math.sin(0.9) + c[1] * math.cos(0.9) - c[2])
        cp, sp = math.cos(p), math.sin(p)
        assert 0.0 * cp - zc * sp == pytest.approx(low[0] * cp - low[1] * sp, abs=1e-9)
    assert tip_back_angle(-0.9, 0.9, rc, zc) < tip_back_angle(0.0, 0.9, rc, zc)
    assert 0.85 < tip_back_angle(-0.9, 0.9, rc, zc) < 1.0   # the fall measured on step-400 begins ~0.95 rad


def test_ccm_abort_is_reached_before_the_turn_over():
    """The abort fires at the tip-back angle (a physical condition, not the 1.2 rad stop), and the
    paper's outcome remains: CCM turns over on the 400 mm step."""
    r = _run("ccm", "step-400")
    assert r.status == "turned_over"
    (ab,) = _mode_events(r, "abort")
    assert "tip-back" in ab[3]
    # the pitch at the abort is below the turned-over threshold, and the turn-over follows it
    ts = r.timeseries
    i = int(np.searchsorted(ts["t"], ab[0]))
    assert 0.8 < ts["pitch"][i] < 1.2 and ts["t"][-1] > ab[0]


def test_clm_climbs_a_low_riser_where_the_flipper_rule_stalls():
    """150 mm: the edge presses near the flipper pivot and the torque rule stalls below its limit
    (this trial was `stuck` at the riser); a steep front flipper that stopped rising starts the climb."""
    r = _run("clm", "sweep-h150")
    assert r.status == "success"
    c = [e for e in _mode_events(r, "climb") if e[1] == "walk"]   # started from walking (not resumed)
    assert len(c) == 1 and "steep" in c[0][3]


def test_clm_climbs_the_terraces_one_by_one():
    """terrace2-front: one climb per terrace, H_EST re-estimated each time from the four tips; the
    first ends on the lower terrace (0.2 m), the robot is on the 0.4 m top at the end."""
    r = _run("clm", "terrace2-front")
    assert r.status == "success"
    climbs = [e for e in _mode_events(r, "climb") if e[1] == "walk"]   # fresh climbs, not resumed ones
    h = [float(e[3].split("H_EST = ")[1].split(" m")[0]) for e in climbs]
    assert len(climbs) >= 2 and h[0] == pytest.approx(0.2, abs=0.03) and max(h[1:]) > 0.05
    ts = r.timeseries
    after_first = ts["t"] > _mode_events(r, "walk")[1][0]   # walking again after the first release
    z_mid = ts["z"][after_first][0]
    assert 0.25 < z_mid < 0.4     # on the lower terrace: chassis origin ~0.2 + pulley radius above the floor


@pytest.mark.slow
def test_clm_climbs_the_terraces_from_the_side():
    assert _run("clm", "terrace2-side").status == "success"


def test_block_gap_is_from_the_outermost_contact_surface():
    """The paper's 10 mm: from the flipper pulley capsule's end (pulley_r beyond its side face)."""
    cfg = SYSTEM.resolve_config({})
    task = SYSTEM.make_task(TrialSpec("octopus", "x", "clm", "block-500", 0, {}), cfg)
    r = cfg.robot
    (box,) = task.layout.boxes
    near = abs(box.center[1]) - box.half[1]          # the block's face toward the robot (|y|)
    outer = r.flipper_y + r.flipper_w / 2 + r.pulley_r
    assert near - outer == pytest.approx(cfg.scene.block_gap, abs=1e-9)


@pytest.mark.slow
def test_clm_rides_over_the_block():
    """block-500: the elbow torque detects the collision, the RF arm lands on the block top and
    later comes down past it, and the robot passes."""
    r = _run("clm", "block-500")
    assert r.status == "success"
    ev = _events(r)
    assert any(e[1] == "RF.support" and "collision: elbow torque" in e[3] for e in ev)
    rf_landed = [e[3] for e in ev if e[1] == "RF.transfer" and e[2] == "RF.support"]
    i = rf_landed.index("landed: on-top")
    assert "landed: reached" in rf_landed[i:]


@pytest.mark.slow
def test_clm_does_not_walk_itself_over_a_riser_beyond_its_reach():
    """550 mm (beyond the arms): without the walk's pitch guard CLM turned over here (77.8 s)."""
    r = _run("clm", "sweep-h550")
    assert r.status != "turned_over" and abs(r.metrics["max_pitch"]) < 1.0


def test_clm_nose_climb_pitches_up_on_loaded_crawlers():
    """The opt-in climb of the paper's Fig. 9 (``clm.nose_climb``): on step-400 the front booms lift
    the nose toward ``climb_pitch`` while the rear crawlers stay on the ground, so the crawlers keep
    a far larger share of the load through the climb than in the level four-arm hoist (the default,
    whose every arm carries the robot at once: share 0 measured), and the robot still gets on top."""
    hoist = _run("clm", "step-400")
    nose = _run("clm", "step-400", **{"clm.nose_climb": True})
    assert nose.status == "success" and hoist.status == "success"
    assert any("front pulley" in e[3] and "over the top" in e[3] for e in _events(nose))
    assert 0.45 < nose.metrics["max_pitch_rad"] < 0.8 and hoist.metrics["max_pitch_rad"] < 0.35
    assert nose.metrics["crawler_load_share_min"] > 0.3 > hoist.metrics["crawler_load_share_min"]
