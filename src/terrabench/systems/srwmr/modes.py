"""The rover's locomotion modes as objects: each turns the active plan step into a nominal command.

One object per plan step (:func:`action_for`), created when the step starts, so every piece of
per-step state (a waypoint index, a crab's start, an inchworm's phase) is born with its step.
Every mode answers the same protocol (:class:`ModeAction`), and the controller
(:class:`~terrabench.systems.srwmr.control.RoverController`) reads nothing else of it:

* :meth:`ModeAction.nominal`: ``u_nom = (vx, vy, wz, ddelta_L, ddelta_R)`` of this period and
  whether the step is complete (:class:`Nominal`);
* :meth:`ModeAction.reply`: the operator answered a reminder: True if the mode moves on inside
  the step (the other RCM phase, the next WCM phase, the next legged action), False if the
  answer ends the step;
* :meth:`ModeAction.unwind`: the supervisor's return to the step's start state, or None for the
  default (the suspension driven back to its start angles).

The wheel modes live here (seed 001 sec. 3, Fig. 5); SWLM / DWLM (:class:`WheelLegged`) run the
action sequence of :class:`~terrabench.systems.srwmr.legged.LeggedAction`. What a mode may read of the controller is
public: ``robot``, ``sup``, ``lim``, ``sc``, ``ts``, ``u_prev``, ``period`` (this period's geometry),
``step_start``, ``local(obs)`` and ``closing_rate(obs, vz, target)``; what it may set is
``steer_goal`` (steering in place) and ``rolling`` (RCM's rolling set for this period's command).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from terrabench.systems.srwmr.constraints import CONSTRAINTS
from terrabench.systems.srwmr.kinematics import delta_for_clearance
from terrabench.systems.srwmr.legged import LEGGED, LeggedAction

#: MC#7 (the forward speed's change per period), whose ramp WCM's roll follows along its heading
_MC7 = next(c for c in CONSTRAINTS if c.name == "MC7")


@dataclass(frozen=True)
class Step:
    """One action of the operator's plan.

    Attributes:
        mode: WRM, WCM, RCLM or RCM.
        v: forward speed (m/s) (WCM: the sideways speed).
        dist: WRM/WCM distance (m) (RCLM: ignored).
        waypoints: WRM path ((x, y), ...) in the start frame; empty = straight ahead.
        dy: WCM sideways displacement (m) (> 0 to the left).
        dx: WCM forward displacement (m) of the same crab: the wheels steer to atan2(dy, dx) and the
            body moves straight along it (0: sideways, +-90 deg).
        wz: RCLM yaw rate (rad/s) commanded while the chassis moves (Task 15).
        diff: differential steering: every steering angle held at 0, the sides' rim speeds differ
            (the paper's 3-D differential-drive model, Task 15); False: all-wheel steering.
        clearance: RCLM target clearance (m).
        vz: RCLM chassis vertical speed (m/s).
        cycles: RCM cycles.  amp: RCM closing-angle swing per cycle (rad).
        auto_rcm: WRM: switch to RCM when the climbing efficiency drops below the threshold.
        until_x: WRM/RCM: the step ends once the start-frame x passes this (m) (None: dist).
        lift: SWLM/DWLM wheels lifted (MC#1: one wheel / a symmetric pair, e.g. ("c2",), ("c1", "c2")).
        height: SWLM/DWLM lift height (m) of the wheel above its side's grounded axles.
        shift: SWLM/DWLM clearance (m) of the CoM shift before the lift (None: by wheel position,
            :data:`~terrabench.systems.srwmr.legged.SHIFT`). SWLM/DWLM ``dist``: the roll while lifted.
        clearance_r: RCLM clearance (m) of the right side's hinge (None: ``clearance`` for both; an
            asymmetric lift, group ``ik``).
        steer_s: RCLM: with the clearance at its target the step holds it and goes on until this long
            (s) after its start (in-place steering at a held clearance, the paper's sec. 8.6; None: the
            step ends at its target).
        hold_s: RCLM: the step ends after this long (s) even short of its target (None: at the
            target only): a lift commanded against a limit the QP holds it at (group ``ik``).
        qp: False: the constraint-saturated projection is bypassed and the nominal command executed
            (group ``ik``'s ``-noqp`` twins; the supervisor still watches the ratios).
        qp_about_target: the QP's rows linearised about the rockers' servo targets (the integrated
            command) instead of the measured closing angles (group ``ik``'s ``-target`` variants).
        halt_tol: the supervisor halts on a monitored ratio above ``kappa (1 + halt_tol)`` (0: at
            kappa, the default): a ratio the QP holds at its kappa is then no halt (group ``ik``).
        trace: keep the per-period QP trace (:mod:`~terrabench.systems.srwmr.qp_trace`) in the
            trial's info (group ``ik``).
    """

    mode: str
    v: float = 0.025
    dist: float = 1.0
    waypoints: tuple = ()
    dy: float = 0.0
    dx: float = 0.0
    wz: float = 0.0
    diff: bool = False
    clearance: float = 0.25
    vz: float = 0.0036
    cycles: int = 1
    amp: float = 0.3
    auto_rcm: bool = False
    until_x: float | None = None
    lift: tuple = ()
    height: float = 0.18
    shift: float | None = None
    clearance_r: float | None = None
    hold_s: float | None = None
    steer_s: float | None = None
    qp: bool = True
    qp_about_target: bool = False
    halt_tol: float = 0.0
    trace: bool = False


@dataclass
class Nominal:
    """A mode's output for one period: ``u`` (5,), ``done`` (the step is complete),
    ``steer_only`` (the wheels steer in place, no IK), ``lifted`` (wheel indices off the ground)
    and ``clutch`` ((L, R) engaged, None: the mode does not drive the clutches)."""

    u: np.ndarray
    done: bool = False
    steer_only: bool = False
    lifted: tuple = ()
    clutch: tuple[bool, bool] | None = None


class ModeAction(Protocol):
    """One plan step being executed (see the module docstring)."""

    def nominal(self, ctl: Any, obs: Any, x: float, y: float, dyaw: float) -> Nominal: ...

    def reply(self, ctl: Any, obs: Any) -> bool: ...

    def unwind(self, ctl: Any, obs: Any) -> Nominal | None: ...


class _Mode:
    """Defaults: an operator's answer ends the step; the supervisor's return is the default one."""

    def __init__(self, step: Any) -> None:
        self.st = step

    def reply(self, ctl: Any, obs: Any) -> bool:
        return False

    def unwind(self, ctl: Any, obs: Any) -> Nominal | None:
        return None


class WheelRolling(_Mode):
    """WRM: straight (the start heading and line held) or along waypoints (pure pursuit, Ackermann
    wz = v * curvature), until ``dist`` or ``until_x``."""

    def __init__(self, step: Any) -> None:
        super().__init__(step)
        self.wp = 0  # the waypoint being pursued

    def nominal(self, ctl: Any, obs: Any, x: float, y: float, dyaw: float) -> Nominal:
        st = self.st
        if st.waypoints:
            pts = np.asarray(st.waypoints, float)
            i = min(self.wp, len(pts) - 1)
            p = np.array([x, y])
            while i < len(pts) - 1 and np.linalg.norm(pts[i] - p) < 0.4:
                i += 1
            self.wp = i
            tx, ty = pts[i] - p
            if i == len(pts) - 1 and math.hypot(tx, ty) < 0.05:
                self.wp = 0
                return Nominal(np.zeros(5), True)
            # pure pursuit: curvature to the look-ahead point in the body frame
            c, s = math.cos(dyaw), math.sin(dyaw)
            bx, by = c * tx + s * ty, -s * tx + c * ty
            L2 = bx * bx + by * by
            kappa_c = 2 * by / max(L2, 1e-6)
            kappa_c = max(-0.8, min(0.8, kappa_c))
            return Nominal(np.array([st.v, 0.0, st.v * kappa_c, 0.0, 0.0]))
        x_start, y_start = ctl.start_local()
        goal = st.until_x if st.until_x is not None else x_start + st.dist
        if x >= goal:
            return Nominal(np.zeros(5), True)
        # hold the start heading and line (small corrections)
        wz = -0.5 * dyaw - 0.5 * (y - y_start) * 0.2
        # the correction's curvature stays below 0.5 /m (no steering swing while the speed ramps up)
        lim = min(0.02, 0.5 * abs(float(ctl.u_prev[0])))
        return Nominal(np.array([st.v, 0.0, max(-lim, min(lim, wz)), 0.0, 0.0]))


class WheelCrabbing(_Mode):
    """WCM: phase 0 steers every wheel to +-90 deg (or to atan2(dy, dx)) in place, phase 1 rolls
    along that direction by the step's displacement, phase 2 steers back to 0."""

    def __init__(self, step: Any) -> None:
        super().__init__(step)
        self.phase = 0
        self.y_start = 0.0  # start-frame y when the roll began (m)
        self.x_start: float | None = None  # start-frame x when an oblique roll began (m)

    def reply(self, ctl: Any, obs: Any) -> bool:
        if self.phase >= 2:
            return False
        self.phase += 1
        if self.phase == 1:
            self.y_start = ctl.local(obs)[1]
        return True

    def nominal(self, ctl: Any, obs: Any, x: float, y: float, dyaw: float) -> Nominal:
        st = self.st
        sgn = 1.0 if st.dy >= 0 else -1.0
        if st.dx:
            # a crab along a straight line at atan2(dy, dx), folded into (-90, 90] deg (spin sign)
            a = math.atan2(st.dy, st.dx)
            fold = a if abs(a) <= math.pi / 2 else a - math.copysign(math.pi, a)
            goal, run = fold, math.hypot(st.dx, st.dy)
        else:
            goal, run = math.pi / 2 * 0.999, abs(st.dy)
        if self.phase == 0:
            ctl.steer_goal = np.full(6, goal)
            if np.max(np.abs(obs.mu - ctl.steer_goal)) < ctl.sup.steer_tol:
                self.phase, self.y_start = 1, ctl.local(obs)[1]
            return Nominal(np.zeros(5), steer_only=True)
        if self.phase == 1:
            lx, ly, dyaw = ctl.local(obs)
            if st.dx:
                if self.x_start is None:
                    self.x_start = lx
                x0 = self.x_start
                done = (lx - x0) * math.cos(math.atan2(st.dy, st.dx)) + (ly - self.y_start) * math.sin(
                    math.atan2(st.dy, st.dx)) >= run
            else:
                done = abs(ly - self.y_start) >= run
            if done:
                self.phase = 2
                return Nominal(np.zeros(5), steer_only=True)
            if not st.dx:
                wz = max(-0.01, min(0.01, -0.5 * dyaw))
                return Nominal(np.array([0.0, sgn * st.v, wz, 0.0, 0.0]))
            # an oblique crab rolls along the wheels' heading as WRM rolls along its own ("WRM is
            # utilized as the action (2) of WCM" [S sec. 3, the control-process figure's caption]):
            # its speed along that heading ramps as MC#7 ramps WRM's forward speed, so the commanded
            # direction stays the steered one (the QP's MC#7 row bounds vx only: vy at full speed from
            # the first period with vx ramping swung the commanded heading from 34 to 90 deg, the IK
            # re-steered every wheel in the soil at once and T9 halted on MC#11 30 ms later). A
            # sideways crab (dx = 0) has vx = 0 and no such swing.
            a = math.atan2(st.dy, st.dx)
            c, s_ = math.cos(a), math.sin(a)
            along = abs(float(ctl.u_prev[0] * c + ctl.u_prev[1] * s_))
            speed = min(abs(st.v), along + _MC7.kappa(st.mode) * max(along, ctl.sc.v_floor))
            # the heading hold's curvature stays below 0.5 /m, as WRM's (no steering swing while the
            # speed ramps up: a 0.003 rad/s correction against 0.05 mm/s would steer every wheel onto a
            # turn in place)
            lim = min(0.01, 0.5 * speed)
            wz = max(-lim, min(lim, -0.5 * dyaw))
            return Nominal(np.array([speed * c, speed * s_, wz, 0.0, 0.0]))
        ctl.steer_goal = np.zeros(6)
        if np.max(np.abs(obs.mu)) < ctl.sup.steer_tol:
            ctl.steer_goal = None
            return Nominal(np.zeros(5), True)
        return Nominal(np.zeros(5), steer_only=True)


class ChassisLifting(_Mode):
    """RCLM: the closing angle driven to the step's clearance at ``vz`` while the wheels roll as
    the suspension motion requires (MC#2); ``v`` and ``wz`` may be non-zero (Tasks 10, 15)."""

    def __init__(self, step: Any, robot: Any) -> None:
        super().__init__(step)
        self.target = delta_for_clearance(robot, step.clearance)
        if step.clearance_r is not None:  # an asymmetric lift: (left, right) closing targets
            self.target = np.array([self.target, delta_for_clearance(robot, step.clearance_r)])

    def nominal(self, ctl: Any, obs: Any, x: float, y: float, dyaw: float) -> Nominal:
        st, td = self.st, self.target
        if np.max(np.abs(obs.delta - td)) < 0.004 and (st.steer_s is None
                                                        or obs.t - ctl.step_start[3] >= st.steer_s):
            return Nominal(np.zeros(5), True)
        if st.hold_s is not None and obs.t - ctl.step_start[3] >= st.hold_s:
            return Nominal(np.zeros(5), True)
        rate = ctl.closing_rate(obs, st.vz, td)
        return Nominal(np.array([st.v, 0.0, st.wz, rate[0], rate[1]]))


class Creeping(_Mode):
    """RCM (inchworm): phase 0 lifts with the front wheels still (the middle and rear wheels roll
    forward), phase 1 lowers with the middle and rear wheels still (the front wheels roll); the
    rolling set of each phase is handed to the command (``ctl.rolling``)."""

    def __init__(self, step: Any) -> None:
        super().__init__(step)
        self.phase = 0
        self.cycle = 0

    def reply(self, ctl: Any, obs: Any) -> bool:
        self.phase = 1 - self.phase
        self.cycle += self.phase == 0
        return True

    def nominal(self, ctl: Any, obs: Any, x: float, y: float, dyaw: float) -> Nominal:
        st = self.st
        if st.until_x is not None and x >= st.until_x:
            return Nominal(np.zeros(5), True)
        d0 = ctl.step_start[2]
        base = float(np.mean(d0))
        hi = base + st.amp
        J = ctl.period.J
        if self.phase == 0:
            if np.min(obs.delta) >= hi - 0.004:
                self.phase = 1
            rate = ctl.closing_rate(obs, st.vz * 2, hi)
            # the front wheels stay where they are: v_b = -J_front,x * rate
            vx = -float(np.mean(J[0:2, 0] * rate))
            ctl.rolling = ([2, 3, 4, 5], ctl.sup.rcm_rim_ratio * st.vz * 2)
        else:
            if np.max(obs.delta) <= base + 0.004:
                self.phase = 0
                self.cycle += 1
                if self.cycle >= st.cycles:
                    return Nominal(np.zeros(5), True)
            rate = ctl.closing_rate(obs, st.vz * 2, base)
            vx = -float(np.mean(J[2:6, 0] * np.repeat(rate, 2)))
            ctl.rolling = ([0, 1], ctl.sup.rcm_rim_ratio * st.vz * 2)
        return Nominal(np.array([vx, 0.0, 0.0, rate[0], rate[1]]))


class WheelLegged(_Mode):
    """SWLM / DWLM: the action sequence of :class:`~terrabench.systems.srwmr.legged.LeggedAction`
    (shift, clutch, lift, roll, lower, release, restore), levelled, with its clutches."""

    def __init__(self, step: Any, robot: Any, obs: Any, k: int) -> None:
        super().__init__(step)
        self.seq = LeggedAction(robot, step, obs, k)
        self.reversing = False  # the supervisor's return has begun (:meth:`unwind`)

    def _out(self, ctl: Any, obs: Any, u: np.ndarray, done: bool) -> Nominal:
        return Nominal(self.seq.level(ctl, obs, u), done, False, self.seq.lifted, self.seq.clutch)

    def nominal(self, ctl: Any, obs: Any, x: float, y: float, dyaw: float) -> Nominal:
        u, done = self.seq.command(ctl, obs, x)
        return self._out(ctl, obs, u, done)

    def reply(self, ctl: Any, obs: Any) -> bool:
        """The answer ends the current action (the step goes on), except while restoring."""
        if self.seq.name == "restore":
            return False
        self.seq.advance(obs, "operator replied: action ended")
        return True

    def unwind(self, ctl: Any, obs: Any) -> Nominal:
        """The wheel lowered with the clutch engaged, released, the clearance restored
        (:meth:`LeggedAction.reverse`, then the remaining actions); ``done`` once back."""
        if not self.reversing:
            self.seq.reverse(obs)
            self.reversing = True
        u, back = self.seq.command(ctl, obs, ctl.local(obs)[0])
        return self._out(ctl, obs, u, back)


#: plan-step mode -> its action class
MODE_CLASSES = {"WRM": WheelRolling, "WCM": WheelCrabbing, "RCLM": ChassisLifting, "RCM": Creeping,
                "SWLM": WheelLegged, "DWLM": WheelLegged}
#: every mode a plan step may name
MODES = tuple(MODE_CLASSES)


def action_for(step: Any, robot: Any, obs: Any, k: int) -> ModeAction:
    """The action object executing plan step ``k`` (``step.mode`` one of :data:`MODES`)."""
    if step.mode in LEGGED:
        return WheelLegged(step, robot, obs, k)
    if step.mode == "RCLM":
        return ChassisLifting(step, robot)
    return MODE_CLASSES[step.mode](step)
