"""Crawler-only baseline (CCM): an automated flipper step-climbing controller, same sensors.

The paper's CCM was driven by two operators; this stand-in follows the autonomous flipper
sequences of Nagatani, Yamasaki & Yoshida (IROS 2008) and Okada, Nagatani & Yoshida (IROS 2009):
approach with the front flippers raised; on contact (flipper torque rule drives the flippers up
to their limit, or the pitch rises) press the front flippers down on the edge and push with the
rear flippers; flatten once the nose is over (pitch falls back); abort past ``abort_pitch``.
Arms as in the paper's CCM trials: rear arms lifted, front arms at their original (stowed) pose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from terrabench.systems.octopus.clm import Command, flipper_rule

APPROACH, PRESS, PUSH, FLATTEN, ABORT = 0, 1, 2, 3, 4


@dataclass(frozen=True)
class CCMConfig:
    """CCM parameters.

    Attributes:
        track_speed: crawler speed (m/s).
        front_approach: front flipper angle while approaching (rad).
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
        abort_pitch: pitch beyond which the climb is aborted (rad).
        d_flip: flipper step toward a target per 0.02 s tick (rad).
        stowed_arm: (swing, boom, elbow) of the front arms (rad): the original pose, every joint 0 (the
            paper keeps the front arms "in the original positions"); lifted_arm of the rear arms.
    """

    track_speed: float = 0.1
    front_approach: float = 1.0
    t0: float = 40.0
    d_a: float = 0.02
    a0: float = 1.0
    d_b: float = 0.02
    press_pitch: float = 0.15
    front_press: float = -0.4
    rear_push: float = -0.9
    push_pitch: float = 0.3
    flatten_pitch: float = 0.1
    level_time: float = 1.0
    abort_pitch: float = 1.0
    d_flip: float = 0.03
    stowed_arm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    lifted_arm: tuple[float, float, float] = (-1.2, -1.1, 2.4)


class CCMController:
    """``obs -> Command`` for the crawler-only mode."""

    def __init__(self, cfg: CCMConfig):
        self.cfg = cfg
        self.cmd = Command()
        self.cmd.arm[:2] = cfg.stowed_arm
        self.cmd.arm[2:] = cfg.lifted_arm
        self.cmd.flip[:] = [cfg.front_approach, cfg.front_approach, 0.0, 0.0]
        self.state = APPROACH
        self.peak = 0.0
        self.level_t = 0.0
        self.started = False
        self.events: list[tuple[float, str]] = []

    def _toward(self, i: int, target: float) -> None:
        c = self.cmd.flip
        c[i] += float(np.clip(target - c[i], -self.cfg.d_flip, self.cfg.d_flip))

    def __call__(self, obs) -> Command:
        cfg, c = self.cfg, self.cmd
        if not self.started:
            # the arms fold from wherever they start, a little at a time
            self.started = True
        c.track[:] = cfg.track_speed
        p = obs.pitch
        self.peak = max(self.peak, p)
        if self.state != ABORT and p > cfg.abort_pitch:
            self.state = ABORT
            self.events.append((obs.t, f"abort: pitch {p:.2f} rad"))
        if self.state == APPROACH:
            for f in (0, 1):
                c.flip[f], _ = flipper_rule(obs.q_flip[f], obs.tau_flip[f], cfg.t0, cfg.d_a, cfg.a0, cfg.d_b)
            # contact: the torque rule has raised the front flippers to their climbing angle and
            # they still push back (an edge on their driving side), or the nose is already rising
            at_cap = min(obs.q_flip[0], obs.q_flip[1]) > cfg.a0 - 0.05
            pushed = max(abs(obs.tau_flip[0]), abs(obs.tau_flip[1])) > cfg.t0
            if p > cfg.press_pitch or (at_cap and pushed):
                self.state = PRESS
                self.events.append((obs.t, "front flippers on the edge: press"))
        elif self.state == PRESS:
            # front flippers laid along the top (level in the world: angle = -pitch): they carry
            # the nose onto the top and drive; pressing further would only stand the robot up
            fp = max(-p, cfg.front_press)
            self._toward(0, fp)
            self._toward(1, fp)
            if p > cfg.push_pitch:
                self.state = PUSH
                self.events.append((obs.t, "rear flippers push"))
        elif self.state == PUSH:
            # pitch feedback: the front flippers stay level on the top, the rear ones push while
            # the nose is up and relax once it is down (a dip is not yet the top: no flatten)
            for f in (0, 1):
                self._toward(f, max(-p, cfg.front_press))
            for f in (2, 3):
                self._toward(f, cfg.rear_push if p > cfg.flatten_pitch else 0.0)
            self.level_t = self.level_t + 0.02 if abs(p) < 0.05 else 0.0
            if self.level_t >= cfg.level_time:
                self.state = FLATTEN
                self.events.append((obs.t, "level on the top: flatten"))
        elif self.state == FLATTEN:
            for f in range(4):
                self._toward(f, 0.0)
            if abs(p) < 0.05 and np.abs(c.flip).max() < 0.05:
                self.state, self.peak = APPROACH, 0.0
                c.flip[:2] = cfg.front_approach
        else:  # ABORT: stop, flatten the flippers
            c.track[:] = 0.0
            for f in range(4):
                self._toward(f, 0.0)
        c.mode, c.moving_arm = self.state, -1
        return c
