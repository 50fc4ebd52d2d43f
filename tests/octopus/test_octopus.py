"""OCTOPUS: pinned model, sensing boundary, CLM rules, stability margin, terrain pieces, trials."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from terrabench import get_system
from terrabench.benchmark.trial import TrialSpec
from terrabench.sim.scene import compile_scene
from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus import clm, rules
from terrabench.systems.octopus.controller_config import CLMConfig
from terrabench.systems.octopus.robot import RobotConfig
from terrabench.systems.octopus.scenarios import SYSTEM
from terrabench.systems.octopus.sensing import FIELDS, Observation
from terrabench.systems.octopus.stability import stability_margin
from terrabench.terrain import pieces


def _task(instance="step-400", method="clm"):
    cfg = SYSTEM.resolve_config({})
    return SYSTEM.make_task(TrialSpec("octopus", "x", method, instance, 0, {}), cfg)


def test_model_counts():
    task = _task()
    m, _ = compile_scene(task)
    assert (m.nbody, m.njnt, m.nu, m.nsensor) == (26, 25, 16, 26)


def test_sensing_boundary():
    task = _task()
    obs = task.bind(*compile_scene(task))
    assert isinstance(obs, Observation)
    names = set(Observation.__slots__) - {n for n in Observation.__slots__ if n.startswith("_")}
    assert names == set(FIELDS)
    for bad in ("pos", "x", "y", "yaw", "contact", "terrain", "qpos", "xpos"):
        assert bad not in names


def test_terrain_case_and_height():
    s = (0.05, 0.45, 0.45)
    assert rules.terrain_case(np.array([0.0, 0.01, 0.0, -0.01]), s) == rules.FLAT
    assert rules.terrain_case(np.array([0.4, 0.4, 0.0, 0.0]), s) == rules.UP
    assert rules.terrain_case(np.array([-0.2, -0.2, 0.0, 0.0]), s) == rules.DOWN
    assert rules.terrain_case(np.array([0.4, 0.0, 0.0, 0.0]), s) == rules.UNDETECTABLE
    assert rules.step_height(np.array([0.4, 0.4, 0.0, 0.0])) == pytest.approx(0.4)


def test_flipper_rule():
    assert rules.flipper_rule(0.5, 10.0, 40, 0.02, 1.48, 0.02) == (0.5, "low")
    assert rules.flipper_rule(0.5, -60.0, 40, 0.02, 1.48, 0.02) == (pytest.approx(0.52), "high")
    assert rules.flipper_rule(0.5, 60.0, 40, 0.02, 1.48, 0.02) == (pytest.approx(0.48), "high")
    assert rules.flipper_rule(1.49, 0.0, 40, 0.02, 1.48, 0.02)[1] == "limit"


def test_cog_height_travel_and_climb_rule():
    rear = np.array([[-0.4, 0.5, -0.55], [-0.4, -0.5, -0.55]])
    assert rules.cog_height(rear, 0.05) == pytest.approx(0.5)
    assert rules.travel(0.0, 0.1, 0.0, 0.02) == pytest.approx(0.002)
    assert rules.travel(0.0, 0.1, np.pi / 3, 0.02) == pytest.approx(0.001)
    b, f, rel = rules.climb_rule(0.1, 0.0, 0.2, 0.4, 0.0, 0.3, 0.05, 0.05, 0.0)
    assert (b, f, rel) == (pytest.approx(0.15), pytest.approx(-0.05), False)
    b, f, rel = rules.climb_rule(0.1, -0.2, 0.5, 0.4, 0.35, 0.3, 0.05, 0.05, 0.0)
    assert (b, f, rel) == (pytest.approx(0.05), pytest.approx(-0.15), True)


def test_arm_stop_cases_and_contact():
    t = np.array([0.75, 0.55, -0.05])
    assert rules.arm_stop_case(np.array([0.5, 0.55, -0.05]), t, 0.1, 0.08) == "blocked"
    assert rules.arm_stop_case(np.array([0.74, 0.55, 0.35]), t, 0.1, 0.08) == "on-top"
    assert rules.arm_stop_case(np.array([0.74, 0.55, -0.3]), t, 0.1, 0.08) == "pit"
    assert rules.arm_stop_case(np.array([0.74, 0.55, -0.04]), t, 0.1, 0.08) == "reached"
    assert rules.contact_detected(30.0, 5.0, 20.0) and not rules.contact_detected(10.0, 5.0, 20.0)


def test_transfer_phases():
    q = np.array([0.0, 0.0, 1.0])
    ph, c = rules.transfer_step(1, q, q.copy(), np.array([0.9, 0.3, 1.2]), -0.6, 0.04, 0.04, 0.15)
    assert ph == 1 and c[1] < 0 and c[2] < 1.0          # lifting: boom up, elbow straightens
    ph, c = rules.transfer_step(1, np.array([0.0, -0.6, 0.3]), c, np.array([0.9, 0.3, 1.2]), -0.6, 0.04, 0.04, 0.15)
    assert ph == 2
    q = np.array([0.0, -0.6, 0.3])
    ph, c = rules.transfer_step(2, q, q.copy(), np.array([0.9, 0.3, 1.2]), -0.6, 0.04, 0.04, 0.15)
    assert ph == 2 and c[0] == pytest.approx(0.04)       # swinging forward


def test_ik_inverts_fk():
    cfg = RobotConfig()
    for k in ("LF", "RF", "LR", "RR"):
        p = np.array([0.7 if k[1] == "F" else -0.45, 0.55 if k[0] == "L" else -0.55, -0.05])
        assert np.allclose(ak.fk(ak.ik(p, cfg, k), cfg, k), p, atol=1e-6)


def test_stability_margin():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    assert stability_margin(sq, [0.5, 0.5]) == pytest.approx(0.5)
    assert stability_margin(sq, [0.2, 0.5]) == pytest.approx(0.2)
    assert stability_margin(sq, [1.0, 0.5]) == pytest.approx(0.0)
    assert stability_margin(sq, [1.3, 0.5]) == pytest.approx(-0.3)
    tri = np.array([[0, 0], [2, 0], [1, 2], [1, 0.5]], float)  # interior point ignored
    assert stability_margin(tri, [1, 0.1]) == pytest.approx(0.1)


def test_least_depth_is_the_smallest_margin_of_the_points_bit_for_bit():
    from terrabench.systems.octopus.stability import least_depth

    rng = np.random.default_rng(5)
    for _ in range(200):
        support = rng.normal(0, 0.6, (int(rng.integers(3, 5)), 2))
        pts = rng.normal(0, 0.3, (4, 2))
        assert least_depth(support, pts) == min(stability_margin(support, p) for p in pts)
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    assert least_depth(sq, np.array([[0.5, 0.5], [0.9, 0.5]])) == pytest.approx(0.1)  # the shallower one
    assert least_depth(sq, np.array([[0.5, 0.5], [1.2, 0.5]])) == pytest.approx(-0.2)  # one outside


def test_pieces_pure():
    a = pieces.jitter(np.random.default_rng(3), 0.03, 3.0)
    b = pieces.jitter(np.random.default_rng(3), 0.03, 3.0)
    assert a == b
    t1 = pieces.terraces((0.2, 0.2), (0.45,), yaw=0.3)
    assert t1 == pieces.terraces((0.2, 0.2), (0.45,), yaw=0.3)
    h = pieces.height_grid(pieces.step(0.4), np.array([-0.5, 0.5]), np.array([0.0]))
    assert h[0, 0] == 0.0 and h[1, 0] == pytest.approx(0.4)
    with pytest.raises(ValueError):
        pieces.step(0.0)


@pytest.mark.parametrize("method", ["clm", "ccm"])
def test_short_trial_deterministic(method):
    spec = SYSTEM.plan(methods=[method], instances=["step-400"], seeds=1, overrides={"protocol.timeout": 3.0})[0]
    r1, r2 = SYSTEM.run_trial(spec), SYSTEM.run_trial(spec)
    assert r1.status == r2.status == "timeout"
    assert r1.metrics.keys() == r2.metrics.keys()
    assert np.array_equal([r1.metrics[k] for k in r1.metrics], [r2.metrics[k] for k in r1.metrics], equal_nan=True)
    assert np.array_equal(r1.timeseries["s"], r2.timeseries["s"])


def test_bad_input():
    with pytest.raises(ValueError, match="method"):
        SYSTEM.plan(methods=["walk"])
    with pytest.raises(ValueError, match="instance"):
        SYSTEM.plan(instances=["step-999"])
    with pytest.raises(ValueError, match="step_height"):
        SYSTEM.plan(overrides={"scene.step_height": 0.0})
    with pytest.raises(ValueError, match="step_height"):
        SYSTEM.plan(overrides={"scene.step_height": 2.0})
    with pytest.raises(ValueError, match="seeds"):
        SYSTEM.plan(seeds=0)


def test_clm_lift_raises_chassis_vertically(octopus_begin):
    """The hoist (``clm.nose_climb=false``): tips on the ground, all tip targets pushed straight down:
    the chassis rises, it does not slide back."""
    task, ctl, ep, obs, stop = octopus_begin("clm", {"protocol.timeout": 40.0, "clm.nose_climb": False})
    start = None
    while stop is None:
        obs, stop = ep.step(ctl(obs))
        x, z = ep.data.xpos[task.chassis, 0], ep.data.xpos[task.chassis, 2]
        if ctl.state == clm.CLIMB and start is None:
            start = (obs.t, x, z)
        if start is not None and obs.t > start[0] + 4.0:
            break
    assert start is not None, "the step was never detected"
    assert z - start[2] > 0.2          # lifted on the arms
    assert x - start[1] > -0.1         # no backward slide on the rolling tips


def test_clm_climbs_and_ccm_limits():
    """CLM climbs the 400 mm step; the crawler-only baseline climbs 200 mm and not 400 mm."""
    (clm_400,) = SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1)
    ccm_200, ccm_400 = SYSTEM.plan(methods=["ccm"], instances=["sweep-h200", "sweep-h400"], seeds=1)
    assert SYSTEM.run_trial(clm_400).status == "success"
    assert SYSTEM.run_trial(ccm_200).status == "success"
    assert SYSTEM.run_trial(ccm_400).status != "success"


def test_steer_turns_back_to_the_start_heading():
    assert rules.steer(0.1, 0.0, 0.2, 0.03) == (0.1, 0.1)
    vl, vr = rules.steer(0.1, 0.05, 0.2, 0.03)           # turned left: the left side speeds up
    assert vl > 0.1 > vr and vl - 0.1 == pytest.approx(0.01)
    assert rules.steer(0.1, -1.0, 0.2, 0.03) == (pytest.approx(0.07), pytest.approx(0.13))  # capped
    assert rules.steer(0.0, 0.1, 0.2, 0.03) == (pytest.approx(0.02), pytest.approx(-0.02))  # in place


def test_gyro_heading_follows_the_true_yaw(octopus_begin):
    """The integrated gyro yaw rate (the heading channel) tracks the simulator's yaw."""
    task, ctl, ep, obs, stop = octopus_begin("clm", {"protocol.timeout": 24.0}, "block-500")
    worst = 0.0
    while stop is None:
        obs, stop = ep.step(ctl(obs))
        xm = ep.data.xmat[task.chassis]
        worst = max(worst, abs(ctl.heading - math.atan2(xm[3], xm[0])))
    assert worst < 0.01


