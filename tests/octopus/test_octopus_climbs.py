"""OCTOPUS climbs (issue 21): terrace by terrace, the riser stall, the block ride-over, CCM's abort
and its tip-back (issue 28, piece 5)."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from terrabench.benchmark.trial import TrialSpec
from terrabench.sim.checks import roll_pitch, turned_over
from terrabench.systems.octopus.ccm import tip_back_angle
from terrabench.systems.octopus.robot import RobotConfig
from terrabench.systems.octopus.scenarios import SYSTEM
from terrabench.systems.octopus.task import TIP_BACK_HOLD, TURN_OVER_PITCH, OctopusTask


def _run(method: str, instance: str, seed: int = 0, **overrides):
    return SYSTEM.run_trial(SYSTEM.trial_spec(method, instance, seed, overrides))


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


def test_ccm_tips_back_on_the_400_mm_step():
    """The paper's CCM failure as physics: on step-400 the COG passes behind the rearmost loaded
    contact (the rear flipper tips) with the nose up and rising: ``tipped_back``, well below the
    old 1.2 rad stop; the controller's abort at its own tip-back angle comes within the hold."""
    r = _run("ccm", "step-400")
    assert r.status == "tipped_back", r.info["reason"]
    tb = r.info["tip_back"]
    assert "behind the rearmost loaded contact" in r.info["reason"]
    assert 0.8 < tb["pitch"] < 1.0 and tb["behind_m"] > 0 and tb["behind_held_m"] > tb["behind_m"]
    assert tb["t_held"] - tb["t"] == pytest.approx(TIP_BACK_HOLD, abs=1e-6) and tb["pitch_held"] > tb["pitch"]
    ts = r.timeseries
    assert ts["pitch"].max() < 1.2 and ts["t"][-1] == pytest.approx(tb["t_held"] + 0.02, abs=1e-6)
    (ab,) = _mode_events(r, "abort")
    assert "tip-back" in ab[3] and tb["t"] <= ab[0] <= tb["t_held"]


def test_ccm_without_the_rear_push_is_not_tipped_back():
    """``ccm.rear_push=0``: the nose rises past 1.2 rad (labelled ``turned_over`` at 15.6 s by the
    old angle stop) with the COG still ahead of the rear contact: not tipped back; the abort
    stops the robot against the riser and it ends ``stuck``."""
    r = _run("ccm", "step-400", **{"ccm.rear_push": 0.0})
    assert r.status == "stuck" and "tip_back" not in r.info
    assert 1.2 < r.metrics["max_pitch"] < TURN_OVER_PITCH


def _rule_stub():
    """An object with what :meth:`OctopusTask._tip_back` reads: the chassis x axis (a view, as
    in the task), the chassis attitude (from its quaternion), the run state."""
    st = SimpleNamespace(chassis=0, data=SimpleNamespace(xquat=np.zeros((1, 4))), _ax=np.zeros(3),
                         _behind=None, _rear_prev=(math.nan, False), _tipped=None,
                         _rear_end=np.array([True, False]))  # geom 0: a rear end (flipper tip), 1: a track run
    st.attitude = lambda: roll_pitch(st.data.xquat[0])

    def row(t, pitch, cog_x, contacts_x, rear_geom=0):
        # nose up = a rotation about -y: x axis (cos p, 0, sin p); the first contact is on rear_geom
        st.data.xquat[0] = (math.cos(pitch / 2), 0.0, -math.sin(pitch / 2), 0.0)
        st._ax[:] = (math.cos(pitch), 0.0, math.sin(pitch))
        loaded = np.array([[x, y] for x in contacts_x for y in (-0.3, 0.3)])
        geoms = np.array([rear_geom if i < 2 else 1 for i in range(len(loaded))])
        OctopusTask._tip_back(st, t, loaded, geoms, np.array([cog_x, 0.0]))
        return st._tipped

    return st, row


