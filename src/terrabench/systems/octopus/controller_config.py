"""The settings of the two OCTOPUS controllers: CLM (compound locomotion, :mod:`.clm`) and CCM
(crawlers only, :mod:`.ccm`); sections ``clm`` and ``ccm`` of :class:`~terrabench.systems.
octopus.config.OctopusConfig`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from terrabench.config import param


@dataclass(frozen=True)
class CLMConfig:
    """CLM parameters (rad per 0.02 s tick unless said otherwise)."""

    track_speed: float = param(0.06, gt=0, unit="m/s",
                               doc="crawler surface speed in compound mode (walking); the walk's pitch guard "
                                   "(guard_pitch) backs off at minus this [S 'fixed and low'; R: a foothold "
                                   "window (targets x to reach_min: 0.55 m front, 0.45 m rear) over the four-"
                                   "transfer gait cycle (~9 s measured on flat) gives 0.05-0.06 m/s; at 0.1 the "
                                   "tracks waited on 26 % of walking ticks (step-400), at 0.06 on 2.3 %; the "
                                   "climb's speed, so the crawlers run at one speed]")
    climb_track_speed: float = param(0.06, gt=0, unit="m/s",
                                     doc="crawler speed while climbing a step (lift, drive and release); the "
                                         "travel S past the edge counts at this speed")
    sigma: tuple[float, float, float] = param((0.05, 0.45, 0.45), length=3, ge=0, unit="m",
                                              doc="(sigma1, sigma2, sigma3) terrain-case thresholds on the front "
                                                  "less rear tip heights of each side: flat below sigma1, up-step "
                                                  "between sigma1 and sigma2, down-step between -sigma3 and -sigma1")
    t0: float = param(40.0, gt=0, unit="N m",
                      doc="flipper torque threshold T0 of the front-flipper torque rule: below it a flipper holds "
                          "its angle")
    d_a: float = param(0.02, gt=0, unit="rad/tick",
                       doc="flipper step dA of the torque rule: a torque beyond T0 moves the flipper by this a tick, "
                           "against the torque's sign")
    a0: float = param(1.4835, ge=-math.pi, le=math.pi, unit="rad",
                      doc="front flipper limit A0 (85 deg): at it the torque rule lowers the flipper by dB; a front "
                          "flipper within 0.1 rad of it, with an up-step sensed, starts a climb")
    d_b_flip: float = param(0.02, gt=0, unit="rad/tick",
                            doc="flipper step dB of the torque rule at the limit A0 (the flipper is lowered)")
    flipper_start: float = param(0.5, ge=-math.pi, le=math.pi, unit="rad",
                                 doc="front flipper angle on flat ground, at the start and after a release; the "
                                     "rear flippers start at 0")
    arm_ab: float = param(-0.6, ge=-math.pi, le=math.pi, unit="rad",
                          doc="boom lift angle A_B of a transfer (our sign: < 0 is up); extra_lift higher after a "
                              "blocked swing, never within 0.05 rad of the boom's upper stop")
    d_swing: float = param(0.04, gt=0, unit="rad/tick", doc="swing step dA of a transfer (its swing phase)")
    d_lift: float = param(0.04, gt=0, unit="rad/tick",
                          doc="elbow step dB of a transfer's lift phase (the boom follows k_boom; the lowering "
                              "follows lower_dz)")
    k_boom: float = param(0.15, ge=0, unit="1/tick",
                          doc="boom gain K of eqs. 19-21: a tick of the lift phase commands the boom K of the way "
                              "from its measured angle to A_B (plus 0.02 rad up)")
    contact_torque: float = param(20.0, gt=0, unit="N m",
                                  doc="elbow-torque change from its free-motion reference (tau_filter) that signals "
                                      "the contact of a lowering tip")
    hit_torque: float = param(45.0, gt=0, unit="N m",
                              doc="elbow-torque rise of a supporting arm above its value when it settled that signals "
                                  "a collision: that arm is transferred next")
    press: float = param(0.005, ge=0, unit="m",
                         doc="a supporting (or landing) tip's target sits this far below its measured height: a press "
                             "of bounded force, so the crawlers carry most of the load (eqs. 22-27, "
                             ":meth:`.clm.CLMController._support`)")
    arm_moving: bool = param(True,
                             doc="supporting arms follow the body (eqs. 22-27: each foothold moves back in {R} by "
                                 "the crawler travel); False (a control for the tests) keeps each foothold's x "
                                 "fixed in {R}, so the tips roll with the body")
    reach_min: tuple[float, float] = param((0.2, -0.9), length=2, unit="m",
                                           doc="(front, rear) arms: a foothold behind this x in {R} is out of range: "
                                               "the crawlers wait for its transfer")
    reach_max: float = param(0.8, gt=0, unit="m",
                             doc="a foothold farther than this from its arm's mount, horizontally, is out of range "
                                 "too (l1 + l2 = 0.9 m reaches 0.87 m at the ground's depth)")
    lower_dz: float = param(0.01, gt=0, unit="m/tick",
                            doc="descent of a lowering tip's target per tick (0.5 m/s), three times that while more "
                                "than 0.15 m above the target height")
    relower_dz: float = param(0.08, ge=0, unit="m",
                              doc="a landed tip that goes on down this far below where it stopped while pressing "
                                  "was not in contact (a torque or tilt transient in the air): it lowers again "
                                  "(0 = off: it presses down at the servo's pace until it settles, 1-3.7 s for the "
                                  "10 of 23 false landings of block-500 seed 0); d_d, the arm stop case's height "
                                  "threshold (docs/octopus.md, 'Tracks stopped')")
    blocked_clear: bool = param(True, doc=(
        "an arm whose last landing was arm stop case 1 (an obstacle between the arm and its target: the tip "
        "stopped > d_c from it in x) and whose foothold then leaves its range lifts clear and is transferred "
        "next while the crawlers drive on (the same transfer would stop at the same obstacle, out of range "
        "again after a few cm: block-500 seed 1, RR on the block's top 0.78 m from its mount, the crawlers "
        "waiting 2 s of every 3.4 s); False: the crawlers wait for it like any out-of-range arm "
        "(docs/octopus.md, 'Case-1 footholds')"))
    tau_filter: float = param(0.15, ge=0, le=1,
                              doc="per-tick weight of the elbow torque in its free-motion reference while lowering "
                                  "(a contact is a jump of contact_torque above it)")
    settle_dz: float = param(0.0005, gt=0, unit="m/tick",
                             doc="a landed tip whose height stays for settle_ticks ticks within settle_dz x "
                                 "settle_ticks of its first has settled: it is a support")
    settle_ticks: int = param(5, ge=1,
                              doc="ticks a landed tip must stay within its settle band (settle_dz) before it is a "
                                  "support")
    stall_dz: float = param(0.04, gt=0, unit="m",
                            doc="a lowering tip that has stopped descending this far above its descending target "
                                "has landed (stopped following)")
    tilt_contact: float = param(0.01, gt=0, unit="rad",
                                doc="the body pitching or rolling this much since an arm began lowering = that "
                                    "arm's tip carries load: it has landed")
    heading_gain: float = param(0.2, ge=0, unit="m/s/rad",
                                doc="the walk's heading hold (:func:`.rules.steer`; 0: none): the gyro yaw rate "
                                    "integrated (> 0: turned left) stands for the operator's move direction; each "
                                    "crawler's speed changes by this x heading (left +, right -)")
    heading_dv: float = param(0.03, ge=0, unit="m/s",
                              doc="largest speed change of each crawler by the heading hold (the two differ by up "
                                  "to twice this)")
    extra_lift: float = param(0.5, ge=0, unit="rad",
                              doc="a swing blocked for phase_timeout lifts the arm this much higher (boom, beyond "
                                  "A_B) and swings again, once; the extra lift stays until the arm lands where it "
                                  "was sent")
    phase_timeout: float = param(3.0, gt=0, unit="s",
                                 doc="a transfer's lift or swing phase unfinished this long moves on to the next "
                                     "phase from where the arm is; a blocked swing first lifts extra_lift higher "
                                     "and swings again")
    release_d_e: float = param(0.005, gt=0, unit="rad/tick",
                               doc="boom step of the release, up to release_boom: quasi-static (0.25 rad/s), where "
                                   "eq. 28's dE would drop the body in 0.7 s")
    release_d_f: float = param(0.01, gt=0, unit="rad/tick",
                               doc="flipper step of the release, up to 0: quasi-static (0.5 rad/s), where eq. 29's "
                                   "dF would drop the body in 0.7 s")
    release_tilt: float = param(0.08, gt=0, unit="rad",
                                doc="the nose rising this much since the release began: the climb resumes and drives "
                                    "release_more further, at most max_resumes times (0 by default: the walk goes on)")
    release_more: float = param(0.15, ge=0, unit="m",
                                doc="a resumed climb drives this much further (travel S) before it releases again")
    pit_depth: float = param(0.45, gt=0, unit="m",
                             doc="no ground this far below the transfer target: a pit (arm stop case 3); the "
                                 "lowering arm stops where it is")
    pit_hold: float = param(0.3, ge=0, le=2.0, unit="s",
                            doc="a lowering arm that has found no contact by pit_depth holds its pose this long "
                                "before it is called a pit: an arm whose tip rests on a top at full stretch (the "
                                "nose-up body on a short tread, where the stretch hides the torque and blocked "
                                "signals) then presses its elbow down by more than contact_torque, a free arm "
                                "hanging straight holds it up (-4 to -10 N m). A pit arm then lands when its elbow "
                                "torque rises contact_torque above its hanging value (the ground coming up to the "
                                "tip). 0: neither, the pit at once and the arm left hanging (before 2026-12-06)")
    targets: tuple[tuple[float, float, float], tuple[float, float, float]] = param(
        ((0.75, 0.55, -0.05), (-0.45, 0.55, -0.05)), length=2, unit="m",
        doc="transfer target tips in {R} (x, |y|, z) for (front, rear) arms, y signed by side (Table 2's analogue)")
    d_c: float = param(0.1, gt=0, unit="m",
                       doc="arm stop threshold dC (x): a landed tip farther than this along x from its target is "
                           "blocked (arm stop case 1)")
    d_d: float = param(0.08, gt=0, unit="m",
                       doc="arm stop threshold dD (z): a landed tip more than this above its target is on top of an "
                           "obstacle (case 2), more than this below it in a pit (case 3)")
    gait_pause: float = param(0.4, ge=0, unit="s", doc="support time between two transfers")
    flipper_feel: bool = param(False,
                               doc="the walk's footholds move with the body's advance read from a front flipper "
                                   "pushed up by a riser (its tip on the riser's face below the top the front arms "
                                   "stand on: the tip's level-frame x changes by the body's advance), where that is "
                                   "less than the crawler odometry (the crawlers slipping against the riser); the "
                                   "odometry elsewhere. Off by default: it halves step-400's walk tip slip (median "
                                   "0.093 -> 0.043 m, 20 seeds) but the climb that starts from footholds held in place "
                                   "releases with less margin (step-400 static minimum median 0.154 -> 0.112 m, worst "
                                   "0.011; docs/octopus.md, 'The front flippers as feelers')")
    feel_torque: float = param(10.0, gt=0, unit="N m",
                               doc="flipper_feel: a front flipper pushed up by more than this (the riser against its "
                                   "tip; a free flipper reads +1 to +3 N m, one against the step-400 riser -18 to "
                                   "-44) is read as a feeler")
    gait_pace: bool = param(True,
                            doc="the walk's crawlers slow (never beyond track_speed) so that no foothold leaves "
                                "its range before its arm's turn, the turns paced by the last four transfers as "
                                "the controller timed them (:meth:`.clm.CLMController._pace`); False: "
                                "track_speed, the crawlers stopping while a foothold is out of range [R: the "
                                "paper keeps the crawler speed fixed and low; slower where the arms need it, "
                                "issue 28 piece 3]")
    d_f: float = param(0.0873, gt=0, unit="rad/tick",
                       doc="flipper step dF of eq. 29 while climbing (down, limited by flip_lead and flip_min); the "
                           "lift moves tip targets, not booms, so eq. 28's dE has no field; the release steps are "
                           "release_d_e and release_d_f")
    climb_distance: float = param(0.3, gt=0, unit="m",
                                  doc="L of eqs. 28-29: travel S past the edge before release, counted from when H "
                                      "reaches H_EST (0.6 x 0.5 m)")
    h2: float = param(0.05, unit="m",
                      doc="H2 of the COG-height rule H = H1 - H2 (eqs. 10-12): height of the robot origin above the "
                          "track bottom less the tip radius (fixed, like the paper's COG)")
    release_boom: float = param(0.0, ge=-math.pi, le=math.pi, unit="rad",
                                doc="boom angle the arms return to on release (at release_d_e a tick)")
    max_lead: float = param(0.35, gt=0, unit="rad",
                            doc="largest lead of an arm joint command over its measured angle (every state)")
    pitch_cap: float = param(0.25, gt=0, le=math.pi / 2, unit="rad",
                             doc="while lifting, the front arms hold while the nose pitch is above this, the rear "
                                 "arms while it is below minus this")
    lift_margin: float = param(0.03, ge=0, unit="m",
                               doc="while lifting, the arms hold once H exceeds H_EST by this (our addition: eq. 28 "
                                   "read literally keeps lowering the booms until S > L and tips the robot over)")
    flip_min: float = param(-0.8, ge=-math.pi, le=math.pi, unit="rad", doc="lowest flipper command while climbing")
    lift_dz: float = param(0.002, gt=0, unit="m/tick",
                           doc="lift: every tip target in {R} moves down by this a tick (IK), so the chassis rises "
                               "vertically on its tips")
    lift_rear: float = param(1.0, ge=0, le=1.0,
                             doc="while lifting, the rear tips move down at this share of lift_dz (1: a level "
                                 "four-arm lift; below 1 the nose rises, the rear crawlers stay on the ground)")
    flip_lead: float = param(0.05, ge=0, unit="rad",
                             doc="while climbing, a flipper command goes at most this far below the measured angle "
                                 "(eq. 29): a flipper on the top or the ground presses with at most flipper_kp x this")
    flip_wait: float = param(0.5, ge=0,
                             doc="front flippers wait while H < flip_wait x H_EST (their tips are still below the "
                                 "edge: they stay raised against the riser)")
    edge_angle: float = param(1.2, gt=0, le=math.pi, unit="rad",
                              doc="a front flipper steeper than this in the level frame (encoder + IMU pitch) that "
                                  "has stopped rising for edge_time is, with an up-step sensed, an edge ahead as the "
                                  "limit A0 is (a climb starts): at a low riser the edge presses near the pivot and "
                                  "the torque rule stalls below the limit (so it stalls at the 100-250 mm risers)")
    edge_time: float = param(1.0, ge=0, unit="s",
                             doc="how long a steep front flipper (edge_angle) must have stopped rising to mean an edge")
    mount_pitch: float = param(0.35, gt=0, le=math.pi / 2, unit="rad",
                               doc="the nose pitched up this much (IMU) with an up-step sensed (four tips down) also "
                                   "starts a climb: the crawlers are mounting an edge with the rear below it, as on "
                                   "the next terrace after a release; the lift then raises the rear first (pitch_cap)")
    max_resumes: int = param(0, ge=0,
                             doc="releases of one climb that may go back to climbing when the nose rises "
                                 "(release_tilt); after them the release walks on, and the walk's triggers "
                                 "(mount_pitch) start a fresh climb with H_EST re-estimated from the four tips (the "
                                 "next terrace). 0 (since 2026-12-05): on a short tread the nose rising in the release "
                                 "is the crawlers mounting the next riser, and the resumed climb lifted every arm "
                                 "clear (footholds out of range) and teetered over the first edge; 20 seeds: terrace "
                                 "margin -0.011 -> +0.024 m (front), -0.014 -> +0.018 m (side), 80/80 either way; "
                                 "the sweep and rough trials are bitwise the same (no resume fires there); 3 = the "
                                 "earlier default (docs/octopus.md, 'Terraces without resumes')")
    stall_time: float = param(3.0, gt=0, unit="s",
                              doc="a climb with every arm lifted clear, past its release distance, whose pitch has "
                                  "held within 0.02 rad this long is stalled (the crawlers slip: 0.18 m of track "
                                  "at 0.06 m/s that moves nothing); the arms are placed again, as at guard_pitch")
    guard_pitch: float = param(0.9, gt=0, le=math.pi / 2, unit="rad",
                               doc="the paper's real-time stability monitor in the walk: beyond this nose-up pitch "
                                   "(below the ~0.93 rad static tip-back angle on the rear flippers, "
                                   ":func:`.ccm.tip_back_angle`) the crawlers back off; without it CLM walked its "
                                   "front arms up the 500-550 mm risers it cannot climb and turned over (3 of 6 sweep "
                                   "trials, after 60 s)")
    climb_hold: bool = param(True,
                             doc="while the lifted body drives, the supporting tips hold their footholds (their "
                                 "targets move back by the crawler travel, as in walking), so a front tip on a short "
                                 "tread does not roll into the next riser and block the climb")
    climb_face_pivot: bool = param(False,
                                   doc="nose climb, before the front is over: eqs. 22-27 turn the supports' targets "
                                       "about the body's instantaneous centre with the front pulley against the "
                                       "riser's face and the rear on the ground (:func:`.clm.face_centre`), the rear "
                                       "tips' x too, instead of about the rear contact with the rear tips held in "
                                       "{R}. Holds every tip within 2-7 cm through the nose lift of step-400 (9-23 cm "
                                       "off), but the held footholds run out of reach after the front is over and "
                                       "the step's static margin falls 0.157 -> 0.074 m, terrace2-front's 0.094 -> "
                                       "0.004 m (10 seeds; docs/octopus.md, 'The nose lift's pivot'): off, as the "
                                       "paper's 'we do not try to keep the position of the endpoint of arms "
                                       "consistent'")
    nose_climb: bool = param(True,
                             doc="the climb of the paper's Fig. 9 (:meth:`.clm.CLMController._climb_nose`): the "
                                 "front booms lift the nose toward climb_pitch while the crawlers drive into the "
                                 "riser ('flippers ... and all boom joints ... rotate down to lift robot body', 'by "
                                 "the friction force generated from crawlers and step, robot can move forward "
                                 "slowly'); the front flippers come down onto the top once they clear its edge; the "
                                 "rear arms press with a bounded force (the rear crawlers stay loaded) until the "
                                 "front pulley is over the top, then lift the rear. The default since the release's "
                                 "wait (place_pitch, off since the walk fixes of 2026-12-04) made the two-terrace "
                                 "tasks 5/5 each (before: 3/5); False is the level four-arm hoist of issue 21")
    place_pitch: float = param(math.pi / 2, gt=0, le=math.pi / 2, unit="rad",
                               doc="after a release the arms are re-placed; while the body is pitched nose-up more "
                                   "than this the crawlers wait until the four arms are down (pi/2, the default: "
                                   "never, the crawlers keep their speed as in the paper). At 0.15 (the earlier "
                                   "default, against the crawlers mounting a short tread's next riser alone, "
                                   "terrace2-front seed 0) the terraces stopped the tracks on 6.1 / 4.9 % of walking "
                                   "ticks (front / side, median of 20 seeds) against 0.2 / 0.0 % and took 62 / 73 s "
                                   "against 55 / 55 s, with the "
                                   "same 40/40 successes: the false landings re-lowered (relower_dz), the settle "
                                   "band and the stalled climb's recovery (stall_time) made the wait unneeded")
    climb_pitch: float = param(0.6, gt=0, le=math.pi / 2, unit="rad",
                               doc="nose-up pitch the front booms lift toward in the nose climb (nose_climb); above it "
                                   "they hold, the front flippers hold and the rear flippers push [P: the CLM climb's "
                                   "largest pitch, 0.6 rad: a measured result used as a setting]; below the walk "
                                   "guard guard_pitch, which backs the crawlers off in the climb too (the stability "
                                   "monitor). Step-400 reads it back (0.603), but with a cap of 0.3-0.55 the step "
                                   "lifts the nose to 0.587-0.590 itself; a cap of 0.45-0.55 fails the zoo's 400 mm "
                                   "course 3/3 (the front flippers held above the top), so 0.6 stays "
                                   "(docs/octopus.md, 'The nose lift's cap')")
    climb_press: float = param(0.01, ge=0, unit="m",
                               doc="nose climb: a pressing (not lifting) tip's target sits this far below its sensed "
                                   "height plus the tick's predicted motion (eqs. 22-27 in x and z): a bounded press "
                                   "(~2x press), so the arms assist and the crawlers carry the rest")
    front_support: bool = param(True,
                                doc="nose climb: once the front is over the top, the front arms stay supports on "
                                    "it (the climb_press bounded press, their targets moved by eqs. 22-27) until the "
                                    "release or until their foothold leaves its range; the paper releases the arms "
                                    "only after H > H_EST and S > L (Fig. 9f-h). False: they unload and lift clear "
                                    "as soon as the front is over (the default before 2026-12-05; the robot then "
                                    "teetered on the edge on its tracks and the rear tips, static margin ~0.02 m)")
    mount_level: bool = param(True,
                              doc="nose climb started by the nose-up trigger (mount_pitch; the next terrace after a "
                                  "release): the ground the crawlers drive on is taken as level (pitch0 = 0) for the "
                                  "rear lift's stop, the 'rear up' latch and the travel direction; the IMU pitch at "
                                  "that start is the edge's, not the ground's. False (before 2026-12-05): the IMU "
                                  "pitch (~0.46 rad), which latched the rear 'up' at once and stopped the rear lift "
                                  "while the nose was still up (terrace2-front seed 8: released at 0.35 rad, the rear "
                                  "dropping onto the edge)")
    release_unload: bool = param(True,
                                 doc="nose climb, the release (Fig. 9f-h: 'the flippers and arms will be "
                                     "released'): a front arm still a support on the top unloads (its target rises "
                                     "by lift_dz a tick) and lifts clear once the target is up at its sensed tip, so "
                                     "the front crawlers settle onto the top. False (before 2026-12-05): it kept its "
                                     "climb press through the release and held the nose up on a tripod with the "
                                     "edge (terrace2-front seed 2: pitch 0.06 rad, static margin -0.022 m)")
    roll_level: float = param(0.05, ge=0, le=1.0, unit="1/tick",
                              doc="nose climb, the rear lift (eq. 28): each rear tip's target rises by roll_level x "
                                  "IMU roll x its y in {R} a tick, an integral roll levelling (the arm on the raised "
                                  "side eases, the other presses on), 3 mm a tick at 0.1 rad roll, of the order of "
                                  "lift_dz; 0 = off (one rear arm lifting the rear alone rolled the body 0.11-0.14 rad "
                                  "on step-400, paper 0.03)")


@dataclass(frozen=True)
class CCMConfig:
    """CCM parameters."""

    track_speed: float = param(0.1, gt=0, unit="m/s", doc="crawler speed (a back-off drives at minus this)")
    front_approach: float = param(0.95, ge=-math.pi, le=math.pi, unit="rad",
                                  doc="front flipper angle held while approaching (and backing off); by default 0.05 "
                                      "rad below the cap a0, so reaching the cap means an edge lifted the flipper")
    settle_time: float = param(0.5, ge=0, unit="s",
                               doc="the torque rule ignores the front flippers' own (self-caused) torque: it starts "
                                   "once they have been within settle_tol of their command this long, and reads the "
                                   "torque change from their settled torque")
    settle_tol: float = param(0.05, gt=0, unit="rad",
                              doc="front flipper angle error from its command that counts as settled (settle_time)")
    t0: float = param(40.0, gt=0, unit="N m",
                      doc="flipper torque threshold T0 of the paper's rule, on the torque change from the settled "
                          "torque; a change beyond it with both front flippers within 0.05 rad of a0 also starts the "
                          "press (first approach only)")
    d_a: float = param(0.02, gt=0, unit="rad/tick",
                       doc="flipper step dA of the torque rule: a torque change beyond T0 moves the flipper by this a "
                           "tick, against its sign")
    a0: float = param(1.0, ge=-math.pi, le=math.pi, unit="rad",
                      doc="flipper limit A0 of the torque rule: the climbing angle here (57 deg), not the joint's 85 "
                          "deg: a flipper raised to 85 deg stands like a wall against the riser and the crawler "
                          "stalls; at 57 deg its driving underside meets the edge of any step below its tip (about "
                          "0.3 m)")
    d_b: float = param(0.02, gt=0, unit="rad/tick",
                       doc="flipper step dB of the torque rule: a flipper at the limit A0 is lowered by this a tick")
    press_pitch: float = param(0.15, ge=0, le=math.pi / 2, unit="rad",
                               doc="pitch that starts pressing the front flippers down (plus retry_pitch a retry)")
    front_press: float = param(-0.4, ge=-math.pi, le=math.pi, unit="rad",
                               doc="lowest front flipper target while pressing and pushing (the target is -pitch: "
                                   "flippers level on the top)")
    rear_push: float = param(-0.9, ge=-math.pi, le=math.pi, unit="rad",
                             doc="rear flipper target while pushing above flatten_pitch (< 0 pushes the rear up)")
    push_pitch: float = param(0.3, ge=0, le=math.pi / 2, unit="rad",
                              doc="pitch above which pressing turns to pushing with the rear flippers")
    flatten_pitch: float = param(0.1, ge=0, le=math.pi / 2, unit="rad",
                                 doc="while pushing, the rear flippers relax (to 0) below this pitch")
    level_time: float = param(1.0, ge=0, unit="s",
                              doc="level (|pitch| < 0.05 rad) this long while pushing = on the top: flatten")
    abort_pitch: float = param(1.2, gt=0, le=math.pi, unit="rad",
                               doc="|pitch| at which the climb is aborted whatever the geometry; at defaults the "
                                   "abort comes from the tip-back condition (tip_back) first")
    tip_back: bool = param(True,
                           doc="abort once the nose-up pitch reaches the static tip-back angle over the rearmost "
                               "ground contact (:func:`.ccm.tip_back_angle`, at the rear flippers' mean angle); "
                               "measured on step-400: the fall starts there (pitch rate 0.2 -> 1 rad/s between 0.95 "
                               "and 1.15 rad) and an abort at 0.7-1.0 rad still turns over, one at 0.6 rad stops the "
                               "robot (stuck)")
    cog_z: float = param(0.07, ge=0, unit="m",
                         doc="COG height above the main-track pulley axis in {R}, for the tip-back angle: the chassis "
                             "(56 kg at 0.06 m) with the arms (20 kg about the 0.15 m mounts) over ~94 kg; the paper "
                             "treats the COG as fixed and low in the chassis")
    stall_time: float = param(6.0, gt=0, unit="s",
                              doc="pressing or pushing this long without a new pitch peak (> 0.02 rad) is a stall: "
                                  "back off (at most retries times)")
    back_time: float = param(3.0, ge=0, unit="s",
                             doc="a stall backs off at -track_speed this long, then approaches again")
    retries: int = param(2, ge=0, doc="back-offs before the controller keeps pushing to the end")
    retry_pitch: float = param(0.3, ge=0, unit="rad",
                               doc="each retry presses only once the pitch exceeds press_pitch + tries x this (not "
                                   "on the flippers' edge contact): the nose rears higher so the flippers can hook "
                                   "over a higher edge")
    heading_gain: float = param(0.2, ge=0, unit="m/s/rad",
                                doc="the heading hold, as in CLM (:func:`.rules.steer`; 0: none): each crawler's "
                                    "speed changes by this x the integrated gyro yaw (left +, right -)")
    heading_dv: float = param(0.03, ge=0, unit="m/s",
                              doc="largest speed change of each crawler by the heading hold (the two differ by up "
                                  "to twice this)")
    d_flip: float = param(0.03, gt=0, unit="rad/tick",
                          doc="flipper step toward a target per 0.02 s tick (every flipper move but the torque rule's)")
    stowed_arm: tuple[float, float, float] = param((0.0, 0.0, 0.0), length=3, ge=-math.pi, le=math.pi, unit="rad",
                                                   doc="(swing, boom, elbow) of the front arms: the original pose, "
                                                       "every joint 0 (the paper keeps the front arms \"in the "
                                                       "original positions\")")
    lifted_arm: tuple[float, float, float] = param((-1.2, -1.1, 2.4), length=3, ge=-math.pi, le=math.pi, unit="rad",
                                                   doc="(swing, boom, elbow) of the rear arms, lifted (as in the "
                                                       "paper's CCM trials)")