def test_rough_ground_instances():
    """The rough group: a sine-sum heightfield per seed, the robot placed above it, both methods run."""
    assert SYSTEM.instances("rough") == ["rough-1", "rough-2", "rough-3"]
    a = SYSTEM.make_task(TrialSpec("octopus", "x", "clm", "rough-3", 0, {}), SYSTEM.resolve_config({}))
    b = SYSTEM.make_task(TrialSpec("octopus", "x", "clm", "rough-3", 1, {}), SYSTEM.resolve_config({}))
    assert a.layout.kind == "rough" and a.layout.terrain != b.layout.terrain   # a terrain per seed
    m, _ = compile_scene(a)
    assert m.nhfield == 1
    for method in ("clm", "ccm"):
        spec = SYSTEM.plan(methods=[method], instances=["rough-2"], seeds=1, overrides={"protocol.timeout": 3.0})[0]
        r = SYSTEM.run_trial(spec)
        assert r.status == "timeout" and abs(r.metrics["max_pitch"]) < 0.5   # placed on the ground, not dropped


def test_the_logging_period_does_not_change_the_motion():
    """The crawler power limit and the crawler energy read this tick's traction, not the last
    stored row's: a coarser log gives the same trajectory at the shared instants."""
    runs = []
    for lp in (0.1, 0.5):
        spec = SYSTEM.plan(methods=["clm"], instances=["step-400"],
                         overrides={"protocol.timeout": 4.0, "protocol.log_period": lp})[0]
        runs.append(SYSTEM.run_trial(spec))
    fine, coarse = (r.timeseries for r in runs)
    idx = np.searchsorted(fine["t"], coarse["t"])
    for col in ("s", "z", "pitch"):
        np.testing.assert_array_equal(fine[col][idx], coarse[col])
    assert runs[0].metrics["energy"] == runs[1].metrics["energy"]


