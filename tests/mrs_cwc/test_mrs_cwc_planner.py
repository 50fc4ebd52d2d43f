"""A* on height maps: optimality on known cases, the cost's physics, waypoint output."""

import math

import numpy as np
import pytest

from terrabench.planning.astar import MOVES, astar, polyline_deviation, simplify
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.planner import PlannerConfig, edge_costs, plan_waypoints
from terrabench.terrain import dataset


def test_flat_ground_gives_the_octile_shortest_path():
    h = np.zeros((30, 30))
    cfg = PlannerConfig(cell=0.1)
    path = astar(edge_costs(h, 0.1, cfg), (0, 0), (20, 10), min_cost_per_cell=0.1)
    steps = np.diff(np.array(path), axis=0)
    length = sum(math.hypot(*s) for s in steps)
    assert length == pytest.approx(10 * math.sqrt(2) + 10)  # octile distance: optimal


def test_a_steep_ridge_is_walked_around_when_a_gap_exists():
    h = np.zeros((40, 40))
    h[20, :35] = 5.0  # a wall with a gap at j >= 35
    cfg = PlannerConfig(cell=0.1)
    path = astar(edge_costs(h, 0.1, cfg), (5, 5), (35, 5), min_cost_per_cell=0.1)
    crossing = [p for p in path if p[0] == 20]
    assert crossing and all(j >= 35 for _, j in crossing)


def test_climbing_costs_more_than_descending_and_cross_slope_costs():
    x = np.arange(20)[:, None] * 0.1
    h = np.repeat(0.3 * x, 20, axis=1)  # 16.7 deg slope rising along +i
    c = edge_costs(h, 0.1, PlannerConfig(cell=0.1))
    up, down, across = MOVES.index((1, 0)), MOVES.index((-1, 0)), MOVES.index((0, 1))
    assert c[up, 10, 10] > c[down, 10, 10] > 0.1
    assert c[across, 10, 10] > 0.1  # moving along the contour: pure cross slope
    assert np.all(c[np.isfinite(c)] >= 0.1 - 1e-12)  # never below the heuristic's bound


def test_unreachable_goal_is_a_clear_error():
    c = np.full((8, 5, 5), np.inf)
    with pytest.raises(ValueError, match="unreachable"):
        astar(c, (0, 0), (4, 4), 1.0)
    with pytest.raises(ValueError, match="outside"):
        astar(c, (0, 0), (9, 4), 1.0)


def test_simplify_keeps_ends_and_corners():
    pts = np.array([[0, 0], [1, 0.01], [2, 0], [2, 1], [2, 2]], float)
    s = simplify(pts, 0.1)
    assert np.array_equal(s, np.array([[0, 0], [2, 0], [2, 2]], float))


def test_planned_waypoints_reach_the_target_and_resemble_the_released_ones():
    cfg = MRSConfig()
    for tid in ("A-10", "B-20"):
        wp = plan_waypoints(dataset.get(tid), cfg)
        assert np.allclose(wp[-1], (9, -9)) and np.hypot(*wp[0]) < 0.2
        assert np.all(np.hypot(*np.diff(wp, axis=0).T) <= cfg.planner.max_spacing + 1e-9)
        # same start and goal: the paths stay within a few metres of the released ones
        assert polyline_deviation(wp, dataset.released_waypoints(tid)) < 3.0


def test_polyline_deviation_of_parallel_lines():
    a = np.array([[0, 0], [10, 0]], float)
    b = np.array([[0, 1], [10, 1]], float)
    assert polyline_deviation(a, b) == pytest.approx(1.0)
