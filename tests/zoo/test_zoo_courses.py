"""Every family's course has its feature where it declares it, a start and a goal line, for
every robot's footprint; the zoo's metrics on synthetic episodes (no simulation)."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from terrabench.terrain.course import add_course
from terrabench.terrain.mjcf import GROUND_BIT
from terrabench.zoo import families as fam
from terrabench.zoo.adapter import adapters
from terrabench.zoo.config import CourseConfig
from terrabench.zoo.metrics import summarize

CC = CourseConfig()
FOOTPRINTS = {r: a.footprint() for r, a in adapters().items() if a.methods}
QUICK = [(f.id, t) for f in fam.FAMILIES.values() for t in f.quick]


def _h(course, x, y=0.0):
    return float(course.height(np.array([x]), np.array([y]))[0])


@pytest.mark.parametrize("robot", sorted(FOOTPRINTS))
@pytest.mark.parametrize("fid, token", QUICK)
def test_layout_start_goal_and_ground(robot, fid, token):
    fp = FOOTPRINTS[robot]
    c = fam.family(fid).course(token, fp, CC)
    x0, x1 = c.feature
    assert c.start_front == pytest.approx(-CC.run_up)
    assert c.goal_x == pytest.approx(x1 + CC.goal_past) and x1 >= x0 >= 0.0
    assert c.lane == pytest.approx(fp.width + 2 * CC.lane_margin)
    # ground under the whole robot at the start and beyond the goal line for its whole length
    lo, hi = c.x_range
    assert lo <= c.start_front - fp.length - 0.5 and hi >= c.goal_x + fp.length
    for x in (c.start_front - fp.length, c.start_front, c.goal_x, c.goal_x + fp.length):
        assert math.isfinite(_h(c, x)), (x, c.note)
    # the fall height is below every piece of ground the robot drives on
    xs = np.linspace(c.start_front - fp.length, c.goal_x + fp.length, 200)
    assert c.fall_z < np.min(c.height(xs, np.zeros_like(xs))) or fid == "gap"
    assert c.note


@pytest.mark.parametrize("token", fam.family("step-up").quick)
def test_step_up_and_block_have_their_height_at_the_feature(token):
    fp, h = FOOTPRINTS["octopus"], float(token)
    up = fam.family("step-up").course(token, fp, CC)
    assert _h(up, -0.05) == 0.0 and _h(up, 0.05) == pytest.approx(h) and _h(up, up.goal_x) == pytest.approx(h)
    blk = fam.family("block").course(token, fp, CC)
    L = CC.block_length
    assert _h(blk, -0.05) == 0.0 and _h(blk, 0.5 * L) == pytest.approx(h) and _h(blk, L + 0.05) == 0.0


def test_step_down_gap_slope_rough_soil_mixed():
    fp = FOOTPRINTS["mrs-cwc"]
    down = fam.family("step-down").course("0.3", fp, CC)
    assert _h(down, -0.05) == pytest.approx(0.3) and _h(down, 0.05) == 0.0
    gap = fam.family("gap").course("0.3", fp, CC)
    d = CC.ditch_depth
    assert _h(gap, -0.05) == pytest.approx(d) and _h(gap, 0.15) == 0.0 and _h(gap, 0.35) == pytest.approx(d)
    assert gap.feature == (0.0, 0.3) and d - CC.fall_drop == pytest.approx(gap.fall_z)
    for fid in ("slope-rigid", "slope-loose"):
        s = fam.family(fid).course("20", fp, CC)
        top = math.tan(math.radians(20)) * CC.slope_length
        assert _h(s, -0.2) == pytest.approx(0.0, abs=1e-9)
        assert _h(s, CC.slope_length) == pytest.approx(top, abs=0.01) and _h(s, s.goal_x) == pytest.approx(top)
        assert s.soil == (None if fid == "slope-rigid" else "loose")
    r = fam.family("rough-sine").course("0.05", fp, CC)
    hf = r.hfield
    inside = (hf.x > CC.rough_ramp) & (hf.x < CC.rough_length - CC.rough_ramp)
    outside = (hf.x < 0) | (hf.x > CC.rough_length)
    assert 0.005 < hf.h[inside].std() and np.abs(hf.h).max() <= 0.05 + 1e-9 and np.all(hf.h[outside] == 0)
    a, b = (fam.family("rough-sine").course("0.05", fp, CC, seed=s).hfield.h for s in (0, 1))
    assert not np.array_equal(a, b)
    mrs = fam.family("rough-mrs").course("B", fp, CC)
    assert mrs.extra["terrain"].startswith("B-") and mrs.hfield.h[inside].std() > 0.01
    soft = fam.family("soft-flat").course("loose", fp, CC)
    assert soft.soil == "loose" and soft.hfield is None and not soft.boxes and soft.floor_z == 0.0
    assert fam.family("soft-flat").value("very_loose") > fam.family("soft-flat").value("loose") > 20.0
    mixed = fam.family("mixed").course("1", fp, CC)
    assert [b.name for b in mixed.boxes] == ["terrace_a", "terrace_b", "block"]
    assert _h(mixed, 0.5) == pytest.approx(0.1) and _h(mixed, 1.07) == 0.0 and _h(mixed, 3.0) == pytest.approx(0.06)


@pytest.mark.parametrize("fid, token", [("step-up", "0.15"), ("gap", "0.3"), ("slope-rigid", "10"),
                                        ("rough-sine", "0.05"), ("rough-mrs", "A")])
def test_add_course_compiles_with_the_robot_s_collision_bits(fid, token):
    c = fam.family(fid).course(token, FOOTPRINTS["octopus"], CC)
    spec = mujoco.MjSpec()
    geoms = add_course(spec, c, contype=GROUND_BIT, conaffinity=0, friction=0.9)
    m = spec.compile()
    assert m.ngeom == (geoms["plane"] is not None) + len(geoms["boxes"]) + (geoms["hfield"] is not None)
    assert all(m.geom_contype[g] == GROUND_BIT and m.geom_conaffinity[g] == 0 for g in range(m.ngeom))


def test_metrics_on_a_synthetic_episode():
    rear = np.linspace(-1.0, 1.0, 11)
    z = np.zeros(11)
    m = summarize("success", 20.0, 100.0, rear, z, z + 0.1, 50.0, 1.0, -1.0)
    assert m["success"] == 1.0 and m["time"] == 20.0 and m["progress"] == pytest.approx(2.0)
    assert m["speed"] == pytest.approx(0.1) and m["energy_per_m"] == pytest.approx(50.0)
    assert m["energy_per_m_kg"] == pytest.approx(1.0) and m["max_pitch"] == pytest.approx(0.1)
    still = summarize("stuck", 20.0, 5.0, np.full(11, -1.0), z, z, 50.0, 1.0, -1.0)
    assert still["success"] == 0.0 and math.isnan(still["time"]) and math.isnan(still["energy_per_m"])


class _Fake:
    """ZooRules on a scripted pose (no simulation): the stop order."""

    columns = ("a",)

    def __init__(self, pose, own=None):
        from types import SimpleNamespace

        from terrabench.zoo.config import ZooConfig

        self._p, self._own = pose, own
        self.course = fam.family("gap").course("0.3", FOOTPRINTS["octopus"], CC)
        self.zoo = ZooConfig()
        self.data = SimpleNamespace(time=0.0)


def _rules(pose, own=None):
    from terrabench.zoo.task import ZooRules

    class T(ZooRules, _Fake):
        def pose(self):
            return self._p

        def own_stop(self, obs, rear):
            return self._own

    t = T(pose, own)
    t.zoo_init()
    return t


def test_stop_order_turned_over_fell_success_own_stuck():
    goal, fall = _rules((0, 0, 1, 0, 0)).course.goal_x, _rules((0, 0, 1, 0, 0)).course.fall_z
    assert _rules((goal + 1, 0.0, fall - 1, 0.0, 1.3)).check(None, False)[0] == "turned_over"
    assert _rules((goal + 1, 0.0, fall - 1, 0.0, 0.0)).check(None, False)[0] == "fell"
    assert "lane" in _rules((goal + 1, 5.0, 1.0, 0.0, 0.0)).check(None, False)[1]
    assert _rules((goal + 1, 0.0, 1.0, 0.0, 0.0), own=("stuck", "halt")).check(None, False)[0] == "success"
    assert _rules((0.0, 0.0, 1.0, 0.0, 0.0), own=("stuck", "halt")).check(None, False) == ("stuck", "halt")
    t = _rules((0.0, 0.0, 1.0, 0.0, 0.0))
    assert t.check(None, False) is None and t.columns[-5:] == ("zoo_rear_x", "zoo_y", "zoo_low_z", "zoo_roll",
                                                                "zoo_pitch")
    out = None
    for k in range(60):  # no progress: stuck after protocol.stuck_time, on the slow checks only
        t.data.time = 0.5 * k
        out = t.check(None, True) or out
    assert out is not None and out[0] == "stuck"