def test_tip_back_rule_fires_when_the_cog_passes_behind_the_rear_contact():
    """The COG crosses the rear contact (0.0 m) at 1 cm a row with the nose rising: the event
    holds TIP_BACK_HOLD after the crossing row, not before; its figures are the crossing's."""
    st, row = _rule_stub()
    p, t = 0.85, 0.0
    for k, cog in enumerate((0.03, 0.02, 0.01, -0.005, -0.015)):
        t, p = 0.1 * k, p + 0.02
        assert row(t, p, cog, (0.0, 0.5)) is None
    ev = row(0.5, p + 0.02, -0.025, (0.0, 0.5))
    assert ev is not None and ev["t"] == pytest.approx(0.3) and ev["behind_m"] == pytest.approx(0.005)
    assert ev["t_held"] - ev["t"] >= TIP_BACK_HOLD - 1e-9 and "0.5 cm behind" in ev["reason"]


def test_tip_back_rule_ignores_stable_high_pitch_unloading_and_nose_down():
    """Not tipped back: a high pitch with the COG ahead of the rear contact (statically stable,
    as CCM without the rear push at 1.2 rad); the rear contact unloaded for a row or for long
    (the rearmost loaded contact jumps 0.45 m ahead: another contact carries the load, the COG
    did not pass one); the COG behind the contact with the nose falling (a recovery); nose down;
    the COG passing behind an edge under the track run (a seesaw: the track behind lands)."""
    _, row = _rule_stub()
    assert all(row(0.1 * k, 1.3, 0.09, (0.0, 0.5)) is None for k in range(10))
    _, row = _rule_stub()
    for k in range(10):
        rear = (0.45,) if k >= 3 else (0.0, 0.45)   # from row 3 on only the front contact is loaded
        assert row(0.1 * k, 0.1 + 0.02 * k, 0.05, rear) is None
    _, row = _rule_stub()
    assert row(0.0, 0.9, 0.01, (0.0, 0.5)) is None
    assert all(row(0.1 * k, 0.9 - 0.01 * k, -0.01, (0.0, 0.5)) is None for k in range(1, 10))
    _, row = _rule_stub()
    assert all(row(0.1 * k, 0.001 + 0.01 * k, 0.03 - 0.01 * k, (0.0, 0.5), rear_geom=1) is None for k in range(10))
    _, row = _rule_stub()
    assert row(0.0, -0.5, 0.01, (0.0, 0.5)) is None
    assert all(row(0.1 * k, -0.5 - 0.02 * k, -0.01 - 0.01 * k, (0.0, 0.5)) is None for k in range(1, 10))


def test_turned_over_keeps_the_pitch_only_as_a_last_resort():
    """The octopus task's attitude guard: |roll| on protocol.turn_over, |pitch| on TURN_OVER_PITCH."""
    assert turned_over(0.0, 1.5, 1.2, TURN_OVER_PITCH) is None
    assert turned_over(1.25, 0.0, 1.2, TURN_OVER_PITCH)[0] == "turned_over"
    status, reason = turned_over(0.0, 1.65, 1.2, TURN_OVER_PITCH)
    assert status == "turned_over" and "1.65" in reason and "1.6" in reason
    assert turned_over(0.0, 1.25, 1.2) is not None   # other systems: one limit for both


def test_clm_climbs_a_low_riser_where_the_flipper_rule_stalls():
    """150 mm: the edge presses near the flipper pivot and the torque rule stalls below its limit
    (this trial was `stuck` at the riser); a steep front flipper that stopped rising starts the climb."""
    r = _run("clm", "sweep-h150")
    assert r.status == "success"
    c = [e for e in _mode_events(r, "climb") if e[1] == "walk"]   # started from walking (not resumed)
    assert len(c) == 1 and "steep" in c[0][3]


