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


def test_the_crawlers_lie_inside_the_tips_polygon_exactly_when_four_arms_support():
    """The paper's Fig. 7 property, as stored (``crawlers_in_tips``, ``crawlers_enclosed_share``):
    with four supporting tips around the body the four track pulleys are inside their polygon; with
    three, the pulley at the missing arm's corner lies beyond the triangle's diagonal, so a crawl
    gait with one arm in transfer cannot hold it (docs/octopus.md, "The crawlers inside the tips'
    polygon")."""
    from terrabench.systems.octopus.scenarios import SYSTEM

    spec = SYSTEM.plan(methods=["clm"], instances=["step-400"], overrides={"protocol.timeout": 18.0})[0]
    r = SYSTEM.run_trial(spec)
    ts = r.timeseries
    depth, mode, tips, moving = ts["crawlers_in_tips"], ts["mode"], ts["tip_contact"], ts["moving_arm"]
    walk = (mode == 0) & (ts["t"] > 1.0)
    supports = np.array([sum(int(b) >> i & 1 and i != int(mv) for i in range(4)) if np.isfinite(mv) else 0
                         for b, mv in zip(tips, moving)])
    four, three = walk & (supports == 4), walk & (supports == 3)
    assert four.sum() >= 5 and three.sum() >= 5
    assert (depth[four] > 0.1).all() and (depth[three] < 0.0).all()
    assert np.isnan(depth[walk & (supports < 3)]).all()
    share = r.metrics["crawlers_enclosed_share"]
    assert 0.0 < share < 1.0
