"""Crawler-only baseline (CCM): an automated flipper step-climbing controller, same sensors.

The paper's CCM was driven manually by two operators "according to the sufficient feedback
visual images" (environment cameras); it gives no rule of theirs, only that they "tried twice"
and the robot "turned over" (Fig. 11a4), and that CCM "can be realized by manual or well-designed
automated control system" (its refs. 15-17). This stand-in replaces the two operators by such an
automated flipper sequence, after the four-sub-crawler robots of its refs. 5, 6 and 16 (Okada,
Nagatani & Yoshida, IROS 2009; Nagatani, Yamasaki & Yoshida, IROS 2008; the paper cites them by
title only and quotes no rule of theirs): approach with the front flippers raised and held; on
contact (the flippers pushed by an edge once they have settled, or the pitch rising) press the
front flippers down on the edge and push with the rear flippers; flatten once the nose is over
(pitch falls back). A climb that stalls (no pitch gain for
``stall_time``) backs off and retries, up to ``retries`` times, as the operators' second try.
It sees what the robot senses (IMU, flipper encoders and torques, gyro), not the operators'
camera views: it cannot judge the step's height or the distance to it.

The PUSH (rear flippers to ``rear_push`` while the pitch is above ``flatten_pitch``) is the
paper's own flipper rule of a climb, eq. 29, for the crawler alone: during the CLM climb "flippers
(A and A') ... rotate down to lift robot body" (A = A' - dF while H < H_EST or S < L) and are
released once the body is over the top; its introduction names the same move for sub-crawler
robots, "rotating sub-crawlers downward to climb over obstacles" (ref. 7). CCM has no H_EST (no
arms to measure it): the pitch stands for "not yet over the top". Without the push
(``ccm.rear_push=0``) the robot stands at 1.2 rad against the 400 mm riser, statically stable,
and ends ``stuck``; with it the rear rises onto the rear flipper tips and the COG passes behind
them (``tipped_back``), the paper's outcome.

The abort fires when the pitch reaches the robot's static tip-back angle over its rearmost
ground contact (geometry, the rear flipper encoders, the IMU pitch: :func:`tip_back_angle`): the
COG is then over the pivot and the fall has begun, so the abort (stop, flatten) is recorded but
cannot hide the outcome, which the task decides from the contacts (``tipped_back``,
:meth:`~terrabench.systems.octopus.task.OctopusTask._tip_back`); ``abort_pitch`` is a plain pitch
limit beside it. Arms as in the paper's CCM trials: rear arms lifted, front arms at their original
pose.
"""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.base import MachineController, ModeMachine
from terrabench.systems.octopus.controller_config import CCMConfig
from terrabench.systems.octopus.robot import RobotConfig
from terrabench.systems.octopus.rules import Command, flipper_rule, steer

APPROACH, PRESS, PUSH, FLATTEN, ABORT, BACK_OFF = 0, 1, 2, 3, 4, 5
MODE_NAMES = {APPROACH: "approach", PRESS: "press", PUSH: "push", FLATTEN: "flatten", ABORT: "abort",
              BACK_OFF: "back-off"}


def tip_back_angle(q_rear: float, pitch: float, robot: RobotConfig, cog_z: float) -> float:
    """Nose-up pitch (rad) at which the COG (0, cog_z) in {R} is over the rearmost ground
    contact: the rear flipper tip pulley at rear flipper angle ``q_rear`` or the rear track
    pulley, whichever is lower in the world at ``pitch`` (it is the pivot).

    A point (x, z) of {R} is at x cos p - z sin p along the ground; the COG is over the centre
    (xc, zc) of a pulley (its lowest point is below the centre) when tan p = -xc / (cog_z - zc).
    """
    px, L = robot.pulley_x, robot.flipper_len
    cands = ((-px - L * math.cos(q_rear), L * math.sin(q_rear), robot.flipper_tip_r), (-px, 0.0, robot.pulley_r))
    sp, cp = math.sin(pitch), math.cos(pitch)
    xc, zc, _ = min(cands, key=lambda c: c[0] * sp + c[1] * cp - c[2])
    return math.atan2(-xc, cog_z - zc)