def test_clm_climbs_the_terraces_one_by_one():
    """terrace2-front: terrace by terrace, H_EST estimated from the four tips: the first climb is
    for the lower terrace (0.2 m) and ends on it; the 0.2 m second riser, below the flippers'
    250 mm ("OCTOPUS can climb the step which height is lower than 250 mm ... without using arms"),
    is mounted by the walk's crawlers and flippers or by a second climb (6 of 20 seeds walking, 14
    by a second climb, since the climbs are not resumed); the robot is on the 0.4 m top at the end."""
    r = _run("clm", "terrace2-front")
    assert r.status == "success"
    climbs = [e for e in _mode_events(r, "climb") if e[1] == "walk"]   # fresh climbs, not resumed ones
    h = [float(e[3].split("H_EST = ")[1].split(" m")[0]) for e in climbs]
    assert len(climbs) >= 1 and h[0] == pytest.approx(0.2, abs=0.03)
    assert all(x > 0.05 for x in h[1:])
    ts = r.timeseries
    after_first = ts["t"] > _mode_events(r, "walk")[1][0]   # walking again after the first release
    z_mid = ts["z"][after_first][0]
    assert 0.25 < z_mid < 0.4     # on the lower terrace: chassis origin ~0.2 + pulley radius above the floor


@pytest.mark.slow
def test_clm_climbs_the_terraces_from_the_side():
    """One crawler meets each edge before the other, so the robot rolls ("the heights of terrace
    under left side and right side crawlers are not same", roll -0.25 rad [P]); from the front it
    does not."""
    side, front = _run("clm", "terrace2-side"), _run("clm", "terrace2-front")
    assert side.status == front.status == "success"
    assert abs(side.metrics["max_roll"]) > 0.15 > 0.1 > abs(front.metrics["max_roll"])


def test_the_side_task_meets_the_edges_at_its_angle():
    """terrace2-side: the terraces are turned by side_yaw_deg and the robot is not (it was turned
    with them once, which made the task the front one in another frame); its start stays on the
    approach axis start_distance behind the first edge, and the terraces are wide enough for the
    path's drift across the axis."""
    from terrabench.systems.octopus.task import SIDE_TERRACE_WIDTH, layout

    cfg = SYSTEM.resolve_config({"scene.side_yaw_deg": 30.0})
    side, front = layout("terrace2-side", cfg, 0), layout("terrace2-front", cfg, 0)
    assert front.start_yaw == front.axis_yaw == 0.0
    assert side.axis_yaw == pytest.approx(math.radians(30.0)) and side.start_yaw == 0.0
    c, s_ = math.cos(side.axis_yaw), math.sin(side.axis_yaw)
    assert side.start[0] * c + side.start[1] * s_ == pytest.approx(-cfg.scene.start_distance)
    # the tracks (0.22 m either side of the centre line) reach the first edge line x cos + y sin = 0
    # 2 * 0.22 tan(30 deg) = 0.25 m apart along the drive
    y = cfg.robot.track_y
    x_left, x_right = (-(side.start[1] + dy) * s_ / c for dy in (y, -y))
    assert abs(x_left - x_right) == pytest.approx(2 * y * math.tan(math.radians(30.0)))
    assert all(b.half[1] == SIDE_TERRACE_WIDTH / 2 for b in side.boxes)


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
    # the arm the crawlers wait for goes first, and an arm lifted over the block lands where it
    # was sent, not on the block's top beside it: the tracks stop on 11 % of walking ticks (40 %
    # before either rule)
    assert any(e[3] == "out of range: its turn comes first" for e in ev)
    assert r.metrics["tracks_stopped_share"] < 0.2



