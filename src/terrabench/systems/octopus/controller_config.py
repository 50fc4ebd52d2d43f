"""The settings of the two OCTOPUS controllers: CLM (compound locomotion, :mod:`.clm`) and CCM
(crawlers only, :mod:`.ccm`); sections ``clm`` and ``ccm`` of :class:`~terrabench.systems.
octopus.config.OctopusConfig`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from terrabench.config import param


@dataclass(frozen=True)
class CLMConfig:
    """CLM parameters (rad per 0.02 s tick unless said otherwise).

    Attributes:
        track_speed: crawler surface speed in compound mode (m/s).
        climb_track_speed: crawler speed while lifting on a step (m/s).
        sigma: (sigma1, sigma2, sigma3) terrain-case thresholds (m).
        t0: flipper torque threshold T0 (N m).
        d_a: flipper step dA of the torque rule.
        a0: front flipper limit A0 (rad) (85 deg).
        d_b_flip: flipper step dB at the limit.
        flipper_start: front flipper angle on flat ground (rad); rear flippers start at 0.
        arm_ab: boom lift angle A_B of a transfer (our sign: < 0 is up) (rad).
        d_swing: swing step dA of a transfer; d_lift: boom/elbow step dB of a transfer.
        k_boom: boom gain K of eqs. 19-21 (per tick).
        contact_torque: elbow-torque change that signals a tip contact (N m).
        hit_torque: elbow-torque change of a supporting arm that signals a collision (N m).
        press: a supporting tip's target sits this far below its measured height (m): a press of
            bounded force, so the crawlers carry most of the load (eqs. 22-27, :meth:`_support`).
        arm_moving: supporting arms follow the body (eqs. 22-27); False (a control for the
            tests) keeps their joint targets fixed in {R}, so their tips roll with the body.
        reach_min: (front, rear) arms: a foothold behind this x in {R} is out of range (m); the
            crawlers wait for its transfer.
        lower_dz: a lowering tip's target descends this much a tick (m) (0.5 m/s), three times
            that while more than 0.15 m above the target height.
        tau_filter: per-tick weight of the elbow torque in its free-motion reference while lowering.
        settle_dz, settle_ticks: a landed tip that moves less than settle_dz (m) a tick for
            settle_ticks ticks has settled: it is a support.
        heading_gain, heading_dv: the heading hold (:func:`steer`): the gyro yaw rate integrated
            stands for the operator's move direction; crawler speeds differ by gain x heading
            (m/s per rad), at most heading_dv (m/s).
        phase_timeout: a transfer's lift or swing phase that has not finished in this long moves on
            to the next phase from where the arm is (s); a blocked swing first lifts the arm
            ``extra_lift`` rad higher (boom) and swings again, until the arm lands where it was sent.
        release_d_e, release_d_f: boom and flipper steps of the release (rad/tick): quasi-static
            (0.25 and 0.5 rad/s), where eqs. 28-29's dE and dF would drop the body in 0.7 s.
        release_tilt: the nose rising this much while releasing means the COG is not over the
            top yet (rad): the climb resumes and drives ``release_more`` m further (m).
        tilt_contact: the body pitching or rolling this much while an arm lowers = that arm's tip
            carries load: it has landed (rad).
        stall_dz: a lowering tip this far above its target has landed (stopped following) (m).
        pit_depth: no ground this far below the transfer target: a pit (arm stop case 3) (m).
        reach_max: a foothold farther than this from its arm's mount, horizontally, is out of
            range too (m) (l1 + l2 = 0.9 m reaches 0.87 m at the ground's depth).
        targets: transfer target tips in {R} (x, |y|, z) for (front, rear) arms (m), Table 2's analogue.
        d_c, d_d: arm stop thresholds dC (x) and dD (z) (m).
        gait_pause: support time between two transfers (s).
        d_f: flipper step dF of eq. 29 (the lift moves tip targets, not booms, so eq. 28's dE has
            no field; the release steps are release_d_e and release_d_f).
        climb_distance: L of eqs. 28-29, travel past the edge before release (m) (0.6 x 0.5 m).
        h2: H2 of the COG-height rule: height of the robot origin above the track bottom less the
            tip radius (m) (fixed, like the paper's COG).
        release_boom: boom angle the arms return to on release (rad).
        lift_margin: while lifting, booms hold once H exceeds H_EST by this (m) (our addition: eq. 28
            read literally keeps lowering the booms until S > L and tips the robot over).
        pitch_cap: while lifting, front booms hold above this pitch, rear booms below minus it (rad).
        flip_min: lowest flipper command while climbing (rad).
        max_lead: largest lead of a joint command over the measured angle (rad).
        edge_angle, edge_time: a front flipper steeper than edge_angle in the level frame (encoder +
            IMU pitch) that has stopped rising for edge_time (s) is, with an up-step sensed, an edge
            ahead as the limit A0 is: at a low riser the edge presses near the pivot and the torque
            rule stalls below the limit (the CLM riser stalls at 100-250 mm).
        mount_pitch: the nose pitched up this much (IMU) with an up-step sensed (four tips down)
            also starts a climb: the crawlers are mounting an edge with the rear below it, as on the
            next terrace after a release; the lift then raises the rear first (pitch_cap).
        max_resumes: releases of one climb that may go back to climbing when the nose rises
            (release_tilt); after them the release walks on, and the walk's triggers (mount_pitch)
            start a fresh climb with H_EST re-estimated from the four tips (the next terrace).
            With 0 the 450 mm sweep step fails 2/3 (its four-tip case is past sigma2, so no walk
            trigger), with 3 it climbs 3/3.
        guard_pitch: the paper's real-time stability monitor in the walk: beyond this nose-up
            pitch (below the ~0.93 rad static tip-back angle on the rear flippers) the crawlers back
            off; without it CLM walked its front arms up the 500-550 mm risers it cannot climb and
            turned over (3 of 6 sweep trials, after 60 s).
        climb_hold: while the lifted body drives, the supporting tips hold their footholds (their
            targets move back by the crawler travel, as in walking), so a front tip on a short tread
            does not roll into the next riser and block the climb.
    """

    track_speed: float = param(0.1, gt=0, unit="m/s", doc="crawler surface speed in compound mode")
    climb_track_speed: float = param(0.06, gt=0, unit="m/s", doc="crawler speed while lifting on a step")
    sigma: tuple[float, float, float] = param((0.05, 0.45, 0.45), length=3, ge=0, unit="m",
                                              doc="(sigma1, sigma2, sigma3) terrain-case thresholds")
    t0: float = param(40.0, gt=0, unit="N m", doc="flipper torque threshold T0")
    d_a: float = param(0.02, gt=0, unit="rad/tick", doc="flipper step dA of the torque rule")
    a0: float = param(1.4835, ge=-math.pi, le=math.pi, unit="rad", doc="front flipper limit A0")
    d_b_flip: float = param(0.02, gt=0, unit="rad/tick", doc="flipper step dB at the limit")
    flipper_start: float = param(0.5, ge=-math.pi, le=math.pi, unit="rad", doc="front flipper angle on flat ground")
    arm_ab: float = param(-0.6, ge=-math.pi, le=math.pi, unit="rad",
                          doc="boom lift angle A_B of a transfer (< 0 is up)")
    d_swing: float = param(0.04, gt=0, unit="rad/tick", doc="swing step of a transfer")
    d_lift: float = param(0.04, gt=0, unit="rad/tick", doc="boom/elbow step of a transfer")
    k_boom: float = param(0.15, ge=0, unit="1/tick", doc="boom gain K of eqs. 19-21")
    contact_torque: float = param(20.0, gt=0, unit="N m", doc="elbow-torque change that signals a tip contact")
    hit_torque: float = param(45.0, gt=0, unit="N m",
                              doc="elbow-torque change of a supporting arm that signals a collision")
    press: float = param(0.005, ge=0, unit="m", doc="a supporting tip's target this far below its measured height")
    arm_moving: bool = param(True, doc="supporting arms follow the body (eqs. 22-27); False keeps their targets fixed")
    reach_min: tuple[float, float] = param((0.2, -0.9), length=2, unit="m",
                                           doc="(front, rear) arms: a foothold behind this x in {R} is out of range")
    reach_max: float = param(0.8, gt=0, unit="m", doc="a foothold farther than this from its arm mount is out of range")
    lower_dz: float = param(0.01, gt=0, unit="m/tick", doc="descent of a lowering tip's target per tick")
    tau_filter: float = param(0.15, ge=0, le=1, doc="per-tick weight of the elbow torque in its free-motion reference")
    settle_dz: float = param(0.0005, gt=0, unit="m/tick", doc="a landed tip moving less than this a tick is settling")
    settle_ticks: int = param(5, ge=1, doc="ticks of settling before a landed tip is a support")
    stall_dz: float = param(0.04, gt=0, unit="m", doc="a lowering tip this far above its target has landed")
    tilt_contact: float = param(0.01, gt=0, unit="rad", doc="body tilt while an arm lowers that means its tip landed")
    heading_gain: float = param(0.2, ge=0, unit="m/s/rad",
                                doc="crawler speed difference per rad of heading error (0: no heading hold)")
    heading_dv: float = param(0.03, ge=0, unit="m/s", doc="largest crawler speed difference of the heading hold")
    extra_lift: float = param(0.5, ge=0, unit="rad", doc="extra boom lift after a blocked swing")
    phase_timeout: float = param(3.0, gt=0, unit="s",
                                 doc="a transfer's lift or swing phase unfinished this long moves on")
    release_d_e: float = param(0.005, gt=0, unit="rad/tick", doc="boom step of the release")
    release_d_f: float = param(0.01, gt=0, unit="rad/tick", doc="flipper step of the release")
    release_tilt: float = param(0.08, gt=0, unit="rad", doc="nose rise while releasing that resumes the climb")
    release_more: float = param(0.15, ge=0, unit="m", doc="extra drive after a resumed climb")
    pit_depth: float = param(0.45, gt=0, unit="m", doc="no ground this far below the transfer target: a pit")
    targets: tuple[tuple[float, float, float], tuple[float, float, float]] = param(
        ((0.75, 0.55, -0.05), (-0.45, 0.55, -0.05)), length=2, unit="m",
        doc="transfer target tips in {R} (x, |y|, z) for (front, rear) arms")
    d_c: float = param(0.1, gt=0, unit="m", doc="arm stop threshold dC (x)")
    d_d: float = param(0.08, gt=0, unit="m", doc="arm stop threshold dD (z)")
    gait_pause: float = param(0.4, ge=0, unit="s", doc="support time between two transfers")
    d_f: float = param(0.0873, gt=0, unit="rad/tick", doc="flipper step dF of eq. 29")
    climb_distance: float = param(0.3, gt=0, unit="m", doc="L of eqs. 28-29: travel past the edge before release")
    h2: float = param(0.05, unit="m",
                      doc="H2 of the COG-height rule (origin above the track bottom less the tip radius)")
    release_boom: float = param(0.0, ge=-math.pi, le=math.pi, unit="rad",
                                doc="boom angle the arms return to on release")
    max_lead: float = param(0.35, gt=0, unit="rad", doc="largest lead of a joint command over the measured angle")
    pitch_cap: float = param(0.25, gt=0, le=math.pi / 2, unit="rad", doc="while lifting, booms hold beyond this pitch")
    lift_margin: float = param(0.03, ge=0, unit="m", doc="while lifting, booms hold once H exceeds H_EST by this")
    flip_min: float = param(-0.8, ge=-math.pi, le=math.pi, unit="rad", doc="lowest flipper command while climbing")
    lift_dz: float = param(0.002, gt=0, unit="m/tick", doc="lift: every tip target moves down by this a tick")
    flip_lead: float = param(0.05, ge=0, unit="rad",
                             doc="flipper command kept within this of the measured angle (eq. 29)")
    flip_wait: float = param(0.5, ge=0, doc="front flippers wait while H < flip_wait x H_EST")
    edge_angle: float = param(1.2, gt=0, le=math.pi, unit="rad",
                              doc="a front flipper this steep (level frame), no longer rising, with an up-step: climb")
    edge_time: float = param(1.0, ge=0, unit="s", doc="the steep front flipper has stopped rising this long")
    mount_pitch: float = param(0.35, gt=0, le=math.pi / 2, unit="rad",
                               doc="the nose pitched up this much with an up-step sensed starts the climb")
    max_resumes: int = param(3, ge=0, doc="releases of one climb that may resume it (nose rising) before walking on")
    guard_pitch: float = param(0.9, gt=0, le=math.pi / 2, unit="rad",
                               doc="walking with the nose up beyond this, the crawlers back off")
    climb_hold: bool = param(True, doc="while climbing, supporting tips hold their footholds (arm moving)")


@dataclass(frozen=True)
class CCMConfig:
    """CCM parameters.

    Attributes:
        track_speed: crawler speed (m/s).
        front_approach: front flipper angle while approaching (rad), held; 0.05 rad below the cap
            a0, so reaching the cap means an edge lifted the flipper.
        settle_time: the torque rule ignores the flippers' own (self-caused) torque until they
            have been within ``settle_tol`` of their command this long (s).
        settle_tol: rad.
        t0, d_a, a0, d_b: the paper's flipper torque rule (N m, rad/tick, rad, rad/tick); the
            limit a0 is the climbing angle here (57 deg), not the joint's 85 deg: a flipper raised
            to 85 deg stands like a wall against the riser and the crawler stalls; at 57 deg its
            driving underside meets the edge of any step below its tip (about 0.3 m).
        press_pitch: pitch that starts pressing the front flippers down (rad).
        front_press: lowest front flipper target while pressing (rad) (the target is -pitch:
            flippers level on the top); rear_push: rear flipper target
            while pushing (rad, < 0 pushes the rear up).
        push_pitch: pitch above which the rear flippers push (rad).
        flatten_pitch: while pushing, the rear flippers relax below this pitch (rad).
        level_time: level (|pitch| < 0.05 rad) this long while pushing = on the top: flatten (s).
        abort_pitch: pitch at which the climb is aborted whatever the geometry (rad); at the task's
            turned-over threshold (1.2 rad), which ends the episode on the same tick, so at defaults
            the abort comes from the tip-back condition (``tip_back``).
        tip_back: abort once the nose-up pitch reaches the static tip-back angle over the rearmost
            ground contact (:func:`tip_back_angle`); measured on step-400: the fall starts there
            (pitch rate 0.2 -> 1 rad/s between 0.95 and 1.15 rad) and an abort at 0.7-1.0 rad still
            turns over, one at 0.6 rad stops the robot (stuck).
        cog_z: COG height above the main-track pulley axis in {R} (m): the chassis (56 kg at
            0.06 m) with the arms (20 kg about the 0.15 m mounts) over ~94 kg; the paper treats
            the COG as fixed and low in the chassis.
        stall_time: pressing or pushing this long without a new pitch peak (> 0.02 rad) is a stall (s).
        back_time: a stall backs off at -track_speed this long, then approaches again (s).
        retries: back-offs before the controller keeps pushing to the end.
        retry_pitch: each retry presses only once the pitch exceeds press_pitch + tries x this
            (rad): the nose rears higher so the flippers can hook over a higher edge.
        heading_gain, heading_dv: the heading hold, as in CLM (:func:`clm.steer`).
        d_flip: flipper step toward a target per 0.02 s tick (rad).
        stowed_arm: (swing, boom, elbow) of the front arms (rad): the original pose, every joint 0 (the
            paper keeps the front arms "in the original positions"); lifted_arm of the rear arms.
    """

    track_speed: float = param(0.1, gt=0, unit="m/s", doc="crawler speed")
    front_approach: float = param(0.95, ge=-math.pi, le=math.pi, unit="rad",
                                  doc="front flipper angle held while approaching")
    settle_time: float = param(0.5, ge=0, unit="s",
                               doc="flippers within settle_tol this long before the torque rule counts")
    settle_tol: float = param(0.05, gt=0, unit="rad", doc="flipper settle tolerance")
    t0: float = param(40.0, gt=0, unit="N m", doc="flipper torque threshold of the paper's rule")
    d_a: float = param(0.02, gt=0, unit="rad/tick", doc="flipper raise step of the torque rule")
    a0: float = param(1.0, ge=-math.pi, le=math.pi, unit="rad", doc="flipper climbing angle limit of the torque rule")
    d_b: float = param(0.02, gt=0, unit="rad/tick", doc="flipper lower step of the torque rule")
    press_pitch: float = param(0.15, ge=0, le=math.pi / 2, unit="rad",
                               doc="pitch that starts pressing the front flippers down")
    front_press: float = param(-0.4, ge=-math.pi, le=math.pi, unit="rad",
                               doc="lowest front flipper target while pressing")
    rear_push: float = param(-0.9, ge=-math.pi, le=math.pi, unit="rad",
                             doc="rear flipper target while pushing (< 0 pushes the rear up)")
    push_pitch: float = param(0.3, ge=0, le=math.pi / 2, unit="rad", doc="pitch above which the rear flippers push")
    flatten_pitch: float = param(0.1, ge=0, le=math.pi / 2, unit="rad",
                                 doc="while pushing, the rear flippers relax below this pitch")
    level_time: float = param(1.0, ge=0, unit="s", doc="level this long while pushing = on the top")
    abort_pitch: float = param(1.2, gt=0, le=math.pi, unit="rad", doc="pitch at which the climb is aborted")
    tip_back: bool = param(True, doc="abort at the static tip-back angle over the rearmost ground contact")
    cog_z: float = param(0.07, ge=0, unit="m", doc="COG height above the main-track pulley axis")
    stall_time: float = param(6.0, gt=0, unit="s",
                              doc="pressing or pushing this long without a new pitch peak is a stall")
    back_time: float = param(3.0, ge=0, unit="s", doc="a stall backs off this long, then approaches again")
    retries: int = param(2, ge=0, doc="back-offs before the controller keeps pushing to the end")
    retry_pitch: float = param(0.3, ge=0, unit="rad", doc="extra press pitch per retry")
    heading_gain: float = param(0.2, ge=0, unit="m/s/rad",
                                doc="crawler speed difference per rad of heading error (0: no heading hold)")
    heading_dv: float = param(0.03, ge=0, unit="m/s", doc="largest crawler speed difference of the heading hold")
    d_flip: float = param(0.03, gt=0, unit="rad/tick", doc="flipper step toward a target per tick")
    stowed_arm: tuple[float, float, float] = param((0.0, 0.0, 0.0), length=3, ge=-math.pi, le=math.pi, unit="rad",
                                                   doc="(swing, boom, elbow) of the front arms")
    lifted_arm: tuple[float, float, float] = param((-1.2, -1.1, 2.4), length=3, ge=-math.pi, le=math.pi, unit="rad",
                                                   doc="(swing, boom, elbow) of the rear arms")
