"""Wheel-legged modes of the HIT-MRII: SWLM (single wheel lifted) and DWLM (a symmetric pair).

Seed 001, sec. 3.1 and Tasks 6/7: "the wheels are lifted by controlling the active suspension
motion and the connection of the clutch positioned at the hinge of the actively and passively
articulated suspensions. ... when the robot body's CoM is positioned in the front or rear of the
body box, the rear or front wheels can be lifted, respectively. In addition, the CoM does not
affect the lifting of the middle wheel." One legged :class:`~terrabench.systems.srwmr.modes.Step`
runs the actions of Fig. 5 for one wheel (SWLM) or one pair at the same position (DWLM):

``shift``   change the clearance so the side's load point moves behind the middle wheel (front
            lift: chassis raised) or ahead of it (rear lift: chassis lowered); the middle lift needs
            no shift. On the fitted linkage the middle axle stands 24 mm ahead of the CoM at 500 mm
            clearance (a front wheel can leave the ground) and 213 / 229 mm behind it at 250 / 150
            mm (a rear wheel can); docs/assumptions-srwmr.md, "CoM shift clearance".
``clutch``  engage the clutch of the lifted side(s) (the bogie locked to the rear rocker section).
``lift``    turn the lifted side's rocker (open for a front or rear lift, close for a middle lift)
            until the wheel's axle has risen ``height`` above the side's grounded axles, estimated
            from the encoders and the IMU (:func:`lift_estimate`); the rocker range ends it early.
``roll``    WRM straight ahead by ``dist`` with the lifted wheels not driven.
``lower``   turn the rocker back until the wheel carries load again (touch-down on the ground or on
            the obstacle) or the rocker is back at its lift start.
``release`` release the clutch (the bogie passive again).
``restore`` back to the clearance the step started at.

MC#1 is checked before any simulation (:func:`check_lift`): SWLM takes one wheel, DWLM one of the
symmetric pairs c1+c2, c3+c4, c5+c6 (Task 7: "the wheels at the same positions on both sides of
the robot are lifted in sequence").
"""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.kinematics import axle_positions, delta_for_clearance, lift_height
from terrabench.systems.srwmr.robot import WHEEL_POS, WHEEL_SIDE, WHEELS, Names, RobotConfig

LEGGED = ("SWLM", "DWLM")
PHASES = ("shift", "clutch", "lift", "roll", "lower", "release", "restore")
#: DWLM lifts a symmetric pair [S Task 7]; SWLM one wheel [S Task 6: "N_w = 1"]
DWLM_PAIRS = (("c1", "c2"), ("c3", "c4"), ("c5", "c6"))
#: clearance (m) of the CoM shift before a lift, by wheel position [R]: the front lift needs the
#: side's load behind the middle axle (chassis raised: 500 mm, inside the tested 150-550 mm [S]);
#: the rear lift the load ahead of it (chassis lowered [S Task 6: "decreased to align the CoM at the
#: front part"], to 175 mm: the lowest of 150-250 mm in 25 mm steps from which the paper's largest
#: rear lift, 200 mm [S Task 13], keeps the body box off loose soil; from 150 mm the lifted side's
#: box lands at ~185 mm of lift, docs/assumptions-srwmr.md "CoM shift clearance"); the middle lift
#: none [S "the CoM does not affect the lifting of the middle wheel"]
SHIFT = {"front": 0.50, "middle": None, "rear": 0.175}
#: closing-angle direction that lifts a wheel at each position with the clutch engaged (the front
#: section turns up against the locked bogie when the hinge opens; it turns down when it closes,
#: which raises the middle axle above the front-rear line)
LIFT_SIGN = {"front": -1.0, "middle": 1.0, "rear": -1.0}
#: lifted wheel's rise speed (m/s) [S Task 6: "the front wheel variation is set to 7 mm/s"]
LIFT_SPEED = 0.007
#: touch-down: the lowered wheel carries this share of the nominal wheel load [R]
TOUCH_SHARE = 0.5
#: clutch settle time before and after the rocker moves (s) [R]
SETTLE_S = 0.5
#: a lift below this share of its target leaves the wheel driven during the roll [R]
DRIVE_SHARE = 0.5
#: DWLM lift: the reference wheels must keep this share of the nominal wheel load [R]
REF_SHARE = 0.1
#: SWLM roll levelling gain (1/s) of the unclutched side [R]: a 2 s time constant, slow against the
#: 10 ms control period and fast against the ~8 mm/s hinge rise of a middle lift (fitted linkage)
LEVEL_GAIN = 0.5