def test_the_mechanism_metrics_are_read_off_the_stored_series():
    """Issue 28's per-trial figures: present, in their ranges, and the extremes of the stored columns."""
    spec = SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1, overrides={"protocol.timeout": 4.0})[0]
    r = SYSTEM.run_trial(spec)
    m = r.metrics
    for k in ("max_pitch_rad", "crawler_load_share_min", "tip_slip_max_m", "tracks_stopped_share", "margin_min_m",
              "margin_sensed_min_m"):
        assert k in m, k
    assert m["max_pitch_rad"] >= abs(m["max_pitch"]) - 1e-9   # the largest |pitch| bounds any pitch extreme
    assert m["tip_slip_max_m"] >= 0.0
    share = m["tracks_stopped_share"]
    assert share != share or 0.0 <= share <= 1.0   # NaN (no walking tick) or a share
    # standing on flat ground at the start, the robot's own (sensed) margin is positive
    assert m["margin_sensed_min_m"] > 0.0


def test_a_climb_phase_share_is_the_mean_over_its_own_run_of_rows():
    """``crawler_load_share_phase_min``: each run of consecutive climb rows in one mode is a phase,
    its share the mean of its finite rows; the least over the phases (a single low row does not
    decide it, a low phase does)."""
    from terrabench.systems.octopus.task import _least_run_mean

    nan = float("nan")
    mode = np.array([0, 1, 1, 1, 2, 2, 0, 1, 1])
    rows = np.isin(mode, (1, 2))
    share = np.array([0.0, 0.9, 0.0, 0.9, 1.0, nan, 0.0, 0.5, 0.6])
    assert _least_run_mean(mode, rows, share) == pytest.approx(0.55)   # phases 0.6, 1.0, 0.55
    share[7:] = nan
    assert _least_run_mean(mode, rows, share) == pytest.approx(0.6)    # a phase without a finite row
    assert np.isnan(_least_run_mean(mode, np.zeros(9, bool), share))


