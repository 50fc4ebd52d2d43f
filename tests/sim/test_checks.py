"""Shared stop rules (sim/checks.py)."""

import math

import numpy as np
import pytest

from terrabench.sim.checks import Stalled, fell, roll_pitch, turned_over


def _quat(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.r_[math.cos(angle / 2), math.sin(angle / 2) * axis]


@pytest.mark.parametrize("angle", [-1.0, -0.3, 0.2, 1.1])
def test_roll_pitch_of_pure_rotations(angle):
    r, p = roll_pitch(_quat([1, 0, 0], angle))
    assert r == pytest.approx(angle) and p == pytest.approx(0.0, abs=1e-12)
    r, p = roll_pitch(_quat([0, 1, 0], -angle))  # about -y: nose up for angle > 0 (x forward, z up)
    assert p == pytest.approx(angle) and r == pytest.approx(0.0, abs=1e-12)


def test_turned_over_and_fell_fire_only_past_their_limits():
    assert turned_over(1.19, -1.19, 1.2) is None
    status, reason = turned_over(0.1, -1.25, 1.2)
    assert status == "turned_over" and "1.25" in reason
    assert fell(-0.4, -0.5) is None and fell(-0.6, -0.5, "leader") == ("fell", "leader below z = -0.5 m")


def test_stalled_after_the_time_without_progress():
    stop = Stalled(2.0, 0.1)
    assert [stop(t, 0.0, 0.0, 5.0) for t in (0.0, 1.0)] == [None, None]
    assert stop(2.0, 0.05, 0.0, 5.0, "at s = 0.05 m")[0] == "stuck"
    stop = Stalled(2.0, 0.1)
    assert all(stop(t, 0.2 * t, 0.0, 5.0 - 0.2 * t) is None for t in np.arange(0.0, 10.0, 0.5))
