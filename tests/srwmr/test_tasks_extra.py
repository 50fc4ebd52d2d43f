"""Tasks 2, 9, 10, 15 (layouts, differential steering, crab direction), the steering fold with
hysteresis, the steer-in-place offset term, the slip along the commanded direction and the
report's T9/T10/T15 figures."""

import math

import numpy as np
import pytest
from fake_rover import Obs, controller

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr import layouts as lay
from terrabench.systems.srwmr.kinematics import (
    STEER_HYSTERESIS,
    axle_positions,
    clearance_range,
    delta_for_clearance,
    differential_kinematics,
    geometry,
    steer_and_spin,
    wheelbase_front_middle,
)
from terrabench.systems.srwmr.metrics import along_command, body_slip, windowed_slip
from terrabench.systems.srwmr.modes import Step
from terrabench.systems.srwmr.robot import WHEEL_SIDE, RobotConfig
from terrabench.systems.srwmr.scenarios import SYSTEM

CFG = RobotConfig()
SIGN = np.array([1.0 if s == "L" else -1.0 for s in WHEEL_SIDE])


# ------------------------------------------------------------------ steering fold
def test_a_heading_across_90_deg_keeps_its_side_near_90_deg():
    r = CFG.wheel_radius
    v = np.array([[1e-4, 0.015], [-1e-4, 0.015], [0.0, -0.015], [-1e-4, 0.015], [-0.01, 0.0], [0.0, 0.0]])
    prev = np.radians([89.9, 89.9, 89.9, 0.0, 0.0, 30.0])
    mu, spin = steer_and_spin(v, r, prev)
    # 1: plain; 2: 90.4 deg kept (not swung to -89.6); 3: a crab to the right entered at +90 deg
    # stays at +90 rolling backwards; 4: from 0 the same heading folds to -89.6 deg, backwards
    assert np.degrees(mu[:4]) == pytest.approx([89.618, 90.382, 90.0, -89.618], abs=1e-3)
    assert np.sign(spin[:4]).tolist() == [1.0, 1.0, -1.0, -1.0]
    # 5: straight backwards from 0 stays at 0 (never 180 deg); 6: a still wheel keeps its angle
    assert mu[4] == 0.0 and spin[4] < 0 and mu[5] == prev[5] and spin[5] == 0.0
    # every choice rolls the wheel at the required velocity
    moving = np.hypot(v[:, 0], v[:, 1]) > 0
    rim = r * spin[:, None] * np.stack([np.cos(mu), np.sin(mu)], axis=1)
    assert np.allclose(rim[moving], v[moving], atol=1e-12)
    # beyond the hysteresis the fold wins again
    a = math.pi / 2 + STEER_HYSTERESIS + 0.02
    mu2, spin2 = steer_and_spin(np.array([[math.cos(a), math.sin(a)]] * 6) * 0.01, r, np.full(6, 1.5))
    assert np.all(mu2 < 0) and np.all(spin2 < 0)


def test_steering_in_place_rolls_the_offset_wheels_out_on_both_sides():
    """While WCM steers in place, each wheel's spin rolls out the motion of its offset contact
    along its heading (the left and right offsets point outwards: opposite signs)."""
    c = controller([Step("WCM", v=0.015, dy=0.5)])
    cmd = c(Obs(0.0))
    mu_rate = (cmd.steer - 0.0) / 0.01
    assert np.all(mu_rate > 0)
    dmu = 1e-6
    mu = np.full(6, 0.3)
    p0 = axle_positions(CFG, [0, 0], mu=mu)
    p1 = axle_positions(CFG, [0, 0], mu=mu + dmu)
    heading = np.stack([np.cos(mu), np.sin(mu)], axis=1)
    along = np.sum((p1 - p0)[:, :2] * heading, axis=1) / dmu  # contact speed per steering rate
    assert along == pytest.approx(-SIGN * CFG.wheel_offset, rel=1e-5)  # a finite difference
    assert cmd.spin * CFG.wheel_radius == pytest.approx(along * mu_rate, rel=1e-7)  # along: a difference quotient


# ------------------------------------------------------------------ differential steering
def test_differential_kinematics_holds_steering_and_splits_the_sides():
    d = delta_for_clearance(CFG, 0.45)
    geom = geometry(CFG, (d, d))
    mu, spin = differential_kinematics(CFG, (0.0, 0.0, 0.02, 0.0, 0.0), geom)
    assert np.all(mu == 0.0)
    # a left turn in place: left wheels backwards, right forwards, rim speed wz * |y|
    assert np.all(spin[SIGN > 0] < 0) and np.all(spin[SIGN < 0] > 0)
    assert spin * CFG.wheel_radius == pytest.approx(-0.02 * geom[0][:, 1])
    # lowering the chassis (closing rate < 0) moves the front wheels forward: they roll for it
    _, spin2 = differential_kinematics(CFG, (0.0, 0.0, 0.0, -0.01, -0.01), geom)
    assert np.all(spin2[:2] > 0) and spin2[:2] * CFG.wheel_radius == pytest.approx(geom[1][:2, 0] * -0.01)