def _walking_clm():
    ctl = clm.CLMController(CLMConfig(), RobotConfig())
    ctl.machine.go(0.0, clm.WALK, "test")
    ctl.queue = []
    obs = SimpleNamespace(t=10.0, q_arm=np.zeros((4, 3)), tau_elbow=np.zeros(4), pitch=0.0, roll=0.0)
    return ctl, obs


def test_the_arm_the_crawlers_wait_for_takes_the_next_gait_turn():
    """Walking, the next transfer is the gait order's, unless a foothold has left its range: that
    arm goes first (the crawlers wait for it) and the cycle goes on from it."""
    ctl, obs = _walking_clm()
    assert clm.GAIT_ORDER[0] == "RR"
    ctl._transfer(obs)
    assert ctl.phase["RR"] == 1 and ctl.next_gait == 1       # no foothold out: the gait order
    ctl, obs = _walking_clm()
    ctl.out_of_reach, ctl.out_arm = True, "LR"
    ctl._transfer(obs)
    assert ctl.phase["LR"] == 1 and sum(map(bool, ctl.phase.values())) == 1
    assert clm.GAIT_ORDER[ctl.next_gait % 4] == "LF"          # then the arm after LR
    assert ctl.machine.events[-1].reason == "out of range: its turn comes first"