class CCMController(MachineController):
    """``obs -> Command`` for the crawler-only mode."""

    def __init__(self, cfg: CCMConfig, dt: float = 0.02, robot: RobotConfig | None = None):
        self.cfg, self.dt = cfg, dt
        self.robot = robot or RobotConfig()
        self.cmd = Command()
        self.cmd.arm[:2] = cfg.stowed_arm
        self.cmd.arm[2:] = cfg.lifted_arm
        self.cmd.flip[:] = [cfg.front_approach, cfg.front_approach, 0.0, 0.0]
        self.peak = 0.0
        self.peak_t = 0.0
        self.level_t = 0.0
        self.settled_t = 0.0
        self.back_until = 0.0
        self.tries = 0
        self.tau_ref = np.zeros(2)
        self.heading = 0.0  # integrated gyro yaw rate (rad), as in CLM
        self.machine = ModeMachine(APPROACH, MODE_NAMES)  # the controller state; records every change


    def _toward(self, i: int, target: float) -> None:
        c = self.cmd.flip
        d = self.cfg.d_flip
        c[i] += min(max(target - c[i], -d), d)  # a scalar clip (np.clip on scalars cost ~60 % of the controller)

    def _approach(self, obs) -> None:
        cfg, c, p = self.cfg, self.cmd, obs.pitch
        for f in (2, 3):
            self._toward(f, 0.0)
        if self.settled_t < cfg.settle_time:
            # raise and hold: the flippers' torque is still their own motion, the rule waits
            for f in (0, 1):
                self._toward(f, cfg.front_approach)
            err = float(np.abs(obs.q_flip[:2] - c.flip[:2]).max())
            self.settled_t = self.settled_t + self.dt if err < cfg.settle_tol else 0.0
            # the torque of a settled flipper on level ground (its pulley's drive friction, its
            # weight) is its own: the rule reads the change from it
            self.tau_ref[:] = obs.tau_flip[:2]
            return
        dtau = obs.tau_flip[:2] - self.tau_ref
        for f in (0, 1):
            # the torque rule on the measured angle A', but its hold case ("low") keeps the held
            # command: holding the measured angle lets the flipper sag by its servo error a tick
            a, case = flipper_rule(float(obs.q_flip[f]), float(dtau[f]), cfg.t0, cfg.d_a, cfg.a0, cfg.d_b)
            if case != "low":
                c.flip[f] = a
        at_cap = min(obs.q_flip[0], obs.q_flip[1]) > cfg.a0 - 0.05
        pushed = float(np.abs(dtau).max()) > cfg.t0
        # a retry rears the nose higher before pressing (an operator's second attempt); only the
        # first approach presses on the flippers' edge contact alone
        pp = cfg.press_pitch + self.tries * cfg.retry_pitch
        if p > pp or (at_cap and pushed and not self.tries):
            why = f"pitch {p:.2f} > {pp:.2f}" if p > pp else \
                f"front flippers at {cfg.a0} rad pushed (torque change {np.abs(dtau).max():.0f} N m > {cfg.t0:g})"
            self.peak, self.peak_t = p, obs.t
            self.machine.go(obs.t, PRESS, why)

    def __call__(self, obs) -> Command:
        cfg, c = self.cfg, self.cmd
        self.heading += obs.yaw_rate * self.dt
        c.track[0], c.track[1] = steer(cfg.track_speed, self.heading, cfg.heading_gain, cfg.heading_dv)
        p = obs.pitch
        if p > self.peak + 0.02:
            self.peak, self.peak_t = p, obs.t
        if self.state != ABORT:
            if abs(p) >= cfg.abort_pitch:
                self.machine.go(obs.t, ABORT, f"|pitch| {abs(p):.2f} rad >= {cfg.abort_pitch}")
            elif cfg.tip_back and p > 0:
                tb = tip_back_angle(0.5 * float(obs.q_flip[2] + obs.q_flip[3]), p, self.robot, cfg.cog_z)
                if p >= tb:
                    self.machine.go(obs.t, ABORT,
                                    f"pitch {p:.2f} rad >= tip-back angle {tb:.2f} rad over the rear contact")
        if self.state in (PRESS, PUSH) and obs.t - self.peak_t > cfg.stall_time and self.tries < cfg.retries:
            self.tries += 1
            self.back_until = obs.t + cfg.back_time
            self.machine.go(obs.t, BACK_OFF,
                            f"no pitch gain for {cfg.stall_time:g} s (try {self.tries} of {cfg.retries})")
        if self.state == APPROACH:
            self._approach(obs)
        elif self.state == PRESS:
            # front flippers laid along the top (level in the world: angle = -pitch): they carry
            # the nose onto the top and drive; pressing further would only stand the robot up
            fp = max(-p, cfg.front_press)
            self._toward(0, fp)
            self._toward(1, fp)
            if p > cfg.push_pitch:
                self.machine.go(obs.t, PUSH, f"pitch {p:.2f} > {cfg.push_pitch}")
        elif self.state == PUSH:
            # pitch feedback: the front flippers stay level on the top, the rear ones push while
            # the nose is up and relax once it is down (a dip is not yet the top: no flatten); the
            # push is eq. 29's flippers rotating down to lift the body (module docstring)
            for f in (0, 1):
                self._toward(f, max(-p, cfg.front_press))
            for f in (2, 3):
                self._toward(f, cfg.rear_push if p > cfg.flatten_pitch else 0.0)
            self.level_t = self.level_t + self.dt if abs(p) < 0.05 else 0.0
            if self.level_t >= cfg.level_time:
                self.machine.go(obs.t, FLATTEN, f"level for {cfg.level_time:g} s")
        elif self.state == FLATTEN:
            for f in range(4):
                self._toward(f, 0.0)
            if abs(p) < 0.05 and np.abs(c.flip).max() < 0.05:
                self.peak, self.settled_t = 0.0, 0.0
                self.machine.go(obs.t, APPROACH, "flat")
        elif self.state == BACK_OFF:
            c.track[:] = -cfg.track_speed
            for f in range(4):
                self._toward(f, 0.0 if f > 1 else cfg.front_approach)
            if obs.t >= self.back_until:
                self.peak, self.settled_t, self.level_t = 0.0, 0.0, 0.0
                self.machine.go(obs.t, APPROACH, f"backed off {cfg.back_time:g} s")
        else:  # ABORT: stop, flatten the flippers
            c.track[:] = 0.0
            for f in range(4):
                self._toward(f, 0.0)
        c.mode, c.moving_arm = self.state, -1
        return c