def test_t15_lowering_lengthens_the_wheelbase_and_t10_heights_are_reachable():
    hi, lo = lay.T15_CLEARANCE
    wb_hi = wheelbase_front_middle(CFG, [delta_for_clearance(CFG, hi)] * 2)[0]
    wb_lo = wheelbase_front_middle(CFG, [delta_for_clearance(CFG, lo)] * 2)[0]
    assert wb_lo > wb_hi + 0.1
    cmin, cmax = clearance_range(CFG)
    assert all(cmin <= h <= cmax for h in lay.T10_HEIGHTS)
    # the highest T10 height keeps MC#3 inside RCLM's threshold, and below the wheels' touching
    d = delta_for_clearance(CFG, max(lay.T10_HEIGHTS))
    eta = (CFG.wheelbase_fm - wheelbase_front_middle(CFG, [d, d])[0]) / CFG.wheelbase_fm
    k3 = mc.thresholds("RCLM")[1]
    assert eta < k3 < (CFG.wheelbase_fm - CFG.wheelbase_fm_least) / CFG.wheelbase_fm


# ------------------------------------------------------------------ layouts
def test_new_tasks_are_in_the_tasks_group_with_their_methods():
    specs = SYSTEM.plan(group="tasks")
    pairs = {(s.instance, s.method) for s in specs}
    for p in [("t2-wall", "wcm"), ("t9-avoid", "wrm"), ("t9-avoid", "wcm"), ("t10-heights", "rclm"),
              ("t15-w002", "rclm"), ("t15-w003", "rclm")]:
        assert p in pairs
    with pytest.raises(ValueError, match="valid: wrm, wcm"):
        lay.layout("t9-avoid", "rclm", CFG)


def test_t2_obstacles_block_the_straight_line_and_the_crabs_clear_them():
    L = lay.layout("t2-wall", "wcm", CFG)
    (wx, wy, whx, why, whz), (rx, ry, rhx, rhy, rhz) = L.boxes
    assert abs(wy) < why and 2 * whz > 0.25 and 2 * rhz > 0.25  # on the start line, taller than the clearance
    modes = [s.mode for s in L.plan]
    assert modes == ["WRM", "WCM", "WRM", "WCM", "WRM"]
    y_after = L.plan[1].dy
    half = CFG.track / 2 + CFG.wheel_width / 2
    assert y_after + half < -why  # past the wall's right end
    assert abs(ry - y_after) < rhy and y_after + L.plan[3].dy - half > ry + rhy  # rocks on the new line, cleared
    assert L.goal_x > rx + rhx


def test_t9_paths_end_at_b_avoiding_the_obstacle():
    wrm = lay.layout("t9-avoid", "wrm", CFG)
    wcm = lay.layout("t9-avoid", "wcm", CFG)
    bx, by = lay.T9_B
    pts = np.asarray(wrm.plan[0].waypoints)
    assert pts[-1] == pytest.approx([bx, by])
    # the WRM path: straight, a 45 deg arc of T9_RADIUS (below the pure-pursuit cap 0.8 /m), straight
    hd = np.degrees(np.arctan2(np.diff(pts[:, 1]), np.diff(pts[:, 0])))
    assert hd[0] == pytest.approx(0.0, abs=1e-9) and hd[-1] == pytest.approx(45.0, abs=1e-6)
    assert 1 / lay.T9_RADIUS < 0.8
    assert wcm.plan[0].dx == bx and wcm.plan[0].dy == by
    # the obstacle stands on the start heading; the WCM footprint swept along A->B misses it
    ox, oy, hx, hy, _ = wcm.boxes[0]
    assert oy == 0.0 and ox - hx > CFG.front_len + CFG.wheel_radius
    a = math.atan2(by, bx)
    n = np.array([-math.sin(a), math.cos(a)])
    robot_half = (CFG.front_len + CFG.wheel_radius) * abs(n[0]) + (CFG.track / 2 + CFG.wheel_width / 2) * abs(n[1])
    obst_half = hx * abs(n[0]) + hy * abs(n[1])
    assert abs(np.dot([ox, oy], n)) > robot_half + obst_half