def test_the_terraces_are_climbed_one_by_one_without_a_resumed_climb_on_lifted_arms():
    """terrace2-front seed 0: with resumes (the earlier default, 3) the release's nose rise on the
    short tread resumes the climb, every arm lifts clear and the robot teeters over the first edge
    on its tracks alone (static margin < 0); without (the default) the walk re-places the arms and
    mounts the second riser (or a fresh climb does), and the static margin stays positive."""
    fresh = _run("clm", "terrace2-front", 0)
    resumed = _run("clm", "terrace2-front", 0, **{"clm.max_resumes": 3})
    assert fresh.status == resumed.status == "success"
    assert not any(e[1] == "release" and e[2] == "climb" for e in _events(fresh))
    assert any(e[1] == "release" and e[2] == "climb" for e in _events(resumed))
    assert [e for e in _mode_events(fresh, "climb") if e[1] == "walk"]   # fresh climbs only
    assert resumed.metrics["margin_min_m"] < 0.0 < fresh.metrics["margin_min_m"]

def test_a_case_1_foothold_out_of_range_lifts_clear_and_the_crawlers_drive_on():
    """block-500 seed 1: the RR arm's target lies beside the block's face, out of the arm's reach
    from above the 0.5 m top, so every transfer stops on the top (arm stop case 1, 0.26 m outward,
    0.78 m from the mount) and its foothold leaves the range after a few cm. Waiting for it
    (``blocked_clear`` off) stops the crawlers during the other arms' transfers; lifting it clear
    lets them drive on: fewer stopped ticks, an earlier pass, the same outcome."""
    on = _run("clm", "block-500", 1)
    off = _run("clm", "block-500", 1, **{"clm.blocked_clear": False})
    assert on.status == off.status == "success"
    cleared = [e for e in _events(on) if "case-1 foothold out of range: lifted clear" in e[3]]
    assert cleared and all(e[1].endswith(".support") for e in cleared)
    assert not any("case-1 foothold" in e[3] for e in _events(off))
    assert on.metrics["tracks_stopped_share"] < 0.5 * off.metrics["tracks_stopped_share"]
    assert on.metrics["sim_time"] < off.metrics["sim_time"]

@pytest.mark.slow
def test_clm_does_not_walk_itself_over_a_riser_beyond_its_reach():
    """550 mm (beyond the arms): without the walk's pitch guard CLM turned over here (77.8 s)."""
    r = _run("clm", "sweep-h550")
    assert r.status != "turned_over" and abs(r.metrics["max_pitch"]) < 1.0


def test_clm_nose_climb_pitches_up_on_loaded_crawlers():
    """The climb of the paper's Fig. 9 (``clm.nose_climb``, the default): on step-400 the front booms
    lift the nose toward ``climb_pitch`` while the rear crawlers stay on the ground, so the crawlers
    keep a far larger share of the load through the climb than in the level four-arm hoist
    (``nose_climb=false``, whose every arm carries the robot at once: share 0 measured), and the
    robot still gets on top."""
    hoist = _run("clm", "step-400", **{"clm.nose_climb": False})
    nose = _run("clm", "step-400")
    assert nose.status == "success" and hoist.status == "success"
    assert any("front pulley" in e[3] and "over the top" in e[3] for e in _events(nose))
    assert 0.45 < nose.metrics["max_pitch_rad"] < 0.8 and hoist.metrics["max_pitch_rad"] < 0.35

    def climb_share(r, q):
        m, sh = np.asarray(r.timeseries["mode"]), np.asarray(r.timeseries["track_share"])
        return float(np.percentile(sh[(m == 1) & np.isfinite(sh)], q))

    # the crawlers are never unloaded through the nose climb (its 5th percentile and its least
    # share above 0); the hoist carries the robot on its arms at some climb instants (share 0).
    # The 5th percentile is 0.28 since the front arms stay supports on the top (front_support),
    # above 0.3 when they lifted clear as the front came over
    assert climb_share(nose, 5) > 0.25 > climb_share(hoist, 5)
    assert nose.metrics["crawler_load_share_min"] > 0.05 > hoist.metrics["crawler_load_share_min"]