def allowed(mode: str) -> tuple[tuple[str, ...], ...]:
    """The lift sets ``mode`` accepts (MC#1, narrowed by the mode)."""
    if mode == "SWLM":
        return tuple(a for a in mc.ALLOWED_LIFTS if len(a) == 1)
    if mode == "DWLM":
        return DWLM_PAIRS
    raise ValueError(f"mode={mode!r} is not a wheel-lifting mode; valid: {', '.join(LEGGED)}")


def check_lift(mode: str, lift) -> tuple[str, ...]:
    """The sorted lift set, or ValueError naming the allowed lifts (MC#1 and the mode's own rule)."""
    key = tuple(sorted(lift))
    mc.mc1_check(key)  # unknown wheels, more than two, front and rear together, two on one side
    ok = allowed(mode)
    if key not in ok:
        raise ValueError(
            f"{mode} lift {'+'.join(key) or '(none)'} is not allowed; "
            f"allowed lifts: {', '.join('+'.join(a) for a in ok)}"
        )
    return key


def position(lift) -> str:
    """front / middle / rear of a lift set (one position: MC#1 and the modes' rules guarantee it)."""
    pos = {WHEEL_POS[WHEELS.index(c)] for c in lift}
    if len(pos) != 1:
        raise ValueError(f"lift {'+'.join(lift)} mixes positions {sorted(pos)}; a legged step lifts one position")
    return pos.pop()


def axle_side_plane(cfg: RobotConfig, obs) -> tuple[np.ndarray, np.ndarray]:
    """(6,) forward and (6,) vertical axle coordinates (m) in the level frame at the chassis centre
    (heading kept), from the encoders (closing angles, bogie angles, differential) and the IMU."""
    p = axle_positions(cfg, obs.delta, obs.zeta, obs.phi)
    roll, pitch = float(obs.rpy[0]), float(obs.rpy[1])
    cp, sp = math.cos(pitch), math.sin(pitch)
    z = sp * p[:, 0] + cp * math.sin(roll) * p[:, 1] + cp * math.cos(roll) * p[:, 2]
    x = cp * p[:, 0] - sp * (math.cos(roll) * p[:, 2] + math.sin(roll) * p[:, 1])
    return x, z


def axle_heights(cfg: RobotConfig, obs) -> np.ndarray:
    """(6,) axle heights (m) relative to the chassis centre in the level frame."""
    return axle_side_plane(cfg, obs)[1]


def lift_estimate(cfg: RobotConfig, obs, idx, opposite: bool = False) -> np.ndarray:
    """Height (m) of each lifted axle ``idx`` above a reference, in the level frame: ``opposite``
    (SWLM) the same-position axle of the other, unclutched side, every wheel of which stays on the
    ground; else (DWLM) its own side's middle axle for a front or rear lift (the wheel a clutched
    side pivots on; the far end may rise too) and the mean of the front and rear axles for a middle
    lift. Taken relative to the value at the lift's start, either is the wheel's rise above where it
    stood (a step edge drops out); the reference wheel's extra sinkage under the added load reads
    as rise."""
    z = axle_side_plane(cfg, obs)[1]
    out = []
    for i in idx:
        if opposite:
            out.append(z[i] - z[i ^ 1])  # c1 <-> c2, c3 <-> c4, c5 <-> c6
        elif WHEEL_POS[i] == "middle":
            out.append(z[i] - 0.5 * (z[i - 2] + z[i + 2]))
        else:
            out.append(z[i] - z[2 + (i % 2)])
    return np.array(out)


def apply_clutch(model, data, want, state) -> tuple[bool, bool]:
    """Engage / release the clutches (L, R) in ``data``: an engaging clutch holds the bogie at its
    present angle (the equality's reference is set first). Returns the new state."""
    want = (bool(want[0]), bool(want[1]))
    for k, s in enumerate(("L", "R")):
        if want[k] == state[k]:
            continue
        eid = model.equality(Names.clutch(s)).id
        if want[k]:
            model.eq_data[eid, 0] = data.qpos[model.joint(Names.bogie(s)).qposadr[0]]
        data.eq_active[eid] = want[k]
    return want


