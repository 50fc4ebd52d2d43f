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