def test_clm_keeps_its_crawlers_running_after_a_release_on_a_short_tread():
    """terrace2-front seed 0: the first climb releases with the rear still below the edge (the
    front at the second riser, the 0.45 m tread is shorter than the robot). The crawlers keep
    their speed while the arms are placed again (``place_pitch`` pi/2, the default) and the robot
    gets on top; waiting with the body pitched until the four arms are down (0.15, the earlier
    default) also succeeds but stops the tracks on 14 % of the walking ticks (18 % at a fixed
    crawler speed, ``gait_pace`` off; the default stops them on 5.8 %, rear footholds out of range while
    the arms are placed again after the first climb, measured 2026-12-06). The wait is
    run with the climb of its time (front arms lifted clear once over, no roll levelling, resumed
    climbs): with the front arms kept as supports, or without resumes, it times out here (150 s,
    measured 2026-12-05)."""
    drives = _run("clm", "terrace2-front")
    waits = _run("clm", "terrace2-front", **{"clm.place_pitch": 0.15, "clm.front_support": False,
                                             "clm.roll_level": 0.0, "clm.max_resumes": 3})
    assert drives.status == "success" and waits.status == "success"
    assert drives.metrics["tracks_stopped_share"] < 0.1 < waits.metrics["tracks_stopped_share"]


def test_front_support_and_roll_levelling_keep_the_step_climb_level_and_stable():
    """step-400 seed 0: the front arms stay supports on the top once the front is over (the paper
    releases the arms after S > L, Fig. 9f-h) and the rear lift levels the roll from the IMU. Without
    both the robot teetered on the edge on its right track and the rear tips (static margin 0.02 m)
    and rolled 0.13 rad while one rear arm lifted the rear alone; with both, the paper's figures
    (roll 0.03 rad, margin 0.15 m) are approached."""
    new = _run("clm", "step-400")
    old = _run("clm", "step-400", **{"clm.front_support": False, "clm.roll_level": 0.0})
    assert new.status == "success" and old.status == "success"
    assert abs(new.metrics["max_roll"]) < 0.05 < 0.1 < abs(old.metrics["max_roll"])
    assert new.metrics["margin_min_m"] > 0.1 > 0.05 > old.metrics["margin_min_m"]
    # the front arms were not lifted clear on unloading: no such event before the release
    release = _mode_events(new, "release")[0][0]
    assert not [e for e in _events(new) if e[0] < release and e[1].startswith(("LF", "RF"))
                and "lifted clear" in e[3]]


def test_the_release_unloads_the_front_arms_so_the_crawlers_settle_on_the_top():
    """The paper releases "the flippers and arms" once H > H_EST and S > L (Fig. 9f-h). A front arm
    kept pressing on the top through the release held the nose up on a tripod with the edge
    (terrace2-front seed 2, the second terrace: pitch 0.06 rad, the COG outside the tripod of the
    right track on the edge and the LF tip, static margin -0.022 m) and slid as the crawlers drove
    on (step-400: tip slip 0.29 m on every one of 20 seeds, 0.22 m with the unload). With
    ``release_unload`` each such arm unloads and lifts clear, and the body settles level. (Measured
    with ``mount_level`` off, as the cause was found: the level start alone also lifts this climb's
    rear higher before the release, which hides the tripod; and at the fixed crawler speed of that
    time, ``gait_pace`` off: the paced walk reaches this riser in another gait phase.)"""
    was = {"clm.mount_level": False, "clm.gait_pace": False}
    new = _run("clm", "terrace2-front", 2, **was)
    old = _run("clm", "terrace2-front", 2, **was, **{"clm.release_unload": False})
    assert new.status == "success" and old.status == "success"
    assert new.metrics["margin_min_m"] > 0.0 > old.metrics["margin_min_m"]
    unloaded = [e for e in _events(new) if e[3] == "release: unloaded, lifted clear"]
    assert unloaded and all(e[1][:2] in ("LF", "RF") for e in unloaded)
    assert not [e for e in _events(old) if "release: unloaded" in e[3]]
    step_new = _run("clm", "step-400")
    step_old = _run("clm", "step-400", **{"clm.release_unload": False})
    assert step_new.metrics["tip_slip_max_m"] < step_old.metrics["tip_slip_max_m"] - 0.03