class LeggedAction:
    """The action sequence of one SWLM / DWLM step, driven by the controller every period."""

    def __init__(self, robot: RobotConfig, st, obs, k: int = 0):
        self.robot, self.st, self.k = robot, st, k
        self.lift = check_lift(st.mode, st.lift)
        self.idx = [WHEELS.index(c) for c in self.lift]
        self.pos = position(self.lift)
        self.sides = sorted({0 if WHEEL_SIDE[i] == "L" else 1 for i in self.idx})
        shift = st.shift if st.shift is not None else SHIFT[self.pos]
        self.d_start = obs.delta.copy()
        self.d_shift = None if shift is None else delta_for_clearance(robot, shift)
        self.phase = 0
        self.t_phase = obs.t
        self.clutch = (False, False)
        self.log: list[dict] = []
        self.lifted: tuple[int, ...] = ()
        self.achieved = 0.0
        self.x0 = None
        self.z_off = None
        self.d_lift0 = None
        self.best = (-1.0, obs.t)
        self.light_t: float | None = None
        self.touch_t = None
        self.rate = LIFT_SPEED
        #: set when the roll began with the lift below DRIVE_SHARE of its target: the step's
        #: legged action was not done (the wheel stayed on the ground and kept driving)
        self.short: str | None = None

    @property
    def name(self) -> str:
        return PHASES[self.phase] if self.phase < len(PHASES) else "done"

    def _note(self, t: float, what: str) -> None:
        self.log.append({"t": round(t, 2), "step": self.k, "mode": self.st.mode, "lift": "+".join(self.lift),
                         "action": self.name, "note": what})

    def advance(self, obs, why: str) -> None:
        """End the current action (also the operator's reply to a reminder) and start the next."""
        if self.name == "lift" and "mm" not in why:
            why += f" (lifted {1000 * self.achieved:.0f} of {1000 * self.st.height:.0f} mm)"
        self._note(obs.t, why)
        self.phase += 1
        self.t_phase = obs.t
        if self.name == "release":
            self.lifted = ()

    def command(self, ctl, obs, x: float):
        """(u_nom (5,), done) of this period; sets ``clutch`` and ``lifted`` for the command."""
        st, robot = self.st, self.robot
        u = np.zeros(5)
        name = self.name
        if name == "shift":
            if self.d_shift is None or np.max(np.abs(obs.delta - self.d_shift)) < 0.004:
                self.advance(obs, "CoM shift done" if self.d_shift is not None else "no CoM shift (middle lift)")
                return u, False
            rate = ctl.closing_rate(obs, st.vz, self.d_shift)
            u[3:5] = rate
            return u, False
        if name == "clutch":
            c = [False, False]
            for s in self.sides:
                c[s] = True
            self.clutch = (c[0], c[1])
            if obs.t - self.t_phase >= SETTLE_S:
                self.d_lift0 = obs.delta.copy()
                self.z_off = lift_estimate(robot, obs, self.idx, self.st.mode == "SWLM")
                # the rocker rate that raises the wheel at LIFT_SPEED: the rigid-link rise per closing
                # angle at this start (kinematics.lift_height, the clutched side on flat ground)
                d0 = float(np.mean(self.d_lift0[self.sides]))
                lever = abs(lift_height(robot, self.pos, 0.01 * LIFT_SIGN[self.pos], d0)) / 0.01
                self.rate = min(LIFT_SPEED / max(lever, 0.2), ctl.lim.rate_max)
                self.best = (-1.0, obs.t)
                self.light_t = None  # since when the DWLM reference wheels read unloaded (None: not now)
                self.advance(obs, f"clutch engaged on side(s) {'+'.join('LR'[s] for s in self.sides)}")
            return u, False
        if name == "lift":
            self.lifted = tuple(self.idx)
            h = lift_estimate(robot, obs, self.idx, self.st.mode == "SWLM") - self.z_off
            self.achieved = float(np.min(h))
            if self.achieved >= st.height:
                self.advance(obs, f"lifted {1000 * self.achieved:.0f} mm (target {1000 * st.height:.0f} mm)")
                return u, False
            if self.achieved > self.best[0] + 0.002:
                self.best = (self.achieved, obs.t)
            lo, hi = ctl.lim.delta_range
            sign = LIFT_SIGN[self.pos]
            at_end = any((sign < 0 and obs.delta[s] <= lo + 0.01) or (sign > 0 and obs.delta[s] >= hi - 0.01)
                         for s in self.sides)
            # DWLM: a side balancing on its middle wheel tips its other end up as well: the lift stops
            refs = [j for j in range(6) if j not in self.idx and WHEEL_POS[j] != self.pos]
            w_nom = robot.total_mass * 9.81 / 6
            light = st.mode == "DWLM" and float(np.min(np.asarray(obs.load)[refs])) < REF_SHARE * w_nom
            # held for SETTLE_S, as a touch-down's load is: one F/T sample reads +-100 N off the soil's
            # load (T12 lift100 DWLM: the rear-left read 30 N while it carried 157 N, and the lift
            # stopped 0.5 mm up)
            self.light_t = (self.light_t if self.light_t is not None else obs.t) if light else None
            unloaded = self.light_t is not None and obs.t - self.light_t >= SETTLE_S
            if at_end or unloaded or obs.t - self.best[1] > 20.0:
                why = ("rocker range end" if at_end else
                       "the reference wheels unloaded: the sides balance on one wheel each" if unloaded else
                       "no rise in 20 s")
                self.advance(obs, f"lift limited at {1000 * self.achieved:.0f} mm ({why}; "
                                  f"target {1000 * st.height:.0f} mm)")
                return u, False
            for s in self.sides:
                u[3 + s] = sign * self.rate
            return u, False
        if name == "roll":
            if self.x0 is None:
                self.x0 = x
                if self.achieved < DRIVE_SHARE * st.height:
                    # a lift that stayed low leaves the wheel on the ground: it keeps driving (undriven it
                    # braked the rover to a stop, measured on the rear lifts of T7 / T13)
                    self.lifted = ()
                    self.short = (f"{'+'.join(self.lift)} lifted {1000 * self.achieved:.0f} of "
                                  f"{1000 * st.height:.0f} mm")
                    self._note(obs.t, f"lift {1000 * self.achieved:.0f} mm < {DRIVE_SHARE:.0%} of the target: "
                                      "the wheel(s) keep driving")
            if x >= self.x0 + st.dist:
                self.x0 = None
                self.advance(obs, f"rolled {st.dist:.2f} m with {'+'.join(self.lift)} lifted")
                return u, False
            dyaw = ctl.local(obs)[2]
            lim = min(0.02, 0.5 * abs(float(ctl.u_prev[0])))
            # slow down over the last 50 mm (no pitching jolt on the carrying wheels as the roll stops)
            u[0] = st.v * max(0.2, min(1.0, (self.x0 + st.dist - x) / 0.05))
            u[2] = max(-lim, min(lim, -0.5 * dyaw))
            return u, False
        if name == "lower":
            w_nom = robot.total_mass * 9.81 / 6
            load = np.asarray(obs.load)[self.idx]
            back = all(abs(obs.delta[s] - self.d_lift0[s]) < 0.004 for s in self.sides)
            if np.all(load >= TOUCH_SHARE * w_nom):
                self.touch_t = self.touch_t if self.touch_t is not None else obs.t
            else:
                self.touch_t = None
            if back or (self.touch_t is not None and obs.t - self.touch_t >= SETTLE_S):
                self.advance(obs, "lowered: " + ("rocker back at its lift start" if back else
                                                 f"touch-down, load {float(np.min(load)):.0f} N"))
                self.touch_t = None
                return u, False
            for s in self.sides:
                err = self.d_lift0[s] - obs.delta[s]
                u[3 + s] = math.copysign(self.rate, err) * min(1.0, abs(err) / 0.02)
            return u, False
        if name == "release":
            self.clutch = (False, False)
            if obs.t - self.t_phase >= SETTLE_S:
                self.advance(obs, "clutch released")
            return u, False
        if name == "restore":
            if np.max(np.abs(obs.delta - self.d_start)) < 0.004:
                self.advance(obs, "clearance restored")
                return u, True
            u[3:5] = ctl.closing_rate(obs, st.vz, float(np.mean(self.d_start)))
            return u, False
        return u, True

    def reverse(self, obs) -> None:
        """The supervisor's return to the initial state: the remaining actions of the step run in
        reverse order from where it stands (wheel lowered with the clutch still engaged, clutch
        released, clearance restored)."""
        name = self.name
        if name in ("lift", "roll"):
            # a lift cut short by the supervisor says how high it got, as the operator's reply does
            up = f" (lifted {1000 * self.achieved:.0f} of {1000 * self.st.height:.0f} mm)" if name == "lift" else ""
            self._note(obs.t, f"reversed{up}: lower now")
            self.phase = PHASES.index("lower")
        elif name in ("shift", "clutch"):
            self._note(obs.t, "reversed: release and restore")
            self.phase = PHASES.index("release")
            self.lifted = ()
        self.t_phase = obs.t

    def level(self, ctl, obs, u: np.ndarray) -> np.ndarray:
        """SWLM: the unclutched side's rocker follows the clutched side's hinge height (measured
        left-right difference from the IMU roll, MC#4's quantity): lifting a middle wheel raises its
        hinge with it (the middle axle hangs below the hinge on the clutched rear section), which
        would otherwise roll the chassis by ~atan(h / d_b)."""
        if self.st.mode != "SWLM" or self.name not in ("lift", "roll", "lower"):
            return u
        o = 1 - self.sides[0]
        dz = max(float(ctl.period.dz[o]), 0.05)  # hinge rise per closing angle (the period's kernel)
        dh = self.robot.hinge_track * math.sin(float(obs.rpy[0]))  # left hinge above the right one
        rate = (-1.0 if o == 0 else 1.0) * LEVEL_GAIN * dh / dz
        u[3 + o] = max(-ctl.lim.rate_max, min(ctl.lim.rate_max, rate))
        return u
