"""Modes and the supervisor of the HIT-MRII as one controller over the saturated IK.

The scripted *operator* of a scenario is a plan: a list of :class:`Step` (one mode action each).
Every 10 ms the controller turns the active step into a nominal command ``u_nom = (vx, vy, wz,
ddelta_L, ddelta_R)``, projects it with :class:`~terrabench.systems.srwmr.ik.SaturatedIK` and
converts it to steering angles, wheel spins and rocker targets with the inverse kinematics.

Modes (seed 001 sec. 3, Fig. 5):

* ``WRM`` wheel rolling: straight (heading held) or along waypoints (Ackermann: wz = v * curvature).
* ``WCM`` wheel crabbing: steer every wheel to +-90 deg in place (wheels spun against the offset
  so they roll, not scrub), roll sideways by ``dy``, steer back.
* ``RCLM`` chassis lifting: change the closing angle to reach a clearance while the wheels roll
  as the suspension motion requires (MC#2); ``v`` may be non-zero (lift while driving).
* ``RCM`` creeping (inchworm): cycles of lift with the front wheels still (the middle and rear
  wheels roll forward) and lower with the middle/rear wheels still (the front wheels roll).

Supervisor (sec. 7): a constraint ratio reaching its threshold halts the motion and reminds the
operator; the scripted operator answers after ``reply_s`` (None: never): an answer ends the
current action (the plan goes on), no answer within ``wait_s`` runs the mode back to its start
state; two reminders in one mode force that return. WRM switches to RCM when the climbing
efficiency over ``eff_window`` s drops below ``eff_min`` (10 %); the health monitor halts for
good when the body slip estimate stays at or above ``health_slip`` (0.96) for ``health_s``.
Mode changes are :class:`~terrabench.systems.base.Transition` records (``info()["events"]``).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from terrabench.config import check_fields, param
from terrabench.systems.base import Transition, events_info
from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.ik import IKLimits, IKState, SaturatedIK
from terrabench.systems.srwmr.kinematics import (
    delta_for_clearance,
    differential_kinematics,
    inverse_kinematics,
    period_geometry,
    steering_wait,
)
from terrabench.systems.srwmr.legged import LEGGED, LeggedAction, check_lift
from terrabench.systems.srwmr.robot import WHEEL_SIDE, RobotConfig

#: +1 for the left wheels (c1, c3, c5), -1 for the right ones
_SIDE_SIGN = np.array([1.0 if s == "L" else -1.0 for s in WHEEL_SIDE])

#: ratios the supervisor halts on (index into constraints.NAMES): the stability margins of sec. 7.1,
#: posture (MC#4, #5) and contact forces (MC#10, #11). MC#6-#9 are kept by the QP; MC#2 and #3 are
#: "feasibility prerequisites ... not considered as stability-margin indicators" [S] (the QP keeps
#: MC#3; MC#2 is logged).
MONITORED = np.array([n in ("MC4", "MC5", "MC10", "MC11") for n in mc.NAMES])
#: RCM still set: gain (1/s) of the hold on the wheels' rotation over the ground; with the 2000 N m s/rad
#: velocity servo a stiffness of 4000 N m/rad, 0.5 s time constant (terrabench choice)
HOLD_GAIN = 2.0
MODE_CODE = {"WRM": 0, "WCM": 1, "RCLM": 2, "RCM": 3, "SWLM": 4, "DWLM": 5, "HALT": 6, "REVERSE": 7, "DONE": 8}


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


@dataclass(frozen=True)
class SupervisorConfig:
    """Supervisor and scripted-operator settings.

    Attributes:
        reply_s: the operator answers a reminder after this (s); None: never answers.
        wait_s: a reminder unanswered this long reverses the mode (s).
        eff_window: climbing-efficiency window (s).  eff_min: RCM below this efficiency [S 10 %].
        health_slip: body-slip health limit [S 0.96].  health_s: held this long (s).
        slip_tau: time constant of the body-slip estimate (s).
        steer_tol: steering error below which wheels roll (rad).
        rcm_rim_ratio: RCM rolling-set rim speed per unit chassis vertical speed [S Task 4: "the
            velocities of the middle and rear wheels are set to 7.0 mm/s ... when the command
            velocity of the robot chassis is 3.6 mm/s"] (a floor over the kinematic speed).
    """

    reply_s: float | None = param(2.0, ge=0.0, le=600.0, unit="s", optional=True,
                                  doc="scripted operator's reply delay (null: never replies)")
    wait_s: float = param(10.0, gt=0.0, le=600.0, unit="s", doc="an unanswered reminder reverses the mode after this")
    eff_window: float = param(20.0, gt=0.0, le=600.0, unit="s", doc="climbing-efficiency window")
    eff_min: float = param(0.10, ge=0.0, le=1.0, doc="WRM -> RCM below this climbing efficiency [S 10 %]")
    health_slip: float = param(0.96, gt=0.0, le=1.0, doc="body-slip health limit [S 0.96]")
    health_s: float = param(5.0, gt=0.0, le=600.0, unit="s", doc="the health limit must hold this long")
    slip_tau: float = param(5.0, gt=0.0, le=600.0, unit="s", doc="time constant of the body-slip estimate")
    steer_tol: float = param(0.05, gt=0.0, le=1.0, unit="rad", doc="wheels roll once steering errors are below this")
    rcm_rim_ratio: float = param(7.0 / 3.6, ge=0.0, le=20.0,
                                 doc="RCM rolling-set rim speed per chassis vertical speed [S Task 4: 7.0/3.6]")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass
class Command:
    """What the task applies: steering targets (6,), wheel spins (6,) (rad/s), rocker closing
    targets (2,) (rad), the executed u (5,), the mode code, ratios (10,), the stop request."""

    steer: np.ndarray
    spin: np.ndarray
    delta: np.ndarray
    u: np.ndarray
    mode: int = 0
    ratios: np.ndarray = field(default_factory=lambda: np.zeros(len(mc.NAMES)))
    stop: str = ""
    step: int = 0
    clutch: tuple = (False, False)


class RoverController:
    """The scripted operator's plan, executed through the saturated IK with the supervisor."""

    def __init__(
        self, plan: list[Step], robot: RobotConfig, sup: SupervisorConfig, lim: IKLimits, sc: mc.Scales, ts: float
    ):
        for st in plan:
            if st.mode not in ("WRM", "WCM", "RCLM", "RCM") + LEGGED:
                raise ValueError(f"mode={st.mode!r} is not implemented; valid: WRM, WCM, RCLM, RCM, SWLM, DWLM")
            if st.mode in LEGGED:
                check_lift(st.mode, st.lift)  # MC#1 before any simulation
        self.plan, self.robot, self.sup, self.lim, self.sc, self.ts = list(plan), robot, sup, lim, sc, ts
        self.ik = SaturatedIK(robot, lim, sc, ts)
        self.events: list[Transition] = []
        self._kappas: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.k = -1
        self.mode = "START"
        self.u_prev = np.zeros(5)
        self.target = None
        self.origin = None
        self.reminders: dict[str, int] = {}
        self.halt_t: float | None = None
        self.returning = False
        self.stop = ""
        self.sb = 0.0
        self.vb_f = self.vc_f = 0.0
        # (t, x_progress, commanded progress), trimmed every step to what the efficiency window reads
        self.hist: deque[tuple[float, float, float]] = deque()
        self.cmd_prog = 0.0
        self.health_t: float | None = None
        self.legged: LeggedAction | None = None
        self.clutch = (False, False)
        self.legged_log: list[dict] = []

    # ---------------------------------------------------------------- bookkeeping
    def info(self) -> dict:
        out = events_info(self.events)
        out.update(self.ik.timing())
        out["reminders"] = dict(self.reminders)
        if self.legged_log or self.legged is not None:
            out["legged"] = self.legged_log + ([] if self.legged is None else self.legged.log)
        return out

    def _kappa(self, mode: str) -> tuple[np.ndarray, np.ndarray]:
        """The mode's threshold vector and the one its QP enforces (built once per mode)."""
        k = self._kappas.get(mode)
        if k is None:
            k = self._kappas[mode] = (mc.thresholds(mode), mc.qp_thresholds(mode))
        return k

    def _enter(self, t: float, mode: str, reason: str) -> None:
        if mode != self.mode:
            self.events.append(Transition(t, self.mode, mode, reason))
            self.mode = mode

    def _next(self, obs, reason: str) -> None:
        self.k += 1
        self.phase = 0
        self.returning = False
        if self.legged is not None:
            # a legged step ends with its clutches released (also after a reverse)
            self.legged_log += self.legged.log
            self.legged = None
        self.clutch = (False, False)
        if self.k >= len(self.plan):
            self._enter(obs.t, "DONE", reason)
            self.stop = self.stop or "plan complete"
            return
        st = self.plan[self.k]
        self.step_start = (obs.xy.copy(), obs.yaw, obs.delta.copy(), obs.t)
        self.cycle = 0
        if st.mode in LEGGED:
            self.legged = LeggedAction(self.robot, st, obs, self.k)
        self._enter(obs.t, st.mode, reason)

    def _local(self, obs) -> tuple[float, float, float]:
        """Pose in the start frame (x along the start heading)."""
        (x0, y0), yaw0 = self.origin
        dx, dy = obs.xy[0] - x0, obs.xy[1] - y0
        c, s = math.cos(yaw0), math.sin(yaw0)
        return c * dx + s * dy, -s * dx + c * dy, obs.yaw - yaw0

    # ---------------------------------------------------------------- the loop
    def __call__(self, obs) -> Command:
        if self.target is None:
            self.target = obs.delta.copy()
            self.origin = (obs.xy.copy(), obs.yaw)
            self.mu_cmd = obs.mu.copy()
            self._next(obs, "plan start")
        ts = self.ts
        # the kinematics of this period, once: the suspension geometry (no steering offsets) for the
        # constraints, and the contact points with the steering offsets for the wheel commands
        # (one compiled call, kinematics.period_geometry), with the hinge rise per closing angle (QP,
        # rates, ratios) and the front-middle wheelbases
        self._susp, self._geom, self._dz, self._wb = period_geometry(self.robot, obs.delta, self.mu_cmd)
        self._J = self._susp[1]
        u_nom = np.zeros(5)
        steer_only = False
        lifted = ()
        if self.stop:
            return self._command(obs, np.zeros(5), hold=True)
        # supervisor: an active halt waits for the operator
        if self.halt_t is not None:
            waited = obs.t - self.halt_t
            rep = self.sup.reply_s
            if rep is not None and waited >= rep and not self.returning:
                # (a forced return is not cut short by the reply)
                self.halt_t = None
                self.events.append(Transition(obs.t, "HALT", self.plan[self.k].mode, "operator replied: action ended"))
                st = self.plan[self.k]
                self.mode = st.mode
                # the next action of this mode: the other RCM phase, the next WCM phase, else the plan's next step
                if st.mode == "RCM":
                    self.phase = 1 - self.phase
                    self.cycle += self.phase == 0
                elif st.mode == "WCM" and self.phase < 2:
                    self.phase += 1
                    if self.phase == 1:
                        self.y_start = self._local(obs)[1]
                elif st.mode in LEGGED and self.legged is not None and self.legged.name != "restore":
                    self.legged.advance(obs, "operator replied: action ended")
                else:
                    self._next(obs, "operator: next action")
                return self._command(obs, np.zeros(5), hold=True)
            if waited >= self.sup.wait_s or self.returning:
                if not self.returning:
                    self.returning = True
                    self.events.append(Transition(obs.t, "HALT", "REVERSE", "no reply: mode reversed to its start"))
                    self.mode = "REVERSE"
                return self._reverse(obs)
            return self._command(obs, np.zeros(5), hold=True)
        st = self.plan[self.k]
        x, y, dyaw = self._local(obs)
        # --- nominal command of the step
        if st.mode == "WRM":
            u_nom, done = self._wrm(obs, st, x, y, dyaw)
        elif st.mode == "WCM":
            u_nom, done, steer_only = self._wcm(obs, st)
        elif st.mode == "RCLM":
            u_nom, done = self._rclm(obs, st)
        elif st.mode in LEGGED:
            u_nom, done = self.legged.command(self, obs, x)
            u_nom = self.legged.level(self, obs, u_nom)
            self.clutch = self.legged.clutch
            lifted = self.legged.lifted
        else:
            u_nom, done = self._rcm(obs, st, x)
        if done:
            self._next(obs, f"{st.mode} action complete")
            return self._command(obs, np.zeros(5), hold=True)
        # --- body-slip estimate, health monitor, climbing efficiency
        v_cmd = float(self.u_prev[0])
        if st.mode == "WRM" and abs(v_cmd) > 1e-4:
            # s_b = 1 - v_b / v_cmd from filtered speeds (the ratio of raw samples explodes while the
            # command ramps up from zero)
            a = ts / self.sup.slip_tau
            self.vb_f += a * (obs.v_body[0] - self.vb_f)
            self.vc_f += a * (v_cmd - self.vc_f)
            self.sb = 1.0 - self.vb_f / self.vc_f if abs(self.vc_f) >= 0.5 * abs(st.v) else 0.0
            if self.sb >= self.sup.health_slip:
                self.health_t = self.health_t if self.health_t is not None else obs.t
                if obs.t - self.health_t >= self.sup.health_s:
                    self.events.append(
                        Transition(
                            obs.t,
                            self.mode,
                            "HALT",
                            f"health monitor: body slip {self.sb:.2f} >= {self.sup.health_slip}",
                        )
                    )
                    self.mode = "HALT"
                    self.stop = f"health halt: body slip {self.sb:.2f} >= {self.sup.health_slip}"
                    return self._command(obs, np.zeros(5), hold=True)
            else:
                self.health_t = None
            self.cmd_prog += v_cmd * ts
            hist, window = self.hist, self.sup.eff_window
            hist.append((obs.t, x, self.cmd_prog))
            # an entry older than one that is already a window old is never read again
            while len(hist) > 1 and obs.t - hist[1][0] >= window:
                hist.popleft()
            if st.auto_rcm and obs.t - hist[0][0] >= window:
                while hist and obs.t - hist[0][0] > window:
                    hist.popleft()
                t0, x0, c0 = self.hist[0]
                eff = (x - x0) / max(self.cmd_prog - c0, 1e-6)
                if eff < self.sup.eff_min:
                    self.plan.insert(self.k + 1, Step("RCM", v=st.v, cycles=999, amp=0.3, until_x=st.until_x))
                    self.hist.clear()
                    self._next(obs, f"climbing efficiency {eff:.0%} < {self.sup.eff_min:.0%}")
                    return self._command(obs, np.zeros(5), hold=True)
        # --- constraint-saturated IK
        kappa, kappa_qp = self._kappa(st.mode)
        J, wb = self._J, self._wb
        u = self.ik.solve(u_nom, IKState(obs.delta, self.u_prev), kappa_qp, J, wb, dz=self._dz)
        if u is None:
            return self._halt(obs, "IK infeasible (no command satisfies the constraints)")
        ratios = self._ratios(obs, u, J, wb)
        if st.mode in LEGGED:
            # a clutched side lifts a wheel, not its hinge: MC#4 is the measured left-right hinge
            # height difference (IMU roll over the hinge track), not the symmetric-lift model's
            ratios[2] = mc.eta_roll(np.array([self.robot.hinge_track * math.sin(float(obs.rpy[0])), 0.0]), self.sc)
        # the QP keeps the command ratios (MC6-MC9) at or below kappa; the supervisor halts on the
        # measured state ratios: MC2 (coordination), MC3-MC5 (posture), MC10/MC11 (loads)
        i = mc.halting_ratio(ratios, kappa, MONITORED)  # the largest ratio / kappa >= 1, or -1
        if i >= 0:
            return self._halt(obs, f"{mc.NAMES[i]} ratio {ratios[i]:.2f} >= {kappa[i]:.2f}")
        return self._command(obs, u, steer_only=steer_only, lifted=lifted, ratios=ratios)

    # ---------------------------------------------------------------- modes
    def _wrm(self, obs, st: Step, x, y, dyaw):
        if st.waypoints:
            pts = np.asarray(st.waypoints, float)
            i = min(getattr(self, "wp", 0), len(pts) - 1)
            p = np.array([x, y])
            while i < len(pts) - 1 and np.linalg.norm(pts[i] - p) < 0.4:
                i += 1
            self.wp = i
            tx, ty = pts[i] - p
            if i == len(pts) - 1 and math.hypot(tx, ty) < 0.05:
                self.wp = 0
                return np.zeros(5), True
            # pure pursuit: curvature to the look-ahead point in the body frame
            c, s = math.cos(dyaw), math.sin(dyaw)
            bx, by = c * tx + s * ty, -s * tx + c * ty
            L2 = bx * bx + by * by
            kappa_c = 2 * by / max(L2, 1e-6)
            kappa_c = max(-0.8, min(0.8, kappa_c))
            return np.array([st.v, 0.0, st.v * kappa_c, 0.0, 0.0]), False
        goal = st.until_x if st.until_x is not None else self._start_x() + st.dist
        if x >= goal:
            return np.zeros(5), True
        # hold the start heading and line (small corrections)
        wz = -0.5 * dyaw - 0.5 * (y - self._start_y()) * 0.2
        # the correction's curvature stays below 0.5 /m (no steering swing while the speed ramps up)
        lim = min(0.02, 0.5 * abs(float(self.u_prev[0])))
        return np.array([st.v, 0.0, max(-lim, min(lim, wz)), 0.0, 0.0]), False

    def _start_x(self):
        (x0, y0), yaw0 = self.origin
        p = self.step_start[0]
        return math.cos(yaw0) * (p[0] - x0) + math.sin(yaw0) * (p[1] - y0)

    def _start_y(self):
        (x0, y0), yaw0 = self.origin
        p = self.step_start[0]
        return -math.sin(yaw0) * (p[0] - x0) + math.cos(yaw0) * (p[1] - y0)

    def _wcm(self, obs, st: Step):
        # phase 0: steer to +-90 in place; 1: roll sideways; 2: steer back to 0
        sgn = 1.0 if st.dy >= 0 else -1.0
        if st.dx:
            # a crab along a straight line at atan2(dy, dx), folded into (-90, 90] deg (spin sign)
            a = math.atan2(st.dy, st.dx)
            fold = a if abs(a) <= math.pi / 2 else a - math.copysign(math.pi, a)
            goal, run = fold, math.hypot(st.dx, st.dy)
        else:
            goal, run = math.pi / 2 * 0.999, abs(st.dy)
        if self.phase == 0:
            self.mu_goal = np.full(6, goal)
            if np.max(np.abs(obs.mu - self.mu_goal)) < self.sup.steer_tol:
                self.phase, self.y_start = 1, self._local(obs)[1]
            return np.zeros(5), False, True
        if self.phase == 1:
            lx, ly, dyaw = self._local(obs)
            if st.dx:
                x0 = getattr(self, "x_crab", None)
                if x0 is None or getattr(self, "_crab_k", None) != self.k:
                    self._crab_k, self.x_crab = self.k, lx
                    x0 = lx
                done = (lx - x0) * math.cos(math.atan2(st.dy, st.dx)) + (ly - self.y_start) * math.sin(
                    math.atan2(st.dy, st.dx)) >= run
            else:
                done = abs(ly - self.y_start) >= run
            if done:
                self.phase = 2
                return np.zeros(5), False, True
            wz = max(-0.01, min(0.01, -0.5 * dyaw))
            if st.dx:
                c, s_ = math.cos(math.atan2(st.dy, st.dx)), math.sin(math.atan2(st.dy, st.dx))
                return np.array([st.v * c, st.v * s_, wz, 0.0, 0.0]), False, False
            return np.array([0.0, sgn * st.v, wz, 0.0, 0.0]), False, False
        self.mu_goal = np.zeros(6)
        if np.max(np.abs(obs.mu)) < self.sup.steer_tol:
            self.mu_goal = None
            return np.zeros(5), True, False
        return np.zeros(5), False, True

    def _rate_for(self, obs, vz: float, target_delta: float) -> np.ndarray:
        """Closing rates (2,) lifting the chassis at ``vz`` towards ``target_delta``."""
        dz = self._dz
        err = target_delta - obs.delta
        rate = np.sign(err) * abs(vz) / np.maximum(dz, 1e-3)
        slow = np.minimum(1.0, np.abs(err) / 0.02)
        return rate * slow

    def _rclm(self, obs, st: Step):
        if getattr(self, "_td_step", None) != self.k:
            self._td_step, self._td = self.k, delta_for_clearance(self.robot, st.clearance)
        td = self._td
        if np.max(np.abs(obs.delta - td)) < 0.004:
            return np.zeros(5), True
        rate = self._rate_for(obs, st.vz, td)
        return np.array([st.v, 0.0, st.wz, rate[0], rate[1]]), False

    def _rcm(self, obs, st: Step, x):
        """Inchworm: phase 0 lift (front wheels still), phase 1 lower (middle/rear still)."""
        if st.until_x is not None and x >= st.until_x:
            return np.zeros(5), True
        d0 = self.step_start[2]
        base = float(np.mean(d0))
        hi = base + st.amp
        J = self._J
        if self.phase == 0:
            if np.min(obs.delta) >= hi - 0.004:
                self.phase = 1
            rate = self._rate_for(obs, st.vz * 2, hi)
            # the front wheels stay where they are: v_b = -J_front,x * rate
            vx = -float(np.mean(J[0:2, 0] * rate))
            self._rolling = ([2, 3, 4, 5], self.sup.rcm_rim_ratio * st.vz * 2)
        else:
            if np.max(obs.delta) <= base + 0.004:
                self.phase = 0
                self.cycle += 1
                if self.cycle >= st.cycles:
                    return np.zeros(5), True
            rate = self._rate_for(obs, st.vz * 2, base)
            vx = -float(np.mean(J[2:6, 0] * np.repeat(rate, 2)))
            self._rolling = ([0, 1], self.sup.rcm_rim_ratio * st.vz * 2)
        return np.array([vx, 0.0, 0.0, rate[0], rate[1]]), False

    def _hold_still(self, obs, rolling) -> np.ndarray:
        """RCM: spin correction that keeps the still set's contact patches in place (docs/srwmr.md, RCM).

        A wheel turns over the ground at its joint rate plus the pitch rate of the link carrying it:
        chassis gyro + z x closing rate (front section), gyro - closing rate + bogie rate (rear section
        and bogie). With its joint held the front wheels rolled forward ~27 mm per lift on the rocker's
        rotation. The still wheels are commanded minus their link rate, plus a hold (gain HOLD_GAIN) on
        their rotation over the ground since the phase began (the velocity servo's droop under load)."""
        still = np.ones(6, bool)
        still[list(rolling)] = False
        key = tuple(np.flatnonzero(still))
        if getattr(self, "_still_key", None) != key:
            self._still_key, self._still_rot, self._zeta_prev = key, np.zeros(6), obs.zeta.copy()
        side = np.array([0, 1, 0, 1, 0, 1])
        zd = (obs.zeta - self._zeta_prev) / self.ts
        self._zeta_prev = obs.zeta.copy()
        link = obs.gyro[1] + np.where(np.arange(6) < 2, self.robot.z_ratio * obs.ddelta[side],
                                      -obs.ddelta[side] + zd[side])
        self._still_rot += (obs.spin + link) * self.ts
        return np.where(still, -link - HOLD_GAIN * self._still_rot, 0.0)

    # ---------------------------------------------------------------- supervisor actions
    def _halt(self, obs, reason: str) -> Command:
        mode = self.plan[self.k].mode
        n = self.reminders.get(mode, 0) + 1
        self.reminders[mode] = n
        self.events.append(Transition(obs.t, mode, "HALT", f"reminder {n}: {reason}"))
        self.mode = "HALT"
        self.halt_t = obs.t
        if n >= 2:
            self.returning = True
            self.events.append(Transition(obs.t, "HALT", "REVERSE", "second reminder in this mode: forced return"))
            self.mode = "REVERSE"
        return self._command(obs, np.zeros(5), hold=True)

    def _reverse(self, obs) -> Command:
        """Run the suspension back to the step's start angles (wheels coordinated), then go on."""
        d0 = self.step_start[2]
        lg = self.legged
        back = np.max(np.abs(obs.delta - d0)) < 0.004
        if lg is not None:
            # SWLM / DWLM: lower the wheel with the clutch engaged, release, restore (legged.py)
            if not getattr(lg, "reversing", False):
                lg.reverse(obs)
                lg.reversing = True
            u, back = lg.command(self, obs, self._local(obs)[0])
            u = lg.level(self, obs, u)
            self.clutch = lg.clutch
            if not back:
                return self._command(obs, u, lifted=lg.lifted)
        if back:
            self.halt_t = None
            self.returning = False
            self.events.append(Transition(obs.t, "REVERSE", self.plan[self.k].mode, "back at the start state"))
            self.mode = self.plan[self.k].mode
            self._next(obs, "after return")
            return self._command(obs, np.zeros(5), hold=True)
        rate = self._rate_for(obs, 0.0036, float(np.mean(d0)))
        return self._command(obs, np.array([0.0, 0.0, 0.0, rate[0], rate[1]]))

    # ---------------------------------------------------------------- output
    def _ratios(self, obs, u, J, wb) -> np.ndarray:
        """The ratios eta of :data:`constraints.NAMES` this period (``constraints.period_ratios``,
        compiled: the expressions of ``eta_roll``, ``eta_yaw``, ... on scalars). MC2: while the
        suspension moves, the commanded rim speeds against the speeds the suspension motion requires
        (the RCM rolling set runs above them on purpose: it shows here)."""
        return mc.period_ratios(self.robot, self.sc, u, self.u_prev, J, self._dz, wb, obs.delta, obs.ddelta,
                                obs.mu, obs.load, getattr(self, "_rim_cmd", None))

    def _command(self, obs, u, *, hold: bool = False, steer_only: bool = False, lifted=(), ratios=None) -> Command:
        ts = self.ts
        goal = getattr(self, "mu_goal", None)
        if goal is not None and (steer_only or self.plan[min(self.k, len(self.plan) - 1)].mode == "WCM"):
            # steering in place (WCM): rate-limited targets, wheels spun against the offset
            step = np.clip(goal - self.mu_cmd, -0.3 * ts, 0.3 * ts)
            mu_rate = step / ts
            self.mu_cmd = self.mu_cmd + step
            if steer_only:
                # the contact of an offset wheel moves along its heading by -e mu_dot on the left and
                # +e mu_dot on the right (offset outwards on both sides): rolled out, not scrubbed
                spin = -_SIDE_SIGN * self.robot.wheel_offset * mu_rate / self.robot.wheel_radius
                self._rim_cmd = spin * self.robot.wheel_radius
                self.u_prev = np.zeros(5)
                return Command(
                    self.mu_cmd.copy(),
                    spin,
                    self.target.copy(),
                    np.zeros(5),
                    MODE_CODE.get(self.mode, 9),
                    np.zeros(len(mc.NAMES)) if ratios is None else ratios,
                    self.stop,
                    self.k,
                    self.clutch,
                )
        if self.plan[min(self.k, len(self.plan) - 1)].diff:
            mu, spin = differential_kinematics(self.robot, u, self._susp)
        else:
            mu, spin = inverse_kinematics(
                self.robot, u, obs.delta, mu_prev=self.mu_cmd, lifted=lifted, geom=getattr(self, "_geom", None)
            )
        rolling = getattr(self, "_rolling", None)
        if rolling is not None:
            # RCM: the rolling set turns at least at the paper's wheel/chassis speed ratio (it must slip
            # to pull: a wheel at the kinematic rim speed has zero slip and only rolling resistance)
            idx, v_rim = rolling
            spin[idx] = np.maximum(spin[idx], v_rim / self.robot.wheel_radius)
            spin = spin + self._hold_still(obs, idx)
            self._rolling = None
        # a wheel whose steering is far from its target waits (no rolling against its heading)
        if steering_wait(mu, obs.mu, u, 0.15):
            spin = spin * 0.0
        self.mu_cmd = mu
        self.target = self.target + u[3:5] * ts
        self._rim_cmd = spin * self.robot.wheel_radius
        self.u_prev = np.asarray(u, float).copy()
        return Command(
            mu.copy(),
            spin,
            self.target.copy(),
            self.u_prev.copy(),
            MODE_CODE.get(self.mode, 9),
            np.zeros(len(mc.NAMES)) if ratios is None else ratios,
            self.stop,
            self.k,
            self.clutch,
        )