def test_an_arm_lifted_higher_glides_to_the_top_of_its_descent():
    """After a blocked swing (extra lift) the lowering target first moves on the straight line from
    the tip to the top of the descent over the transfer target, not in one jump."""
    ctl, obs = _walking_clm()
    k, i = "RR", clm.ARM_INDEX["RR"]
    ctl.phase[k], ctl.extra_lift[i] = 2, ctl.cfg.extra_lift
    tip = np.array([-0.5, -0.6, 0.9])
    ctl.tip_r[i] = tip
    ctl.phase_t[i] = ctl.cfg.phase_timeout + 1.0      # the swing is over: on to phase 3
    ctl._transfer(obs)
    assert ctl.phase[k] == 3 and ctl.glide[i] is not None
    p0, p1, n = ctl.glide[i]
    tx, ty, _ = ctl.targets[k]
    assert p0 == pytest.approx(tip.tolist()) and p1[:2] == pytest.approx([tx, ty]) and p1[2] < tip[2] - 0.1
    path = []
    for _ in range(n):  # a servo that follows its command exactly
        ctl.tip_r[i] = ak.fk(ctl.cmd.arm[i], ctl.robot, k)
        ctl.prev_tip_z, ctl.tip_z = ctl.tip_z, ctl.tip_r[:, 2].tolist()
        ctl._transfer(obs)
        path.append(ak.fk(ctl.cmd.arm[i], ctl.robot, k))
    assert ctl.phase[k] == 3                           # still lowering: no contact in the air
    path = np.array(path)
    d = np.asarray(p1) - np.asarray(p0)
    off = np.linalg.norm(np.cross(path - np.asarray(p0), d / np.linalg.norm(d)), axis=1)
    assert off.max() < 0.01                            # the commanded tips lie on the line
    assert path[-1] == pytest.approx(list(p1), abs=0.01) and ctl.glide[i] is None


def test_a_climb_at_the_guard_with_every_arm_lifted_places_the_arms_again():
    """The stability monitor stops the crawlers beyond guard_pitch and the rear booms bring the nose
    down; with every arm lifted clear nothing can, so the arms are placed again (walk)."""
    ctl, obs = _walking_clm()
    obs.pitch = ctl.cfg.guard_pitch + 0.05
    ctl.machine.go(obs.t, clm.CLIMB, "test")
    ctl.lifted = np.ones(4, bool)
    ctl.guarding, ctl.still_pitch, ctl.still_t = False, obs.pitch, 0.0
    ctl.cmd.flip[:] = [-0.5, -0.5, -0.8, -0.8]
    ctl._climb_nose(obs)
    assert ctl.state == clm.WALK and ctl.placing and ctl.queue == list(clm.GAIT_ORDER)
    assert ctl.cmd.flip[:2].tolist() == [ctl.cfg.flipper_start] * 2 and (ctl.cmd.flip[2:] >= 0).all()
    assert "every arm lifted clear" in ctl.machine.events[-1].reason


def _alone_in_a_climb(pitch: float, s: float):
    """A controller in the climb's state machine with every arm lifted clear (no climb physics)."""
    ctl, obs = _walking_clm()
    obs.pitch = pitch
    ctl.machine.go(obs.t, clm.CLIMB, "test")
    ctl.lifted, ctl.guarding = np.ones(4, bool), False
    ctl.still_pitch, ctl.still_t, ctl.s, ctl.s_release = pitch, 0.0, s, 0.45
    return ctl, obs


def test_a_stalled_climb_with_every_arm_lifted_places_the_arms_again():
    """Below the guard, past the release distance, the pitch held still for stall_time: the
    crawlers slip with no arm to help (a stall); a pitch that moves, a climb short of its release
    distance or an arm still down is not one."""
    n = int(round(_walking_clm()[0].cfg.stall_time / 0.02)) + 2

    def run(pitches, s, lifted=(True,) * 4):
        ctl, obs = _alone_in_a_climb(pitches[0], s)
        ctl.lifted[:] = lifted
        why = ""
        for k in range(n):
            obs.pitch = pitches[k % len(pitches)]
            why = why or ctl._stalled_alone(obs)
        return why

    assert run([0.74], s=0.6).startswith("pitch held at 0.74 rad")
    assert run([0.70, 0.74], s=0.6) == ""          # the nose moving: the body moves
    assert run([0.74], s=0.3) == ""                # not yet its release distance
    assert run([0.74], s=0.6, lifted=(True, True, False, True)) == ""   # a rear arm still down


def test_beyond_reach_matches_where_the_ik_stretches_the_arm():
    """``beyond_reach`` is true exactly where :func:`ik_f` cannot put the tip on its target."""
    robot = RobotConfig()
    rng = np.random.default_rng(0)
    for k in clm.ARMS:
        c = ak.ik_constants(robot, k)
        for p in rng.uniform([-1.4, -1.4, -1.0], [1.4, 1.4, 0.6], size=(200, 3)):
            q = np.array(ak.ik_f(*p.tolist(), c))
            err = np.linalg.norm(ak.fk(q, robot, k) - p)
            assert (err > 1e-6) == ak.beyond_reach(*p.tolist(), c), (k, p, err)