def test_a_climb_started_nose_up_takes_its_ground_as_level():
    """terrace2-front seed 8: the second terrace's climb starts from the nose-up trigger (the
    crawlers already up the second riser, pitch 0.46 rad). Read as the ground's pitch, that
    latched the rear "up" at once and ended the rear lift while the nose was still up: the
    release came at 0.35 rad with the rear dropping onto the first edge (static margin -0.000 m).
    With the ground taken as level (``mount_level``) the rear arms lift the rear until the body is
    level and the margin stays positive. (At the fixed crawler speed of the time, ``gait_pace``
    off: the paced walk reaches this riser in another gait phase.)"""
    new = _run("clm", "terrace2-front", 8, **{"clm.gait_pace": False})
    old = _run("clm", "terrace2-front", 8, **{"clm.mount_level": False, "clm.gait_pace": False})
    assert new.status == "success" and old.status == "success"
    assert new.metrics["margin_min_m"] > 0.05 > 0.01 > old.metrics["margin_min_m"]
    assert new.metrics["max_pitch"] < old.metrics["max_pitch"]


def test_the_walk_paces_its_crawlers_instead_of_stopping_them():
    """block-500 seed 0: over the block the transfers take longer (landings re-lowered, collisions,
    a blocked swing) and at a fixed crawler speed a foothold left its range during another arm's
    transfer: the crawlers stopped on 11 % of walking ticks. Slowed so that no foothold need leave
    its range before its turn (``gait_pace``, the default, paced by the transfers the controller
    timed) they stop on fewer than 5 %, run slower on average but never faster than the fixed
    speed, and the robot still passes."""
    on = _run("clm", "block-500")
    off = _run("clm", "block-500", **{"clm.gait_pace": False})
    assert on.status == off.status == "success"
    assert on.metrics["tracks_stopped_share"] < 0.05 < 0.08 < off.metrics["tracks_stopped_share"]
    # slowed, not stopped: the mean speed over the walk stays near the fixed one's, and the paced
    # walk never drives faster than the fixed one does
    v_on, v_off = on.metrics["walk_speed_mean_mps"], off.metrics["walk_speed_mean_mps"]
    assert 0.5 * v_off < v_on
    assert np.nanmax(on.timeseries["track_cmd"]) <= np.nanmax(off.timeseries["track_cmd"]) + 1e-12


def test_an_arm_resting_on_the_top_at_full_stretch_is_a_foothold_not_a_pit():
    """terrace2-front seed 15: after the first release the nose-up body (0.46 rad) lowers the LF arm
    onto the second top at full stretch, where the stretch hides the torque jump; without the pit
    check the arm was called a pit and left hanging on the top, and its roller tip rolled 0.74 m
    with the body until its next turn (the trial's walk-phase tip slip). With it (``pit_hold``)
    the arm presses its elbow down at the end of the hold, lands there and holds its foothold;
    the drop deeper than the arm (the zoo's step-down, test_octopus.py) is still a pit."""
    on = _run("clm", "terrace2-front", seed=15)
    off = _run("clm", "terrace2-front", seed=15, **{"clm.pit_hold": 0.0})
    assert on.status == off.status == "success"
    assert any("held at full stretch" in e[3] for e in _events(on))
    assert not any("held at full stretch" in e[3] for e in _events(off))
    assert off.metrics["tip_slip_walk_max_m"] > 0.5
    assert on.metrics["tip_slip_walk_max_m"] < 0.25


