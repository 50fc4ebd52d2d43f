import math

import numpy as np
import pytest

from terrabench.metrics.navigation import group_summary, journey, navigation_metrics, wilson_interval

TARGET, START = (9.0, -9.0), (0.0, 0.0)
L0 = math.hypot(9, 9)


def straight(n=200, stop=0.3):
    s = np.linspace(0, 1, n)[:, None]
    end = np.array(TARGET) * (1 - stop / L0)
    xy = s * end
    return np.hstack([xy, np.zeros((n, 1))])


def test_a_straight_flat_run_has_nef_one():
    m = navigation_metrics(straight(), TARGET, START, energy=100.0, success_threshold=0.5)
    assert m["success"] == 1.0 and m["d_min"] == 0.0
    assert m["NCR"] == pytest.approx(1.0)
    assert m["journey"] == pytest.approx(L0 - 0.3)
    assert m["NEF"] == pytest.approx(L0 / (L0 - 0.3))  # slightly above 1: stops 0.3 m short
    assert m["NEC"] == pytest.approx(100.0 / L0)


def test_failure_keeps_the_closest_approach():
    path = straight(stop=3.0)
    m = navigation_metrics(path, TARGET, START, energy=50.0, success_threshold=0.5)
    assert m["success"] == 0.0
    assert m["d_min"] == pytest.approx(3.0)
    assert m["NCR"] == pytest.approx((L0 - 3) / L0)
    assert m["NEF"] == pytest.approx(1.0)


def test_a_detour_lowers_nef_and_climbing_counts_in_the_journey():
    xy = straight()
    wiggly = xy.copy()
    wiggly[:, 2] = 0.5 * np.sin(np.linspace(0, 20 * np.pi, len(xy)))
    flat = navigation_metrics(xy, TARGET, START, 1.0, 0.5)
    bumpy = navigation_metrics(wiggly, TARGET, START, 1.0, 0.5)
    assert bumpy["journey"] > flat["journey"] and bumpy["NEF"] < flat["NEF"]


def test_journey_starts_at_the_first_sample_not_the_origin():
    path = np.array([[0, 0, 5.0], [1, 0, 5.0]])
    assert journey(path) == pytest.approx(1.0)


def test_moving_away_gives_zero_ncr_and_undefined_nec():
    path = np.array([[0, 0, 0], [-1, 1, 0.0]])
    m = navigation_metrics(path, TARGET, START, 10.0, 0.5)
    assert m["NCR"] == 0.0 and math.isnan(m["NEC"])


def test_group_summary_counts_every_trial():
    trials = ([{"success": 1.0, "NCR": 1.0, "NEF": 0.8, "NEC": 200.0}] * 3
              + [{"success": 0.0, "NCR": 0.5, "NEF": 0.4, "NEC": float("nan")}])
    s = group_summary(trials)
    assert s["n"] == 4 and s["NSR"] == 75.0
    assert s["NCR"] == pytest.approx(87.5) and s["NEF"] == pytest.approx(0.7) and s["NEC"] == pytest.approx(200.0)
    assert (s["n_NCR"], s["n_NEF"], s["n_NEC"]) == (4, 4, 3)  # the NaN NEC is left out of its mean
    assert s["NSR_lo"] < 75.0 < s["NSR_hi"]


def test_pooled_nec_is_total_energy_over_total_progress():
    trials = [{"success": 1.0, "energy": 100.0, "D_ef": 10.0, "NEC": 10.0},
              {"success": 0.0, "energy": 100.0, "D_ef": 0.01, "NEC": 10000.0}]
    s = group_summary(trials)
    assert s["NEC"] == pytest.approx(5005.0)  # the paper's mean: dominated by the stuck trial
    assert s["NEC_pooled"] == pytest.approx(200.0 / 10.01)


def test_wilson_interval_edges():
    lo, hi = wilson_interval(0, 50)
    assert lo == pytest.approx(0.0, abs=1e-12) and 0.05 < hi < 0.1
    lo, hi = wilson_interval(50, 50)
    assert hi == pytest.approx(1.0) and 0.9 < lo < 0.95
