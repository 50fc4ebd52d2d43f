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
efficiency over ``eff_window`` s drops below ``eff_min`` (10 %); the health monitor (WRM and a
legged step's roll) halts for good when the body slip estimate stays at or above ``health_slip``
(0.96) for ``health_s`` while the rover is commanded to move.
Mode changes are :class:`~terrabench.systems.base.Transition` records (``info()["events"]``).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from terrabench.sim.checks import DONE, HALT, StopRequest
from terrabench.systems.base import MachineController, ModeMachine
from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.config import SupervisorConfig
from terrabench.systems.srwmr.ik import IKLimits, IKState, SaturatedIK
from terrabench.systems.srwmr.kinematics import (
    differential_kinematics,
    inverse_kinematics,
    period_geometry,
    steering_wait,
)
from terrabench.systems.srwmr.legged import LEGGED, LeggedAction, check_lift
from terrabench.systems.srwmr.modes import MODES, ModeAction, Step, WheelLegged, action_for
from terrabench.systems.srwmr.robot import WHEEL_SIDE, RobotConfig

#: +1 for the left wheels (c1, c3, c5), -1 for the right ones
_SIDE_SIGN = np.array([1.0 if s == "L" else -1.0 for s in WHEEL_SIDE])

#: RCM still set: gain (1/s) of the hold on the wheels' rotation over the ground; with the 2000 N m s/rad
#: velocity servo a stiffness of 4000 N m/rad, 0.5 s time constant (terrabench choice)
HOLD_GAIN = 2.0
MODE_CODE = {"WRM": 0, "WCM": 1, "RCLM": 2, "RCM": 3, "SWLM": 4, "DWLM": 5, "HALT": 6, "REVERSE": 7, "DONE": 8}


@dataclass
class Command:
    """What the task applies: steering targets (6,), wheel spins (6,) (rad/s), rocker closing
    targets (2,) (rad), the executed u (5,), the mode code, ratios (10,), the stop request (None:
    go on), the plan step's index, the clutches (L, R)."""

    steer: np.ndarray
    spin: np.ndarray
    delta: np.ndarray
    u: np.ndarray
    mode: int = 0
    ratios: np.ndarray = field(default_factory=lambda: np.zeros(len(mc.NAMES)))
    stop: StopRequest | None = None
    step: int = 0
    clutch: tuple = (False, False)


class Period(NamedTuple):
    """The kinematics of one control period, computed once (:func:`~terrabench.systems.srwmr.
    kinematics.period_geometry`): the suspension geometry without steering offsets (for the
    constraints; ``J`` its Jacobian), the contact geometry with them (for the wheel commands),
    the hinge rise per closing angle ``dz`` (2,) and the front-middle wheelbases ``wb``."""

    susp: Any
    geom: Any
    dz: np.ndarray
    wb: Any

    @property
    def J(self) -> np.ndarray:
        return self.susp[1]


class RoverController(MachineController):
    """The scripted operator's plan, executed through the saturated IK with the supervisor.

    The plan's steps run one after another, each as a mode object
    (:func:`~terrabench.systems.srwmr.modes.action_for`); the supervisor (halts, reminders, the
    return to a step's start state, the health monitor, the WRM -> RCM switch) is this class. The
    mode the rover is in is a :class:`~terrabench.systems.base.ModeMachine`: the plan's modes and
    the supervisor's ``HALT``, ``REVERSE`` and ``DONE``, every change recorded by the machine.
    """

    def __init__(
        self, plan: list[Step], robot: RobotConfig, sup: SupervisorConfig, lim: IKLimits, sc: mc.Scales, ts: float
    ):
        for st in plan:
            if st.mode not in MODES:
                raise ValueError(f"mode={st.mode!r} is not implemented; valid: {', '.join(MODES)}")
            if st.mode in LEGGED:
                check_lift(st.mode, st.lift)  # MC#1 before any simulation
        self.plan, self.robot, self.sup, self.lim, self.sc, self.ts = list(plan), robot, sup, lim, sc, ts
        self.ik = SaturatedIK(robot, lim, sc, ts)
        self._ratio_k = mc.ratio_consts(robot, sc)  # the scalars the ratio kernel reads, once
        self.machine = ModeMachine("START")
        self._kappas: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.k = -1
        self.action: ModeAction | None = None  # the plan step being executed
        self.step_start: tuple | None = None  # (xy, yaw, delta, t) when the step began
        self.period: Period | None = None
        self.u_prev = np.zeros(5)
        self.target: np.ndarray | None = None  # rocker closing targets (2,) (rad)
        self.origin: tuple | None = None  # (xy, yaw) of the plan's start frame
        self.mu_cmd: np.ndarray | None = None  # steering commands (6,) (rad)
        self.steer_goal: np.ndarray | None = None  # steering in place (WCM) towards this (6,)
        self.rolling: tuple | None = None  # RCM: (wheel indices, rim speed) of this period's rolling set
        self.rim_cmd: np.ndarray | None = None  # the last commanded rim speeds (6,) (m/s), MC#2's input
        self.reminders: dict[str, int] = {}
        self.halt_t: float | None = None
        self.returning = False
        self.stop: StopRequest | None = None
        self.sb = 0.0
        self.vb_f = self.vc_f = 0.0
        self.load_f: np.ndarray | None = None  # the wheel loads MC#10/#11 read (sup.load_tau's filter)
        self._load_a = min(1.0, ts / sup.load_tau) if sup.load_tau > 0.0 else 1.0  # the filter's gain a period
        # (t, x_progress, commanded progress), trimmed every step to what the efficiency window reads
        self.hist: deque[tuple[float, float, float]] = deque()
        self.cmd_prog = 0.0
        self.health_t: float | None = None
        self.clutch = (False, False)
        self.legged_log: list[dict] = []
        self.short_lifts: list[str] = []  # legged steps whose lift stayed below legged.DRIVE_SHARE
        self.abandoned: list[str] = []  # steps the operator's reply ended before their own end
        self.halt_why = ""  # the last reminder's reason
        # RCM's hold of the still set: its wheel indices, rotation over the ground, last zeta
        self.still_key: tuple | None = None
        self.still_rot = np.zeros(6)
        self.zeta_prev: np.ndarray | None = None
        # group ``ik`` only (Step.trace / Step.qp): the per-period QP trace, and for a plan that
        # bypasses the projection a shadow QP whose solution is traced but not executed
        self.trace = None
        if any(getattr(s, "trace", False) for s in plan):
            from terrabench.systems.srwmr.qp_trace import QPTrace

            self.trace = QPTrace(sc, robot.track / 2, bypassed=any(not getattr(s, "qp", True) for s in plan))
            self._shadow = SaturatedIK(robot, lim, sc, ts)

    # ---------------------------------------------------------------- bookkeeping
    @property
    def mode(self) -> str:
        """The machine's mode: a plan mode, ``HALT``, ``REVERSE``, ``DONE`` (``START`` before the plan)."""
        return self.machine.state

    @property
    def legged(self) -> LeggedAction | None:
        """The step's legged action sequence (SWLM / DWLM), else None."""
        return self.action.seq if isinstance(self.action, WheelLegged) else None

    def info(self) -> dict:
        out = super().info()
        out.update(self.ik.timing())
        out["reminders"] = dict(self.reminders)
        if self.trace is not None:
            out.update(self.trace.info())
        if self.legged_log or self.legged is not None:
            out["legged"] = self.legged_log + ([] if self.legged is None else self.legged.log)
        return out

    def _kappa(self, mode: str) -> tuple[np.ndarray, np.ndarray]:
        """The mode's threshold vector and the one its QP enforces (built once per mode)."""
        k = self._kappas.get(mode)
        if k is None:
            k = self._kappas[mode] = (mc.thresholds(mode), mc.qp_thresholds(mode))
        return k

    def _next(self, obs, reason: str) -> None:
        self.k += 1
        self.returning = False
        if self.legged is not None:
            # a legged step ends with its clutches released (also after a reverse)
            self.legged_log += self.legged.log
            if self.legged.short:
                self.short_lifts.append(self.legged.short)
        self.action = None
        self.clutch = (False, False)
        if self.k >= len(self.plan):
            self.machine.go(obs.t, "DONE", reason)
            if self.short_lifts or self.abandoned:
                # the plan reached its end, but a legged step's lift did not happen (its wheel rolled on
                # the ground) or a step was cut short by the operator after a reminder: what the plan
                # commands was not done, whatever the goal line says
                why = []
                if self.short_lifts:
                    why.append("plan complete without its lift: " + "; ".join(self.short_lifts))
                if self.abandoned:
                    why.append("plan complete without " + "; ".join(self.abandoned))
                self.stop = self.stop or StopRequest(HALT, "; ".join(why))
            else:
                self.stop = self.stop or StopRequest(DONE, "plan complete")
            return
        st = self.plan[self.k]
        self.step_start = (obs.xy.copy(), obs.yaw, obs.delta.copy(), obs.t)
        self.action = action_for(st, self.robot, obs, self.k)
        self.machine.go(obs.t, st.mode, reason)

    def local(self, obs) -> tuple[float, float, float]:
        """Pose in the start frame (x along the start heading)."""
        (x0, y0), yaw0 = self.origin
        dx, dy = obs.xy[0] - x0, obs.xy[1] - y0
        c, s = math.cos(yaw0), math.sin(yaw0)
        return c * dx + s * dy, -s * dx + c * dy, obs.yaw - yaw0

    def start_local(self) -> tuple[float, float]:
        """Where the step began, in the start frame (x, y)."""
        (x0, y0), yaw0 = self.origin
        p = self.step_start[0]
        return (math.cos(yaw0) * (p[0] - x0) + math.sin(yaw0) * (p[1] - y0),
                -math.sin(yaw0) * (p[0] - x0) + math.cos(yaw0) * (p[1] - y0))

    def closing_rate(self, obs, vz: float, target_delta: float) -> np.ndarray:
        """Closing rates (2,) lifting the chassis at ``vz`` towards ``target_delta``."""
        dz = self.period.dz
        err = target_delta - obs.delta
        rate = np.sign(err) * abs(vz) / np.maximum(dz, 1e-3)
        slow = np.minimum(1.0, np.abs(err) / 0.02)
        return rate * slow

    # ---------------------------------------------------------------- the loop
    def __call__(self, obs) -> Command:
        if self.target is None:
            self.target = obs.delta.copy()
            self.origin = (obs.xy.copy(), obs.yaw)
            self.mu_cmd = obs.mu.copy()
            self._next(obs, "plan start")
        # the kinematics of this period, once (one compiled call, kinematics.period_geometry)
        self.period = Period(*period_geometry(self.robot, obs.delta, self.mu_cmd))
        if self.stop:
            return self._command(obs, np.zeros(5), hold=True)
        if self.halt_t is not None:
            return self._halted(obs)
        st = self.plan[self.k]
        x, y, dyaw = self.local(obs)
        nom = self.action.nominal(self, obs, x, y, dyaw)
        if nom.clutch is not None:
            self.clutch = nom.clutch
        if nom.done:
            self._next(obs, f"{st.mode} action complete")
            return self._command(obs, np.zeros(5), hold=True)
        if st.mode == "WRM" or st.mode in LEGGED:
            # (a legged step rolls on its grounded wheels: the same health monitor; its own speed is
            # zero outside the roll, where the monitor reads nothing)
            cmd = self._monitor_rolling(obs, st, x)
            if cmd is not None:
                return cmd
        # --- constraint-saturated IK
        kappa, kappa_qp = self._kappa(st.mode)
        J, wb = self.period.J, self.period.wb
        if st.qp_about_target:  # group ``ik`` variant: the rows linearised about the rockers' servo targets
            s0, _g, dz_t, wb_t = period_geometry(self.robot, self.target, self.mu_cmd)
            u = self.ik.solve(nom.u, IKState(self.target, self.u_prev), kappa_qp, s0[1], wb_t, dz=dz_t)
            qp_ik, u_qp = self.ik, u
        elif st.qp:
            u = self.ik.solve(nom.u, IKState(obs.delta, self.u_prev), kappa_qp, J, wb, dz=self.period.dz)
            qp_ik, u_qp = self.ik, u
        else:  # group ``ik``'s -noqp twins: the nominal command executed, the projection only traced
            qp_ik = self._shadow
            u_qp = qp_ik.solve(nom.u, IKState(obs.delta, self.u_prev), kappa_qp, J, wb, dz=self.period.dz)
            u = np.asarray(nom.u, float).copy()
        if u is None:
            return self._halt(obs, "IK infeasible (no command satisfies the constraints)")
        ratios = self._ratios(obs, u, J, wb)
        if st.mode in LEGGED:
            # a clutched side lifts a wheel, not its hinge: MC#4 is the measured left-right hinge
            # height difference (IMU roll over the hinge track), not the symmetric-lift model's
            ratios[2] = mc.eta_roll(np.array([self.robot.hinge_track * math.sin(float(obs.rpy[0])), 0.0]), self.sc)
        if self.trace is not None:
            self.trace.record(obs.t, st.mode, MODE_CODE[st.mode], nom.u, u if u_qp is None else u_qp, u, self.u_prev,
                              ratios, kappa, kappa_qp, qp_ik._G, qp_ik._h, qp_ik._lb, qp_ik._ub)
        # the QP keeps the command ratios (MC6-MC9) at or below kappa; the supervisor halts on the
        # measured state ratios: MC2 (coordination), MC3-MC5 (posture), MC10/MC11 (loads)
        # (group ``ik``: Step.halt_tol > 0 halts only above kappa (1 + halt_tol), past the QP's own boundary)
        kappa_halt = kappa * (1.0 + st.halt_tol) if st.halt_tol else kappa
        i = mc.halting_ratio(ratios, kappa_halt, mc.MONITORED)  # the largest ratio / kappa >= 1, or -1
        if i >= 0:
            return self._halt(obs, f"{mc.NAMES[i]} ratio {ratios[i]:.2f} >= {kappa_halt[i]:.2f}")
        return self._command(obs, u, steer_only=nom.steer_only, lifted=nom.lifted, ratios=ratios)

    # ---------------------------------------------------------------- supervisor
    def _monitor_rolling(self, obs, st: Step, x: float) -> Command | None:
        """WRM and a legged step's roll: the body-slip estimate and the health monitor; WRM also keeps
        the climbing efficiency's window (the switch to RCM, ``Step.auto_rcm``), which a legged roll
        neither reads nor fills; a Command when one acts, else None."""
        ts = self.ts
        v_cmd = float(self.u_prev[0])
        if abs(v_cmd) <= 1e-4:
            self.health_t = None  # standing: no slip to watch (a later roll starts its own count)
            return None
        # s_b = 1 - v_b / v_cmd from filtered speeds (the ratio of raw samples explodes while the
        # command ramps up from zero)
        a = ts / self.sup.slip_tau
        self.vb_f += a * (obs.v_body[0] - self.vb_f)
        self.vc_f += a * (v_cmd - self.vc_f)
        self.sb = 1.0 - self.vb_f / self.vc_f if abs(self.vc_f) >= 0.5 * abs(st.v) else 0.0
        if self.sb >= self.sup.health_slip:
            self.health_t = self.health_t if self.health_t is not None else obs.t
            if obs.t - self.health_t >= self.sup.health_s:
                why = f"body slip {self.sb:.2f} >= {self.sup.health_slip}"
                self.machine.go(obs.t, "HALT", f"health monitor: {why}")
                self.stop = StopRequest(HALT, f"health halt: {why}")
                return self._command(obs, np.zeros(5), hold=True)
        else:
            self.health_t = None
        if st.mode != "WRM":
            return None  # a legged roll: the health monitor only (the climbing efficiency is WRM's)
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
        return None

    def _halted(self, obs) -> Command:
        """An active halt waits for the operator: a reply ends the action (the mode may move on
        inside the step, :meth:`ModeAction.reply`); no reply within ``wait_s`` (or a forced return)
        runs the step back to its start state."""
        waited = obs.t - self.halt_t
        rep = self.sup.reply_s
        if rep is not None and waited >= rep and not self.returning:
            # (a forced return is not cut short by the reply)
            self.halt_t = None
            self.machine.go(obs.t, self.plan[self.k].mode, "operator replied: action ended")
            if not self.action.reply(self, obs):
                self.abandoned.append(f"the end of step {self.k + 1} ({self.plan[self.k].mode}: the operator "
                                      f"moved on after {self.halt_why})")
                self._next(obs, "operator: next action")
            return self._command(obs, np.zeros(5), hold=True)
        if waited >= self.sup.wait_s or self.returning:
            if not self.returning:
                self.returning = True
                self.machine.go(obs.t, "REVERSE", "no reply: mode reversed to its start")
            return self._reverse(obs)
        return self._command(obs, np.zeros(5), hold=True)

    def _halt(self, obs, reason: str) -> Command:
        mode = self.plan[self.k].mode
        n = self.reminders.get(mode, 0) + 1
        self.reminders[mode] = n
        self.machine.go(obs.t, "HALT", f"reminder {n}: {reason}")
        self.halt_t = obs.t
        self.halt_why = reason
        if n >= 2:
            self.returning = True
            self.machine.go(obs.t, "REVERSE", "second reminder in this mode: forced return")
        return self._command(obs, np.zeros(5), hold=True)

    def _reverse(self, obs) -> Command:
        """Run the step back to its start state (the mode's own :meth:`ModeAction.unwind`, else the
        suspension back to the step's start angles, wheels coordinated), then go on."""
        d0 = self.step_start[2]
        nom = self.action.unwind(self, obs)
        if nom is None:
            back = np.max(np.abs(obs.delta - d0)) < 0.004
        else:
            self.clutch = nom.clutch
            back = nom.done
            if not back:
                return self._command(obs, nom.u, lifted=nom.lifted)
        if back:
            self.halt_t = None
            self.returning = False
            self.machine.go(obs.t, self.plan[self.k].mode, "back at the start state")
            self._next(obs, "after return")
            return self._command(obs, np.zeros(5), hold=True)
        rate = self.closing_rate(obs, 0.0036, float(np.mean(d0)))
        return self._command(obs, np.array([0.0, 0.0, 0.0, rate[0], rate[1]]))

    # ---------------------------------------------------------------- output
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
        if self.still_key != key:
            self.still_key, self.still_rot, self.zeta_prev = key, np.zeros(6), obs.zeta.copy()
        side = np.array([0, 1, 0, 1, 0, 1])
        zd = (obs.zeta - self.zeta_prev) / self.ts
        self.zeta_prev = obs.zeta.copy()
        link = obs.gyro[1] + np.where(np.arange(6) < 2, self.robot.z_ratio * obs.ddelta[side],
                                      -obs.ddelta[side] + zd[side])
        self.still_rot += (obs.spin + link) * self.ts
        return np.where(still, -link - HOLD_GAIN * self.still_rot, 0.0)

    def _ratios(self, obs, u, J, wb) -> np.ndarray:
        """The ratios eta of :data:`constraints.NAMES` this period (``constraints.period_ratios``,
        compiled: the expressions of ``eta_roll``, ``eta_yaw``, ... on scalars). MC2: while the
        suspension moves, the commanded rim speeds against the speeds the suspension motion requires
        (the RCM rolling set runs above them on purpose: it shows here)."""
        load = obs.load
        if self.sup.load_tau > 0.0:  # a first-order filter (in place), started at the first reading
            if self.load_f is None:
                self.load_f = np.array(load, float)
            else:
                self.load_f += self._load_a * (load - self.load_f)
            load = self.load_f
        return mc.period_ratios(self.robot, self.sc, u, self.u_prev, J, self.period.dz, wb, obs.delta, obs.ddelta,
                                obs.mu, load, self.rim_cmd, self._ratio_k)

    def _out(self, mu, spin, u, ratios) -> Command:
        return Command(mu, spin, self.target.copy(), u, MODE_CODE.get(self.mode, 9),
                       np.zeros(len(mc.NAMES)) if ratios is None else ratios, self.stop, self.k, self.clutch)

    def _command(self, obs, u, *, hold: bool = False, steer_only: bool = False, lifted=(), ratios=None) -> Command:
        ts = self.ts
        step = self.plan[min(self.k, len(self.plan) - 1)]
        goal = self.steer_goal
        if goal is not None and (steer_only or step.mode == "WCM"):
            # steering in place (WCM): rate-limited targets, wheels spun against the offset
            d_mu = np.clip(goal - self.mu_cmd, -0.3 * ts, 0.3 * ts)
            mu_rate = d_mu / ts
            self.mu_cmd = self.mu_cmd + d_mu
            if steer_only:
                # the contact of an offset wheel moves along its heading by -e mu_dot on the left and
                # +e mu_dot on the right (offset outwards on both sides): rolled out, not scrubbed
                spin = -_SIDE_SIGN * self.robot.wheel_offset * mu_rate / self.robot.wheel_radius
                self.rim_cmd = spin * self.robot.wheel_radius
                self.u_prev = np.zeros(5)
                return self._out(self.mu_cmd.copy(), spin, np.zeros(5), ratios)
        if step.diff:
            mu, spin = differential_kinematics(self.robot, u, self.period.susp)
        else:
            mu, spin = inverse_kinematics(self.robot, u, obs.delta, mu_prev=self.mu_cmd, lifted=lifted,
                                          geom=self.period.geom)
        rolling = self.rolling
        if rolling is not None:
            # RCM: the rolling set turns at least at the paper's wheel/chassis speed ratio (it must slip
            # to pull: a wheel at the kinematic rim speed has zero slip and only rolling resistance)
            idx, v_rim = rolling
            spin[idx] = np.maximum(spin[idx], v_rim / self.robot.wheel_radius)
            spin = spin + self._hold_still(obs, idx)
            self.rolling = None
        # a wheel whose steering is far from its target waits (no rolling against its heading)
        if steering_wait(mu, obs.mu, u, 0.15):
            spin = spin * 0.0
        self.mu_cmd = mu
        self.target = self.target + u[3:5] * ts
        self.rim_cmd = spin * self.robot.wheel_radius
        self.u_prev = np.asarray(u, float).copy()
        return self._out(mu.copy(), spin, self.u_prev.copy(), ratios)