def test_the_front_flippers_read_the_bodys_advance_against_the_riser():
    """step-400 seed 0: from ~15 s the front flippers are pushed up the riser's face and the body
    advances at 30-90 % of the crawler command, so footholds moved by the crawler odometry drag
    the roller tips back (walk-phase tip slip ~0.11 m). Read from the flippers' tips against the
    face (``flipper_feel``), the advance moves the footholds with the body: the slip halves."""
    on = _run("clm", "step-400", **{"clm.flipper_feel": True})
    off = _run("clm", "step-400")
    assert on.status == off.status == "success"
    assert off.metrics["tip_slip_walk_max_m"] > 0.09
    assert on.metrics["tip_slip_walk_max_m"] < 0.6 * off.metrics["tip_slip_walk_max_m"]


def test_a_pit_arm_lands_when_the_ground_comes_up_to_it():
    """A front arm finds no ground and hangs free (-5 N m at its elbow) with the nose up ~0.55 rad;
    the nose then drops onto the tread and brings the top up to the hanging tip, which rolled 0.4-0.8
    m with the body (found on terrace2-side seed 4 when that task was the front task turned; here
    terrace2-front seed 11: walk slip 0.64 m without the rule). The pit arm's elbow torque rising
    ``contact_torque`` above its free hang lands it there."""
    on = _run("clm", "terrace2-front", seed=11)
    off = _run("clm", "terrace2-front", seed=11, **{"clm.pit_hold": 0.0})
    assert on.status == off.status == "success"
    assert any("ground under a pit arm" in e[3] for e in _events(on))
    assert off.metrics["tip_slip_walk_max_m"] > 0.35
    assert on.metrics["tip_slip_walk_max_m"] < 0.25


def test_the_step_not_the_booms_cap_sets_the_climbs_pitch():
    """step-400 seed 0: the front booms lift the nose up to ``climb_pitch`` and hold; the crawlers
    driving up the riser and the rear flippers' push raise it the rest of the way (Fig. 9e). So
    below the step's own pitch the largest pitch does not follow the cap (0.587-0.590 rad over 20
    seeds for caps 0.3-0.55), and a cap above it is read back (0.85 -> 0.81); the default, the
    paper's measured 0.6, sits 0.013 rad above the step's pitch and holds the nose at 0.603."""
    runs = {cap: _run("clm", "step-400", **{"clm.climb_pitch": cap}) for cap in (0.3, 0.45, 0.55, 0.85)}
    assert all(r.status == "success" for r in runs.values())
    pitch = {cap: r.metrics["max_pitch_rad"] for cap, r in runs.items()}
    low = [pitch[c] for c in (0.3, 0.45, 0.55)]
    assert max(low) - min(low) < 0.01
    assert min(low) > 0.55 + 0.02  # above every one of those caps
    assert pitch[0.85] > max(low) + 0.15  # a cap above the step's pitch is read back


def test_the_face_centre_holds_the_front_pulley_on_the_face_and_the_rear_on_the_ground():
    """clm.face_centre: a small turn of the body about the returned centre moves the front pulley
    centre along the riser's face (its level-frame x still to second order) and the rear contact
    along the ground (its level-frame z still), at any pitch and rear contact; about the rear contact
    (the foothold rule's default centre) the front pulley centre moves into the face to first order."""
    from terrabench.systems.octopus.clm import face_centre

    rc, rng = RobotConfig(), np.random.default_rng(3)

    def level(x, z, p):  # {R} -> the level frame (x, z), the IMU pitch p nose-up
        return x * math.cos(p) - z * math.sin(p), x * math.sin(p) + z * math.cos(p)

    def turned(pt, c, p, d):  # a body point after the body turns by d about the level-frame centre c
        x, z = level(*pt, p)
        cx, cz = level(*c, p)
        cs, sn = math.cos(d), math.sin(d)
        return cx + (x - cx) * cs - (z - cz) * sn, cz + (x - cx) * sn + (z - cz) * cs

    d = 1e-4  # a turn this small: what stays still does to second order (~d^2 x 0.4 m), a first-order
    # move is d x ~0.1 m or more
    for _ in range(200):
        p = float(rng.uniform(0.0, 0.9))
        rear = (float(rng.uniform(-0.6, -0.2)), float(rng.uniform(-0.2, -0.05)))
        front = (rc.pulley_x, 0.0)
        c = face_centre(*rear, p, rc.pulley_x)
        assert abs(turned(front, c, p, d)[0] - level(*front, p)[0]) < 0.01 * d
        assert abs(turned(rear, c, p, d)[1] - level(*rear, p)[1]) < 0.01 * d
        # about the rear contact the front pulley centre moves back and forth by ~d x its height over it
        rise = level(*front, p)[1] - level(*rear, p)[1]
        assert abs(turned(front, rear, p, d)[0] - level(*front, p)[0]) == pytest.approx(d * rise, rel=1e-3)


