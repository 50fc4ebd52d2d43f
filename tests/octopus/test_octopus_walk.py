"""OCTOPUS CLM walking on flat ground (ground-truth probe): arm moving holds the footholds, the
crawlers carry the load and set the pace (paper: arm moving, eqs. 22-27; Fig. 14 phase B2)."""

import numpy as np
import pytest

from terrabench.systems.octopus.probe import probe_walk


@pytest.fixture(scope="module")
def walk():
    return probe_walk(25.0)


def test_tips_hold_their_footholds(walk):
    d = walk.all_drifts()
    assert len(d) >= 6                      # every arm supported and was transferred again
    assert np.median(d) < 0.02 and d.max() < 0.03   # the target: < 2 cm per support phase


def test_tracks_carry_the_load(walk):
    assert walk.track_share > 0.6           # tracks + flippers: most of the normal ground load
    assert walk.unloaded_frac < 0.05        # and they are almost never unloaded


def test_walking_speed_follows_the_tracks(walk):
    # while the crawlers run the chassis moves at their speed (little slip); overall it is
    # slower because the crawlers wait for transfers whose footholds left the arm's range
    assert walk.speed_driving == pytest.approx(walk.track_speed, rel=0.1)
    assert 0.2 * walk.track_speed < walk.speed < walk.speed_driving


def test_without_arm_moving_the_tips_roll_along():
    """The control: tips whose joints are not moved with the body (press kept, no foothold
    tracking) roll over the ground about as far as the body moves."""
    p = probe_walk(25.0, {"clm.arm_moving": False})
    assert np.median(p.all_drifts()) > 0.1


@pytest.fixture(scope="module")
def step_walk():
    """CLM's first 18 s on step-400 (the walk up to the riser): the result, its walking rows and
    the number of supporting tips per row (in contact, not the arm in transfer)."""
    from terrabench.systems.octopus.scenarios import SYSTEM

    spec = SYSTEM.plan(methods=["clm"], instances=["step-400"], overrides={"protocol.timeout": 18.0})[0]
    r = SYSTEM.run_trial(spec)
    ts = r.timeseries
    tips, moving = ts["tip_contact"], ts["moving_arm"]
    walk = (ts["mode"] == 0) & (ts["t"] > 1.0)
    supports = np.array([sum(int(b) >> i & 1 and i != int(mv) for i in range(4)) if np.isfinite(mv) else 0
                         for b, mv in zip(tips, moving)])
    return r, walk, supports


def test_the_crawlers_lie_inside_the_tips_polygon_exactly_when_four_arms_support(step_walk):
    """The paper's Fig. 7 property, as stored (``crawlers_in_tips``, ``crawlers_enclosed_share``):
    with four supporting tips around the body the four track pulleys are inside their polygon; with
    three, the pulley at the missing arm's corner lies beyond the triangle's diagonal, so a crawl
    gait with one arm in transfer cannot hold it (docs/octopus.md, "The crawlers inside the tips'
    polygon")."""
    r, walk, supports = step_walk
    depth = r.timeseries["crawlers_in_tips"]
    four, three = walk & (supports == 4), walk & (supports == 3)
    assert four.sum() >= 5 and three.sum() >= 5
    assert (depth[four] > 0.1).all() and (depth[three] < 0.0).all()
    assert np.isnan(depth[walk & (supports < 3)]).all()
    share = r.metrics["crawlers_enclosed_share"]
    assert 0.0 < share < 1.0
    assert r.metrics["walk_three_supports_share"] == pytest.approx(np.mean(supports[walk] >= 3))


def test_three_supporting_tips_widen_the_crawlers_margin(step_walk):
    """Fig. 7's conclusion ("robot in CLM always has bigger stability margin than CCM"): the margin
    of the supporting tips and the crawlers together (``margin_sensed``) against the crawlers' own
    about the same COG (``margin_crawlers``). A hull of more points is never smaller, so the gain
    is >= 0 on every row; with three or more supporting tips placed around the body (the premise)
    it is centimetres on every walking row, because each side of the crawlers' rectangle has a tip
    beyond it (docs/octopus.md, "The crawlers inside the tips' polygon")."""
    r, walk, supports = step_walk
    ts = r.timeseries
    gain = ts["margin_sensed"] - ts["margin_crawlers"]
    ok = np.isfinite(gain)
    assert ok[walk].all() and (gain[ok] >= -1e-12).all()
    assert gain[walk & (supports >= 3)].min() > 0.03
    assert r.metrics["margin_gain_walk_min_m"] == pytest.approx(gain[walk].min())
    assert r.metrics["margin_gained_share"] == pytest.approx(np.mean(gain[walk] > 1e-3))