def test_an_arm_over_a_drop_deeper_than_its_reach_finds_no_ground():
    """Zoo step-down 0.6 m (deeper than the arm): the front arm lowering over the drop stops at full
    stretch; that is not a contact (the tip would press at the stretch forever, the gait waiting):
    it lowers on to the pit case, and the robot goes down the step."""
    zoo = get_system("zoo")
    r = zoo.run_trial(zoo.plan(methods=["octopus.clm"], instances=["step-down@0.6"], seeds=1)[0])
    assert r.status == "success"
    ev = [tuple(e) for e in r.info["events"]]
    assert any("pressed at full stretch" in e[3] for e in ev)
    assert any(e[3] == "no ground within reach (pit)" for e in ev)


def _pit_check(tau_elbow: float):
    """A walking CLM whose RR arm has just reached pit_depth (phase 4), held pit_hold with the given
    elbow torque."""
    ctl, obs = _walking_clm()
    k, i = "RR", clm.ARM_INDEX["RR"]
    ctl.phase[k], ctl.t3[i] = 4, 0.0
    obs.tau_elbow = np.array([0.0, 0.0, 0.0, tau_elbow])
    ctl.tip_r[i] = [-0.6, -0.6, -0.45]
    for _ in range(round(ctl.cfg.pit_hold / ctl.dt) + 1):
        ctl._transfer(obs)
    return ctl, obs, k, i


def test_the_pit_check_reads_the_elbow_a_resting_tip_presses_down():
    """At pit_depth with no contact signal the arm holds pit_hold, then: an elbow pressing down by
    more than contact_torque (a tip resting at full stretch) lands it; a free hang (holding the
    forearm up) is a pit, and a later rise of contact_torque over that hang lands it."""
    ctl, obs, k, i = _pit_check(+74.0)
    assert ctl.phase[k] == 0 and ctl.landing[i] and "held at full stretch" in ctl.stretched_on[i]
    ctl, obs, k, i = _pit_check(-6.0)
    assert ctl.phase[k] == 0 and not ctl.landing[i] and ctl.in_pit[i]
    assert ctl.machine.events[-1].reason == "no ground within reach (pit)"
    obs.tau_elbow = np.array([0.0, 0.0, 0.0, -6.0 + ctl.cfg.contact_torque - 1.0])
    ctl._support(obs, 0.0)
    assert not ctl.landing[i]                           # a rise below contact_torque: still hanging
    obs.tau_elbow = np.array([0.0, 0.0, 0.0, -6.0 + ctl.cfg.contact_torque + 1.0])
    ctl._support(obs, 0.0)
    assert ctl.landing[i] and "ground under a pit arm" in ctl.stretched_on[i]
    ctl, obs, k, i = _pit_check(-90.0)                  # wedged, not hanging: no reference to watch
    assert not ctl.in_pit[i] and not ctl.landing[i]


def test_the_front_flipper_feeler_reads_the_advance_from_its_tip_against_the_face():
    """flipper_feel: a front flipper pushed up a riser's face turns from q1 to q2 as the body
    advances L (cos q1 - cos q2) (level body); above the top's edge, or not pushed, it reads nothing;
    upright at its limit against the face it reads 0."""
    ctl, obs = _walking_clm()
    rb, cfg = ctl.robot, ctl.cfg
    ctl.contact = [True, True, True, True]
    ctl.tip_r = np.array([[0.7, 0.5, 0.35], [0.7, -0.5, 0.35], [-0.5, 0.5, -0.05], [-0.5, -0.5, -0.05]])
    pushed = np.array([-30.0, -30.0, 0.0, 0.0])

    def feel(q, tau=pushed):
        ctl._tip_c, ctl._att = None, (0.0, 0.0)
        obs.q_flip, obs.tau_flip = np.array([q, q, 0.0, 0.0]), tau
        return ctl._feel(obs)

    assert feel(0.40) == math.inf                       # the first reading has nothing to compare
    assert feel(0.45) == pytest.approx(rb.flipper_len * (math.cos(0.40) - math.cos(0.45)), rel=1e-12)
    assert feel(0.50, np.zeros(4)) == math.inf          # not pushed: no reading
    ctl.tip_r[:2, 2] = 0.0                              # the top at the tip's height: the run rides the edge
    feel(0.50)
    assert feel(0.55) == math.inf
    ctl.tip_r[:2, 2] = 0.35
    feel(cfg.a0 - 0.2)
    assert feel(cfg.a0 - 0.05, np.zeros(4)) == 0.0      # upright against the face: the body stands