def test_the_face_centre_holds_the_tips_through_the_nose_lift(octopus_begin):
    """step-400 seed 0, from the climb's start to the front over the top (the nose lift, Fig. 9e):
    turning the footholds about the rear contact (the default) lets every tip drift 10-21 cm with
    the body; about the body's instantaneous centre (``clm.climb_face_pivot``) each stays within
    6 cm (docs/octopus.md, "The nose lift's pivot")."""
    from terrabench.systems.octopus.clm import CLIMB
    from terrabench.systems.octopus.robot import ARMS, Names

    def drift(face: bool) -> list[float]:
        _, ctl, ep, obs, stop = octopus_begin("clm", {"protocol.timeout": 40.0, "clm.climb_face_pivot": face})
        tips = [ep.model.body(Names.tip(k)).id for k in ARMS]
        start = None
        while stop is None and obs.t < 40.0:
            cmd = ctl(obs)
            if start is None and ctl.machine.state == CLIMB:
                start = ep.data.xpos[tips, :2].copy()
            if start is not None and ctl.over:
                assert not any(ctl.lifted)
                return np.linalg.norm(ep.data.xpos[tips, :2] - start, axis=1).tolist()
            obs, stop = ep.step(cmd)
        raise AssertionError(f"no climb over the top by {obs.t:.1f} s")

    held, dragged = drift(True), drift(False)
    assert max(held) < 0.06
    assert min(dragged) > 0.09 and max(dragged) > 0.2


def test_the_climbs_stages_run_in_order_and_the_rear_lift_loads_the_arms():
    """step-400 seed 0: the stored ``climb_stage`` runs lift -> rear lift -> drive on -> release,
    once each, inside the climb and release modes. The crawlers carry most of the normal load
    while the nose lifts (their friction on the riser moves the body, Fig. 9e) and under a third
    in the rear lift, where eq. 28's rear booms lift the rear crawlers off the lower ground while
    the front booms press on the top (``climb_press``); without that press the crawlers carry
    about half there."""
    from terrabench.systems.octopus.clm import CLIMB, DRIVE_ON, LIFT, REAR_LIFT, RELEASE, RELEASING

    r = _run("clm", "step-400")
    assert r.status == "success"
    ts = r.timeseries
    stage, mode = np.nan_to_num(ts["climb_stage"]), ts["mode"]
    runs = [int(k) for i, k in enumerate(stage) if k and (i == 0 or stage[i - 1] != k)]
    assert runs == [LIFT, REAR_LIFT, DRIVE_ON, RELEASING]
    assert np.all(np.isin(mode[stage > 0], (CLIMB, RELEASE))) and np.all(stage[mode == RELEASE] == RELEASING)
    m = r.metrics
    assert m["crawler_load_share_lift"] > 0.5 > 0.35 > m["crawler_load_share_rear_lift"]
    unpressed = _run("clm", "step-400", **{"clm.climb_press": 0.0}).metrics["crawler_load_share_rear_lift"]
    assert unpressed > 0.45
    # the climb mode's one run is the three stages in turn: its mean share lies between theirs
    stages = [m[f"crawler_load_share_{k}"] for k in ("lift", "rear_lift", "drive_on")]
    assert min(stages) < m["crawler_load_share_phase_min"] < max(stages)