def test_wcm_crab_steers_to_the_direction_of_dx_dy():
    c = controller([Step("WCM", v=0.015, dx=3.0, dy=2.0)])
    cmd = c(Obs(0.0))
    assert c.steer_goal == pytest.approx(np.full(6, math.atan2(2.0, 3.0)))
    assert np.all(cmd.u == 0)  # steering in place first
    # steered: the crab moves along the line once MC#7 has ramped the forward speed up (~3 s)
    c.action.phase, c.action.y_start = 1, 0.0
    heading, steer = [], []
    for k in range(400):
        cmd = c(Obs(5.0 + 0.01 * k, mu=cmd.steer if k else np.full(6, math.atan2(2.0, 3.0))))
        heading.append(math.atan2(cmd.u[1], cmd.u[0]))
        steer.append(np.degrees(cmd.steer))
    # the speed ramps along the steered line from the first period (vy with vx, not vy at once):
    # the commanded heading and the wheels never swing towards 90 deg while MC#7 ramps (T9's MC#11 halt)
    assert np.array(heading) == pytest.approx(math.atan2(2.0, 3.0), abs=1e-6)
    assert np.array(steer) == pytest.approx(33.69, abs=0.05)
    assert cmd.u[0] == pytest.approx(0.015 * 3 / math.hypot(3, 2))  # at the step's speed after the ramp
    assert np.degrees(cmd.steer) == pytest.approx(np.full(6, 33.69), abs=0.05)


# ------------------------------------------------------------------ metrics
def test_slip_along_the_commanded_direction():
    v = np.array([0.01, 0.02, 0.0, 0.0])
    vc = np.array([0.02, 0.02, 0.0, 0.0])
    vl = np.array([0.0, 0.0, 0.009, 0.012])
    vyc = np.array([0.0, 0.0, -0.015, 0.015])
    par, cmd = along_command(v, vc, vl, vyc)
    assert par[:2].tolist() == v[:2].tolist() and cmd[:2].tolist() == vc[:2].tolist()  # WRM rows exact
    assert par[2:] == pytest.approx([-0.009, 0.012]) and cmd[2:] == pytest.approx([0.015, 0.015])
    assert body_slip(par, cmd) == pytest.approx(1 - (0.03 + 0.003) / 0.07)
    w = windowed_slip(np.r_[np.full(10, 0.01), np.full(10, 0.015)], np.full(20, 0.02), 10)
    assert w == pytest.approx([0.5, 0.25])


def test_t10_period_labels_and_t15_slope():
    from terrabench.systems.srwmr.report_tasks import t10_periods, yaw_vs_wheelbase

    assert t10_periods() == ["250", "250->450", "450", "450->150", "150", "150->480", "480", "480->250"]
    assert len(t10_periods()) == len(lay.layout("t10-heights", "rclm", CFG).plan)
    # a synthetic T15 series: closing angle falls (wheelbase grows) and the yaw rate falls with it
    t = np.arange(0.0, 60.0, 0.5)
    d = np.linspace(0.58, -0.26, len(t))
    wb = np.array([wheelbase_front_middle(CFG, [x, x])[0] for x in d])
    rate = 0.01 - 0.02 * (wb - wb[0])
    yaw = np.concatenate([[0.0], np.cumsum(rate[1:] * np.diff(t))])
    ts = {"t": t, "step": np.ones(len(t)), "yaw": yaw, "delta_L": d, "delta_R": d}
    w, r = yaw_vs_wheelbase(ts, CFG)
    assert np.polyfit(w, r, 1)[0] == pytest.approx(-0.02, rel=0.05)


def test_in_place_steering_holds_the_clearance_and_turns_below_the_command():
    """Sec. 8.6: differential steering in place at a held clearance. The RCLM step does not end at
    its (already reached) clearance but steers for ``steer_s`` (so a 20 s window times out instead
    of succeeding at once); the clearance stays where it is, and the body turns the commanded way
    at a fraction of the command on loose soil (the paper: about one-fifth)."""
    spec = SYSTEM.plan(methods=["rclm"], instances=["steer-w002"], seeds=1,
                       overrides={"protocol.timeout": 20.0})[0]
    r = SYSTEM.run_trial(spec)
    assert r.status == "timeout"
    t = np.asarray(r.timeseries["t"], float)
    yaw = np.unwrap(np.asarray(r.timeseries["yaw"], float))
    dl = np.asarray(r.timeseries["delta_L"], float)
    assert np.ptp(dl) < 0.01                               # the closing angle held (rad)
    rate = (yaw[-1] - yaw[t >= 5.0][0]) / (t[-1] - t[t >= 5.0][0])
    assert 0.0 < rate < 0.5 * 0.02
