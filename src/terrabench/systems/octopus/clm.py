"""Compound locomotion mode (CLM): four arms walk while the crawlers drive (paper, Control system).

The rules are small pure functions on measured values (:mod:`.rules`, each unit-tested) and the
settings are :class:`~terrabench.systems.octopus.controller_config.CLMConfig`;
:class:`CLMController` strings the rules together: terrain exploration from the arm tips, the
COG height and the travel past the edge, the front-flipper torque rule, the crawl gait with
three-phase arm transfers ended by the elbow-torque contact signal, the arm stop cases, and the
step-climbing sequence (eqs. 28-29).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from terrabench.sim.pymath import hypot
from terrabench.systems.base import MachineController, ModeMachine
from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus.controller_config import CLMConfig
from terrabench.systems.octopus.robot import ARMS, CORNER, RobotConfig
from terrabench.systems.octopus.rules import (
    ELBOW_LIFT,
    FLAT,
    UP,
    Command,
    arm_stop_case,
    cog_height,
    contact_detected,
    flipper_rule,
    steer,
    terrain_angles,
    terrain_case,
    transfer_step,
    travel,
)

GAIT_ORDER = ("RR", "RF", "LR", "LF")  # inferred from the paper's Fig. 14 description
ARM_INDEX = {k: i for i, k in enumerate(ARMS)}


@numba.njit(cache=True)
def _within(c, q, m):  # pragma: no cover
    """``c`` (n, 3) clipped in place to [q - m, q + m]: numpy's minimum(maximum(c, q - m), q + m),
    compiled (its semantics: each keeps its first operand when that is NaN or not beyond)."""
    for a in range(c.shape[0]):
        for b in range(c.shape[1]):
            v, lo, hi = c[a, b], q[a, b] - m, q[a, b] + m
            v = v if (v >= lo or math.isnan(v)) else lo
            c[a, b] = v if (v <= hi or math.isnan(v)) else hi


@numba.njit(cache=True)
def _out_of_range(fx, fy, rmin, mx, my, rmax, behind):  # pragma: no cover
    """Whether a foothold at (fx, fy) in {R} has left its arm's range: further than ``rmax`` from
    the mount at (mx, my) (Python's hypot), or, where ``behind`` is tested, behind ``rmin`` in x.
    The one range test of the walk (:func:`_hold`) and the climb."""
    return (behind and fx < rmin) or hypot(fx - mx, fy - my) > rmax


@numba.njit(cache=True)
def _hold(foot, on, shift, landing, dx, tip_r, press, ikc, rmin, mount, rmax, arm):  # pragma: no cover
    """The arm moving of eqs. 22-27 for the supporting arms (bits ``on``, 1 << arm index), compiled:
    each foothold (``foot`` (4, 3) in {R}, updated in place) moves back by ``dx`` where ``shift``,
    its height set ``press`` below the sensed tip (``tip_r`` (4, 3), z), and the arm's joints
    (``arm`` rows) put the tip there (:func:`~.arm_kinematics.ik_f`). Returns the bits of the arms
    whose foothold was beyond the range before the move: behind ``rmin[i]`` in x or further than
    ``rmax`` from the mount (``mount[i]`` = (sx mx, sy my); Python's hypot). A landing arm
    (``landing``) whose foothold is beyond is a caster: it does not move (the caller marks it)."""
    out = 0
    for i in range(4):
        if not on >> i & 1:
            continue
        fx, fy = foot[i, 0], foot[i, 1]
        beyond = _out_of_range(fx, fy, rmin[i], mount[i, 0], mount[i, 1], rmax, True)
        if beyond:
            out |= 1 << i
        if shift >> i & 1 and not (landing >> i & 1 and beyond):
            foot[i, 0] = fx - dx
        foot[i, 2] = tip_r[i, 2] - press
        arm[i, 0], arm[i, 1], arm[i, 2] = ak.ik_f(foot[i, 0], fy, foot[i, 2], ikc[i])
    return out


@numba.njit(cache=True)
def _travel_left(fx, fy, rmin, mx, my, rmax, two):  # pragma: no cover
    """How far (m) the body can still move forward before a foothold at (fx, fy) in {R} leaves its
    arm's range (``rmin`` the least x, ``rmax`` from the mount at (mx, my)), the foothold moving
    back. ``two`` is 2.0 passed at run time: the formula's square is libm's pow (Python's float
    ``**``), which LLVM would rewrite as x * x for a constant exponent (not the same bits)."""
    left = fx - rmin
    dy2 = (fy - my) ** two
    if dy2 >= rmax * rmax:
        return 0.0
    # the reach circle's rear crossing: fx - d - sx mx = -sqrt(rmax^2 - dy^2)
    d = fx - mx + math.sqrt(rmax * rmax - dy2)
    d = d if d < left else left  # Python's min(left, d)
    return d if d > 0.0 else 0.0  # max(0.0, d)


@numba.njit(cache=True)
def _pace_bound(foot, on, rem, period, rmin, mount, rmax, two):  # pragma: no cover
    """:meth:`CLMController._pace`'s bound over the footholds ``on`` (bits): the travels left,
    sorted, the k-th (from 0) over ``rem + k period`` where that wait is positive, the least."""
    left = np.empty(4)
    n = 0
    for i in range(4):
        if on >> i & 1:
            d = _travel_left(foot[i, 0], foot[i, 1], rmin[i], mount[i, 0], mount[i, 1], rmax, two)
            j = n
            while j > 0 and left[j - 1] > d:
                left[j] = left[j - 1]
                j -= 1
            left[j] = d
            n += 1
    v = math.inf
    for k in range(n):
        wait = rem + k * period
        if wait > 0.0:
            x = left[k] / wait
            v = x if x < v else v  # Python's min(v, x)
    return v


@numba.njit(cache=True)
def _climb_supports(tgt, lifted, tip_r, over, climb_hold, piv_x, piv_z, cs, sn, lx, lz, lx_rear, lift_front,
                    lift_rear, roll_k, lift_dz, press, front_support, ikc, rmin, mount, rmax,
                    arm, rear_turn):  # pragma: no cover
    """The nose climb's arm moving (:meth:`CLMController._climb_nose`, eqs. 22-27 for every support
    not ``lifted``), compiled: each tip target (``tgt`` (4, 3) in {R}, updated in place) turned by
    the tick's pitch change (cos ``cs``, sin ``sn``) about the rear ground contact (``piv_x``,
    ``piv_z``) and moved by the crawler travel (``lx``, ``lz``; ``lx_rear`` for the rear tips' x),
    its height bounded by the sensed tip (``tip_r`` (4, 3), z) less ``press``, and the arm's joints
    (``arm`` rows) put the tip there (:func:`~.arm_kinematics.ik_f`). The tick's decisions come in
    as flags: ``lift_front`` (the front booms lift), ``lift_rear`` (the rear booms lift the rear,
    once ``over``), ``roll_k`` = roll_level x IMU roll (the roll levelling's factor). Returns the
    bits of the arms whose foothold has left its range: those lift clear (the caller, in arm order:
    the event), their joints not set here. ``rear_turn`` (``climb_face_pivot`` before ``over``; the
    centre then :func:`face_centre`): the rear tips' x turns about the centre too, moved by
    ``lx_rear`` only. The arithmetic and Python's min are the Python loop's
    it replaced, bit for bit (tests/octopus/test_octopus_climb_kernel.py)."""
    out = 0
    for i in range(4):
        if lifted[i]:
            continue
        tx, ty, tz = tgt[i, 0], tgt[i, 1], tgt[i, 2]
        tip_z = tip_r[i, 2]
        front = i < 2
        if front and not over:
            # a lifting boom: its target moves down in {R} (a position lift, self-limiting). The
            # pitch-change prediction moves x only: in z it closes a loop through the free roller
            # (the body turns about a point ahead of the assumed pivot as the tip rolls: measured,
            # pitch 0.2 -> 0.9 rad in 0.5 s); without it in z the push eases as the nose rises.
            # No travel: the body is against the riser (travel counts from H >= H_EST)
            if climb_hold:
                tx = piv_x + (tx - piv_x) * cs + (tz - piv_z) * sn
            if lift_front:
                tz -= lift_dz
            # a tip the rising nose has lifted off the top comes down onto it again (a loaded
            # tip sits above its target by more than the press: unchanged)
            low = tip_z - press
            tz = low if low < tz else tz  # Python's min(tz, low)
            tgt[i, 0], tgt[i, 2] = tx, tz
            arm[i, 0], arm[i, 1], arm[i, 2] = ak.ik_f(tx, ty, tz, ikc[i])
            continue
        # a pressing (or pushing) arm: from its sensed tip (x) and its target (z), the tick's
        # predicted motion; x does not accumulate (odometry counts while the crawlers are blocked)
        x0 = tx
        dx, dz = tx - piv_x, tz - piv_z
        tx, tz = piv_x + dx * cs + dz * sn - lx, piv_z - dx * sn + dz * cs - lz
        if not front and rear_turn:
            tx = tx + lx - lx_rear  # turned about the body's centre; the rear's own travel only
        elif not front:
            # x: the rear tips keep their footholds (a pitch-change prediction about the rear
            # contact moved them more: measured, tip slip 0.37 -> 0.45 m); the body advances only
            # once lifted over the edge (S's rule: odometry from H >= H_EST), before that its
            # crawlers push on the riser
            tx = x0 - lx_rear
        if not front and over:
            # the front on the top, on its crawlers: the rear booms lift the rear (eq. 28) until H
            # (the rear tips, on the lower ground) exceeds H_EST by lift_margin, the nose not below
            # -climb_pitch; the front crawlers carry the front, the rear flippers push
            if lift_rear:
                tz -= lift_dz
            # roll levelling (IMU): the rear tip on the raised side eases, the other presses on
            tz += roll_k * ty
        else:
            # press: the target at most climb_press below the sensed tip (a lifting arm unloads
            # at lift_dz a tick)
            eased, low = tz + lift_dz, tip_z - press
            tz = low if low < eased else eased  # Python's min(eased, low)
        tgt[i, 0], tgt[i, 2] = tx, tz
        # (every arm here tests "behind": the lifting front arms took the branch above)
        beyond = _out_of_range(tx, ty, rmin[i], mount[i, 0], mount[i, 1], rmax, True)
        # front_support off: a front arm over the top that has unloaded (its target back at the
        # press) lifts clear and the front crawlers carry the front alone; on (the default), it
        # stays a support on the top at the bounded press until the release (Fig. 9f-h)
        beyond = beyond or (front and not front_support and tz >= tip_z - press - 1e-6)
        if beyond and (not front or over):
            out |= 1 << i
            continue
        arm[i, 0], arm[i, 1], arm[i, 2] = ak.ik_f(tx, ty, tz, ikc[i])
    return out


def face_centre(px: float, pz: float, pitch: float, pulley_x: float) -> tuple[float, float]:
    """The body's instantaneous centre of rotation in {R} (x, z) while the front pulley stands against
    a riser's face and the rear contact ``(px, pz)`` (in {R}, :meth:`CLMController._rear_pivot`) on
    the ground: the face holds the front pulley centre's level-frame x, the ground the rear
    contact's level-frame z, so the centre is where the normals cross, (the rear contact's x, the
    front pulley centre's z) in the level frame ({R} turned by the IMU ``pitch``; the pulley
    centres at z = 0 in {R}, the front one at x = ``pulley_x``)."""
    cp, sp = math.cos(pitch), math.sin(pitch)
    xc, zc = px * cp - pz * sp, pulley_x * sp
    return xc * cp + zc * sp, zc * cp - xc * sp


# ---------------------------------------------------------------------------- controller
WALK, CLIMB, RELEASE, INIT = 0, 1, 2, 3
#: names of the controller states (the logged ``mode`` codes) in events and timelines
MODE_NAMES = {WALK: "walk", CLIMB: "climb", RELEASE: "release", INIT: "init"}
#: the climb's stages (the logged ``Command.stage``; 0 outside a climb): the nose lift of Fig. 9e
#: (until the front is over the top; the lift to H_EST in the vertical climb), the rear lift of
#: eq. 28 (until the rear is up), the drive on over the top (S toward L) and the release
LIFT, REAR_LIFT, DRIVE_ON, RELEASING = 1, 2, 3, 4
STAGE_NAMES = {LIFT: "lift", REAR_LIFT: "rear_lift", DRIVE_ON: "drive_on", RELEASING: "release"}
#: arm sub-states in events: ``"<arm>.support"`` / ``"<arm>.transfer"``
SUPPORT, TRANSFER = "support", "transfer"


class CLMController(MachineController):
    """The CLM state machine: ``obs -> Command``."""

    def __init__(self, cfg: CLMConfig, robot: RobotConfig, dt: float = 0.02):
        self.cfg, self.robot, self.dt = cfg, robot, dt
        self.cmd = Command()
        self.targets = {k: self._target(k) for k in ARMS}
        self._ikc = np.array([ak.ik_constants(robot, k) for k in ARMS])  # each arm's IK constants (ak.ik_f)
        self._fkc = ak.fk_constants(robot)
        self._tgt_q = {k: ak.ik(self.targets[k], robot, k) for k in ARMS}  # the transfer targets' joints
        self.phase = {k: 0 for k in ARMS}  # 0 support, 1-3 transfer phases
        self.tau_ref = np.zeros(4)
        self.t3 = np.zeros(4)
        self.contact = [False] * 4  # supporting tips (Python bools: read every tick, item by item)
        self._tip_c = np.zeros((4, 3))  # the tips in {C} this tick (tip_c), None until first used
        self._att = (0.0, 0.0)  # this tick's IMU (roll, pitch) (rad)
        self._rot = np.zeros((3, 3))  # {R} -> {C} of this tick's IMU (tip_c's buffer)
        self.tip_r = np.zeros((4, 3))  # the tips in {R} this tick: the FK fills this buffer each tick
        self.foot = np.zeros((4, 3))  # footholds of the supporting arms in {R} (m)
        # each arm's range: the least x of its foothold and its mount (sx mx, sy my) (_hold)
        mx, my, _ = robot.arm_mount
        self._rmin = np.array([cfg.reach_min[0 if CORNER[k][0] > 0 else 1] for k in ARMS], dtype=float)
        self._mount = np.array([[CORNER[k][0] * mx, CORNER[k][1] * my] for k in ARMS], dtype=float)
        self.tip_z = self.prev_tip_z = [0.0] * 4  # tip heights in {R} now and a tick ago (m)
        self.low_z = np.zeros(4)
        self.phase_t = np.zeros(4)  # time in the current lift/swing phase (s)
        self.extra_lift = np.zeros(4)  # boom lift beyond A_B after a blocked swing (rad)
        self.att0 = (0.0, 0.0)  # IMU pitch and roll when the lowering began (rad)
        self.landing = [False] * 4  # landed, pressing, not yet settled
        # why an arm landed at full stretch (the pit check, pit_hold), or "": it has no press to test
        self.stretched_on = [""] * 4
        self.in_pit = [False] * 4  # found no ground (a pit): hanging at full stretch until its turn
        self.feel_x: list = [None, None]  # each front feeler's tip x in {C} a tick ago (flipper_feel)
        self.land_z = [0.0] * 4  # a landing tip's height where it stopped (m)
        self.land_why = ""  # the signal of the last landing: torque / blocked / tilted
        self.glide: list = [None] * 4  # a lowering arm's line to the top of its descent (p0, p1, ticks)
        self.glide_n = [0] * 4  # ticks of that line done
        self.settle_z0 = [0.0] * 4  # a landing tip's height at the start of its settle window (m)
        self.still = np.zeros(4, int)  # tip height target of a lowering arm in {R} (m)
        self.tp = 0.0  # terrain pitch T_P of the last four-tip exploration (rad)
        self.out_of_reach = False
        self.out_arm = ""  # the last arm whose foothold left its range (diagnostics)
        self.flip_prev, self.flip_still = 0.0, 0.0  # the front flipper angle and how long it has held (s)
        self.guarding = False  # the walk's pitch guard is backing the crawlers off
        self.caster = [False] * 4  # landed beyond its range: rolls with the body until its turn
        self.stop_case = [""] * 4  # each arm's last arm stop case (rules.arm_stop_case)
        self.queue: list[str] = list(ARMS)  # place all four arms first (init)
        self.next_gait = 0
        self.pause_until = 0.0
        self.transfer_t0 = 0.0  # when the arm now in transfer left its foothold (s)
        self.transfer_times: list[float] = []  # the last four transfers, each with its gait pause (s)
        self.gait_period = math.inf  # their mean, once four are timed (s): gait_pace's T
        self.s = 0.0
        self.h_est = 0.0
        self.last_case = FLAT
        self.started = False
        self.queue_reason: dict[str, str] = {}
        self.s_release = cfg.climb_distance
        self.heading = 0.0  # integrated gyro yaw rate (rad): the operator's move direction is 0
        self.release_pitch = 0.0
        self.resumes = 0  # releases of this climb that resumed it
        self.placing = False  # since a release, until the four arms are down again (place_pitch)
        self.machine = ModeMachine(INIT, MODE_NAMES)  # the controller state; records every change


    @property
    def tip_c(self) -> np.ndarray:
        """(4, 3) arm tips in {C} (m): this tick's encoders' tips (``tip_r``) turned level by the
        IMU (eqs. 10-12), computed on first use in a tick (the walk reads them only with all four
        tips down, the climb every tick)."""
        if self._tip_c is None:
            # the rotation into one buffer (ak.rotation_rc's values); the product stays numpy's
            # matmul (BLAS: a hand-written 3-term dot rounds differently on some CPUs' kernels)
            ak.rotation_rc_into(self._att[0], self._att[1], self._rot)
            self._tip_c = self.tip_r @ self._rot.T
        return self._tip_c

    def _arm_event(self, t: float, k: str, src: str, dst: str, reason: str) -> None:
        self.machine.note(t, f"{k}.{src}", f"{k}.{dst}", reason)

    def _target(self, k: str) -> np.ndarray:
        front, rear = self.cfg.targets
        x, y, z = front if k[1] == "F" else rear
        return np.array([x, y if k[0] == "L" else -y, z])

    # ---------------------------------------------------------------- helpers
    def _start(self, obs) -> None:
        c = self.cmd
        c.arm[:] = obs.q_arm
        c.flip[:] = [self.cfg.flipper_start, self.cfg.flipper_start, 0.0, 0.0]
        self.started = True

    def _all_down(self) -> bool:
        """Every arm a support: all four tips in contact and none in transfer."""
        return not any(self.phase.values()) and all(self.contact)

    def _lift_clear(self, obs, i: int, k: str, reason: str) -> None:
        """Arm ``i`` off the ground: no longer a support, its boom to A_B and its elbow up about its
        present swing (the pose is set once; :meth:`_lead` then holds it within ``max_lead``)."""
        self.contact[i] = False
        self.cmd.arm[i] = np.array([obs.q_arm[i][0], self.cfg.arm_ab, ELBOW_LIFT])
        self._arm_event(obs.t, k, SUPPORT, TRANSFER, reason)

    def _lead(self, obs) -> None:
        """The arm command kept within ``max_lead`` of the encoders."""
        _within(self.cmd.arm, obs.q_arm, self.cfg.max_lead)

    def _in_transfer(self) -> str | None:
        """The arm in transfer (the first: the dict is in ARMS order), or None."""
        for k, ph in self.phase.items():
            if ph:
                return k
        return None

    def _transfer(self, obs) -> int:
        """Advance the arm in transfer (if any); returns its index or -1."""
        cfg = self.cfg
        k = self._in_transfer()
        if k is None:
            if obs.t < self.pause_until or any(self.landing):
                return -1
            why = "gait turn"
            if self.queue:
                k = self.queue.pop(0)
                if self.placing:
                    # arms placed again after a release: the gait cycle goes on after the last one
                    self.next_gait = GAIT_ORDER.index(k) + 1
            elif self.state == WALK:
                # the gait turn; an arm whose foothold has left its range (the crawlers are waiting
                # for it) goes first and the cycle goes on from it
                j = GAIT_ORDER.index(self.out_arm) if self.out_of_reach else self.next_gait % 4
                k, self.next_gait = GAIT_ORDER[j], j + 1
                if self.out_of_reach:
                    why = "out of range: its turn comes first"
            else:
                return -1
            self.phase[k] = 1
            self.contact[ARM_INDEX[k]] = False
            self.stretched_on[ARM_INDEX[k]], self.in_pit[ARM_INDEX[k]] = "", False
            self.transfer_t0 = obs.t
            self._arm_event(obs.t, k, SUPPORT, TRANSFER, self.queue_reason.pop(k, why))
        i = ARM_INDEX[k]
        q = obs.q_arm[i]
        tgt = self._tgt_q[k]
        ph = self.phase[k]
        if ph == 4:
            # the pit check: the arm holds the command it reached pit_depth with. A straight arm
            # hanging free holds its forearm up (elbow torque < 0); one whose tip rests on a top
            # (the stretch hides the torque jump and the blocked tip above) presses it down
            self.t3[i] += self.dt
            if self.t3[i] < cfg.pit_hold - 1e-9:
                return i
            tau = float(obs.tau_elbow[i])
            self.phase[k] = 0
            if tau > cfg.contact_torque:
                self.stretched_on[i] = f"held at full stretch, elbow torque {tau:+.0f} N m"
                self._land(obs, k, i)
            else:
                self._arm_event(obs.t, k, TRANSFER, SUPPORT, "no ground within reach (pit)")
                self.pause_until = obs.t + cfg.gait_pause
                # the hanging arm's torque: ground that comes up under the tip later (the nose
                # dropping onto a tread) is a jump above it (_support). Only from a free hang
                # (within contact_torque of zero): an arm that already reads a large upward torque
                # is wedged (a tip against a gap's wall, the zoo's gap@0.3: -88 to -138 N m, swinging
                # by more than contact_torque), no reference for a jump
                self.in_pit[i], self.tau_ref[i] = tau > -cfg.contact_torque, tau
            return i
        if ph == 3:
            # lower: the tip target descends straight down over the transfer target (IK), so the
            # tip lands where it was sent; contact = the elbow torque signal, or the tip stops
            # following its descent (encoders)
            self.t3[i] += self.dt
            tx, ty, tz = self.targets[k].tolist()
            g = self.glide[i]
            if g is not None:
                # first a straight line from where the swing ended to the top of the descent, at
                # the fast rate: the servos' own path there (a joint-space sweep) would swing
                # the tip out and land it off its foothold (the block's top, 0.26 m out)
                p0, p1, n = g
                self.glide_n[i] += 1
                u = min(self.glide_n[i] / n, 1.0)
                gx, gy, gz = (p0[j] + u * (p1[j] - p0[j]) for j in range(3))
                if u >= 1.0:
                    self.glide[i] = None
                self.low_z[i] = gz
            else:
                gx, gy = tx, ty
                # fast while high above the expected ground, then slow for a soft touch
                self.low_z[i] -= cfg.lower_dz * (3.0 if self.low_z[i] > tz + 0.15 else 1.0)
            # a target beyond the arm's reach stretches it straight: the tip stops and the elbow's
            # torque jumps at full stretch, with no ground under it (a drop deeper than the arm)
            stretched = ak.beyond_reach(gx, gy, float(self.low_z[i]), self._ikc[i])
            touched = abs(obs.tau_elbow[i] - self.tau_ref[i]) > cfg.contact_torque and not stretched
            # blocked: the tip lags its target and has stopped descending (a servo lag alone
            # while the target falls fast is not a contact)
            stopped = self.tip_r[i, 2] - self.prev_tip_z[i] > -0.25 * cfg.lower_dz
            blocked = stopped and self.tip_r[i, 2] - self.low_z[i] > cfg.stall_dz and not stretched
            # or the body tilts while the arm descends: the arm has started to carry it (IMU)
            tilted = max(abs(obs.pitch - self.att0[0]), abs(obs.roll - self.att0[1])) > cfg.tilt_contact
            if self.t3[i] > 0.2 and (touched or blocked or tilted):
                self.land_why = "+".join(n for n, on in (("torque", touched), ("blocked", blocked),
                                                          ("tilted", tilted)) if on)
                self._land(obs, k, i)
                return i
            # the free-motion reference follows the slow changes (gravity, servo lag, the IK's
            # posture): a contact is a jump above it
            self.tau_ref[i] += cfg.tau_filter * (obs.tau_elbow[i] - self.tau_ref[i])
            new_ph = 4 if self.low_z[i] < tz - cfg.pit_depth else 3
            c = ak.ik_f(gx, gy, float(self.low_z[i]), self._ikc[i])
        else:
            ab = max(cfg.arm_ab - self.extra_lift[i], self.robot.boom_range[0] + 0.05)
            new_ph, c = transfer_step(ph, q, self.cmd.arm[i], tgt, ab, cfg.d_swing, cfg.d_lift, cfg.k_boom)
            # arm stop case 1 in time: a swing the arm cannot finish (a link against an obstacle)
            # lifts the arm higher and swings again, once; a lift or a second blocked swing goes on
            # to the next phase from where the arm is
            self.phase_t[i] = self.phase_t[i] + self.dt if new_ph == ph else 0.0
            if self.phase_t[i] > cfg.phase_timeout:
                self.phase_t[i] = 0.0
                if ph == 2 and self.extra_lift[i] < cfg.extra_lift:
                    self.extra_lift[i] = cfg.extra_lift
                    new_ph = 1
                    self._arm_event(obs.t, k, TRANSFER, TRANSFER,
                                    f"swing blocked for {cfg.phase_timeout:g} s: lift {cfg.extra_lift:g} rad higher")
                else:
                    new_ph = ph + 1
                    self._arm_event(obs.t, k, TRANSFER, TRANSFER,
                                    f"phase {ph} blocked for {cfg.phase_timeout:g} s: next phase")
                    if ph == 2:
                        c[0] = q[0]
        if ph == 2 and new_ph == 3:
            self.tau_ref[i] = obs.tau_elbow[i]
            self.t3[i] = 0.0
            # the descent starts at the tip's height or lower, where the arm reaches the target
            # without its boom against its upper stop (a knee-up whip that would look like a stop)
            tx, ty, tz = self.targets[k].tolist()
            z, lo = float(self.tip_r[i, 2]), self.robot.boom_range[0] + 0.1
            while z > tz and ak.ik_f(tx, ty, z, self._ikc[i])[1] < lo:
                z -= 0.02
            self.low_z[i] = z
            # an arm lifted higher after a blocked swing starts its descent far from the top of
            # it: a straight line there first (see phase 3)
            p0 = self.tip_r[i].tolist()
            d = math.dist(p0, (tx, ty, z))
            far = d > cfg.d_d and self.extra_lift[i] > 0
            self.glide[i] = (p0, (tx, ty, z), math.ceil(d / (3.0 * cfg.lower_dz))) if far else None
            self.glide_n[i] = 0
            self.att0 = (obs.pitch, obs.roll)
        self.cmd.arm[i] = c
        if new_ph == 4 and cfg.pit_hold > 0:  # no contact by pit_depth: the pit check (phase 4) first
            self.phase[k], self.t3[i] = 4, 0.0
        elif new_ph == 4:  # joint limit without contact: a deep pit; the arm stays where it is
            self._arm_event(obs.t, k, TRANSFER, SUPPORT, "no ground within reach (pit)")
            self.phase[k] = 0
            self.pause_until = obs.t + cfg.gait_pause
        else:
            self.phase[k] = new_ph
        return i

    def _land(self, obs, k: str, i: int) -> None:
        """The lowering arm stopped (contact signal): it presses (see :meth:`_support`) and is a
        support once its tip has settled (:meth:`_settle`)."""
        cfg = self.cfg
        self.phase[k] = 0
        self.landing[i], self.still[i] = True, 0
        p = self.tip_r[i].copy()
        self.foot[i] = p
        self.land_z[i] = float(p[2])
        self.cmd.arm[i] = ak.ik(p - np.array([0.0, 0.0, cfg.press]), self.robot, k)

    def _settle(self, obs, k: str, i: int) -> None:
        """A landing tip that has stopped moving (encoders) for ``settle_ticks`` is a support:
        its elbow torque becomes the collision reference and the arm stop case is recorded."""
        cfg = self.cfg
        f = self.foot[i]
        stretched = ak.beyond_reach(f[0], f[1], self.tip_z[i] - cfg.press, self._ikc[i])
        stretched = stretched and not self.stretched_on[i]  # a tip held at full stretch cannot press further
        if cfg.relower_dz and (self.tip_z[i] < self.land_z[i] - cfg.relower_dz or stretched):
            # the pressing tip went on down below where it stopped, or presses at the arm's full
            # stretch (nothing under it within reach): the signal was not a contact (a torque or
            # tilt transient in the air); lower again
            self.landing[i], self.stretched_on[i] = False, ""
            # (the descent goes on from its target, so a deep pit is still found: phase 4)
            self.phase[k], self.t3[i], self.low_z[i] = 3, 0.0, min(self.low_z[i], self.tip_z[i])
            self.tau_ref[i], self.att0 = obs.tau_elbow[i], (obs.pitch, obs.roll)
            where = "pressed at full stretch" if stretched else f"went on down {cfg.relower_dz:g} m"
            self._arm_event(obs.t, k, TRANSFER, TRANSFER, f"no contact ({self.land_why}): the tip {where}: "
                            "lowering again")
            return
        # settled: settle_ticks ticks within a band of settle_dz a tick about the first (a band, not a
        # per-tick limit: a pressing tip jitters by more than settle_dz a tick while the crawlers
        # run, and a per-tick test kept a landed arm "landing" for 11 s, terrace2-front seed 8)
        if self.still[i] == 0:
            self.settle_z0[i] = self.tip_z[i]
        self.still[i] += 1
        if abs(self.tip_z[i] - self.settle_z0[i]) > cfg.settle_dz * cfg.settle_ticks:
            self.still[i] = 0
        if self.still[i] < cfg.settle_ticks:
            return
        self.landing[i], self.contact[i] = False, True
        self.tau_ref[i] = obs.tau_elbow[i]
        case = arm_stop_case(self.tip_r[i], self.targets[k], cfg.d_c, cfg.d_d)
        self.stop_case[i] = case
        self._arm_event(obs.t, k, TRANSFER, SUPPORT,
                        f"landed: {case}" + (f" ({self.stretched_on[i]})" if self.stretched_on[i] else ""))
        if case == "reached":
            self.extra_lift[i] = 0.0
        self.pause_until = obs.t + cfg.gait_pause
        # the gait cycle's pace, timed by the controller: the last four transfers, pause included
        self.transfer_times = [*self.transfer_times[-3:], obs.t - self.transfer_t0 + cfg.gait_pause]
        if len(self.transfer_times) == 4:
            self.gait_period = sum(self.transfer_times) / 4

    def _pace(self, t: float) -> float:
        """``gait_pace``: the crawler speed (m/s) at which no foothold need leave its range before
        its arm's turn: at best the k-th nearest to its range end (travel left d_k) has its turn
        after the transfer now under way and k - 1 more, each taking the mean of the last four as
        the controller timed them (T), so v <= d_k / (T_rem + (k - 1) T), T_rem the present
        transfer's expected remainder (at least a quarter of T). A bound, not a guarantee: the
        turns keep GAIT_ORDER's cycle, and a foothold that still leaves its range stops the
        crawlers as before (``out_of_reach``). Unbounded (inf) before four transfers."""
        period = self.gait_period
        if period == math.inf:
            return period
        moving = any(self.phase.values())
        rem = max(period - (t - self.transfer_t0), 0.25 * period) if moving else max(self.pause_until - t, 0.0)
        on = 0
        for i, k in enumerate(ARMS):
            if self.contact[i] and not self.phase[k] and not self.caster[i]:
                on |= 1 << i
        return _pace_bound(self.foot, on, rem, period, self._rmin, self._mount, self.cfg.reach_max, 2.0)

    def _feel(self, obs) -> float:
        """``flipper_feel``: the body's advance (m) over the last tick read from the front flippers
        against a riser, the mean over the feelers read at both ticks; inf when none is.

        A flipper pushed up (torque below -``feel_torque``) has its tip pulley against the riser's
        face while the tip's centre is below the top the highest supporting front arm stands on
        (its tip in {C} less the tip radius): the contact is then at the centre's height and the
        face is fixed, so the tip centre's level-frame x (IMU roll and pitch) moves back by the
        body's advance. Above the top's edge the flipper's run rides the edge instead and nothing
        is read (the tip model would under-count there). A feeler that reaches its upper limit
        (``a0``) against the face stands upright there: the body cannot advance into the riser
        until the climb, and it reads 0."""
        cfg, rb = self.cfg, self.robot
        q, tau = obs.q_flip.tolist(), obs.tau_flip.tolist()
        up = cfg.a0 - 0.1
        pushed = [tau[0] < -cfg.feel_torque, tau[1] < -cfg.feel_torque]
        held = [q[0] > up and self.feel_x[0] is not None, q[1] > up and self.feel_x[1] is not None]
        tops = ([z for z, on in zip(self.tip_c[:2, 2].tolist(), self.contact[:2]) if on]
                if any(pushed) or any(held) else [])
        if not tops:
            self.feel_x = [None, None]
            return math.inf
        top = max(tops) - rb.tip_r
        r = ak.rotation_rc(obs.roll, obs.pitch).tolist()
        reads = []
        for f in (0, 1):
            if held[f]:
                reads.append(0.0)  # upright against the face: the body stands
                continue
            x = z = None
            if pushed[f]:
                px, pz = rb.pulley_x + rb.flipper_len * math.cos(q[f]), rb.flipper_len * math.sin(q[f])
                x = r[0][0] * px + r[0][2] * pz
                z = r[2][0] * px + r[2][2] * pz
            if x is not None and z < top:
                if self.feel_x[f] is not None:
                    reads.append(self.feel_x[f] - x)
                self.feel_x[f] = x
            else:
                self.feel_x[f] = None
        return sum(reads) / len(reads) if reads else math.inf

    def _support(self, obs, v: float, dx_max: float = math.inf) -> bool:
        """Arm moving (eqs. 22-27): each supporting arm's joints follow the body so its tip holds
        its foothold; returns True when a foothold has left its arm's working range.

        The body moves L = v dt a tick along the terrain, at T_P - R_P to its own x axis (T_P the
        terrain pitch from the last four-tip exploration, R_P the IMU pitch), so a foothold moves
        by -L (cos, 0, sin)(T_P - R_P) in {R}. Its height is not predicted but sensed: the target
        sits ``press`` below the tip's measured height (encoders), a press of a bounded force
        (the servo stiffness times ``press``) whatever the body does, so the crawlers carry the
        rest of the load.
        """
        cfg = self.cfg
        a = self.tp - obs.pitch
        dx = v * self.dt * math.cos(a)
        if dx > dx_max:  # the front feelers read less advance than the odometry (flipper_feel)
            dx = max(dx_max, 0.0)
        moving, phase, contact, caster = cfg.arm_moving, self.phase, self.contact, self.caster
        if not (any(self.landing) or any(self.in_pit)):
            # every support settled (most ticks): the four in one compiled pass (the kernel called
            # directly: self._hold's arguments)
            on = shift = 0
            for i, k in enumerate(ARMS):
                if contact[i] and not phase[k]:
                    on |= 1 << i
                    if moving and not caster[i]:
                        shift |= 1 << i
            bits = _hold(self.foot, on, shift, 0, dx, self.tip_r, cfg.press, self._ikc, self._rmin, self._mount,
                         cfg.reach_max, self.cmd.arm)
            out = False
            if bits:  # a foothold beyond its range (about one tick in ten)
                for i, k in enumerate(ARMS):
                    if bits >> i & 1 and not caster[i]:
                        out = self._beyond(obs, i, k) or out
            return out
        # an arm landing or hanging in a pit: arm by arm, its events in order with the others'
        hold = self._hold
        out = False
        for i, k in enumerate(ARMS):
            if self.in_pit[i] and not phase[k]:
                # a hanging pit arm whose tip the ground has come up to (elbow torque in the contact
                # direction): it lands there at full stretch instead of rolling with the body
                rise = obs.tau_elbow[i] - self.tau_ref[i]
                if rise > cfg.contact_torque:
                    self.in_pit[i] = False
                    self.stretched_on[i] = f"ground under a pit arm, elbow torque {rise:+.0f} N m"
                    self._land(obs, k, i)
            if phase[k] or not (contact[i] or self.landing[i]):
                continue
            if self.landing[i]:
                self._settle(obs, k, i)
                if phase[k]:  # not a contact: lowering again
                    continue
            landing = self.landing[i]
            bit = 1 << i
            beyond = bool(hold(bit, bit if moving and (landing or not caster[i]) else 0, bit if landing else 0, dx))
            if landing:
                # a foothold already beyond the range where the arm landed (a pitched body's
                # descent ends far out): no transfer now brings it back, so the crawlers do not
                # wait for it; the arm rolls with the body (a caster) until its next turn
                caster[i] = beyond
            if beyond and not caster[i]:
                out = self._beyond(obs, i, k) or out
        return out

    def _hold(self, on: int, shift: int, landing: int, dx: float) -> int:
        """:func:`_hold` on this controller's footholds, tips, constants and arm command."""
        cfg = self.cfg
        return _hold(self.foot, on, shift, landing, dx, self.tip_r, cfg.press, self._ikc, self._rmin,
                     self._mount, cfg.reach_max, self.cmd.arm)

    def _beyond(self, obs, i: int, k: str) -> bool:
        """A supporting arm whose foothold has left its range (not a caster): a case-1 foothold lifts
        clear and is transferred next (returns False); any other makes the crawlers wait for its
        transfer, which comes first (returns True)."""
        if self.cfg.blocked_clear and self.stop_case[i] == "blocked":
            # case 1 (an obstacle between the arm and its target): the same transfer stops at the
            # same obstacle, so waiting for it stops the crawlers every few cm; the arm lifts
            # clear (no support, no drag) and is transferred next while the crawlers drive on
            self._lift_clear(obs, i, k, "case-1 foothold out of range: lifted clear, the crawlers go on")
            if k in self.queue:
                self.queue.remove(k)
            self.queue.insert(0, k)
            self.queue_reason[k] = "lifted clear after a case-1 foothold: transferred next"
            return False
        self.out_arm = k
        if k in self.queue[1:]:
            # the crawlers wait for this arm: its transfer comes first
            self.queue.remove(k)
            self.queue.insert(0, k)
        return True

    # ---------------------------------------------------------------- climbing
    def _h_over(self) -> float:
        """H - H_EST from the front tips (m): the track bottom's height over the top the front tips
        stand on, -Z_C(front tips' midpoint) - H2. With the rear tips on the lower ground this is
        eqs. 9-12's H - H_EST (H_EST = front less rear tip height); it needs no rear tip down there,
        so it holds when the rear arms have lifted clear."""
        return -self._front_mid_z() - self.cfg.h2

    def _front_mid_z(self) -> float:
        """Z_C of the front tips' midpoint (m) (np.mean's value for two)."""
        z0, z1 = self.tip_c[:2, 2].tolist()
        return (z0 + z1) / 2

    def _nose_start(self, obs, resume: bool = False, mounted: bool = False) -> None:
        """State of a (fresh or resumed) nose climb: every arm a support, none lifted clear.
        ``mounted``: the walk's nose-up trigger started it (the crawlers already up an edge)."""
        self.lifted = np.zeros(4, bool)
        self.lifting = np.ones(4, bool) if not resume else np.zeros(4, bool)
        self.lifting[2:] = False  # only the front booms lift (the rear arms press)
        if not resume:
            # the pitch of the ground the crawlers drive on: the IMU's, but level for a mounted
            # start (the body is up an edge, not on its ground: mount_level)
            self.pitch0 = 0.0 if (mounted and self.cfg.mount_level) else obs.pitch
        self.prev_pitch = obs.pitch
        self.still_pitch, self.still_t = obs.pitch, 0.0  # the stall test's reference pitch and time (s)
        self.over = resume
        self.up = resume

    def _rear_pivot(self, obs) -> tuple[float, float]:
        """The rear ground contact in {R} (x, z) the body pitches about: the lower in {C} of the rear
        pulley's bottom and the rear flipper tip pulleys' bottom (encoders + IMU)."""
        r = self.robot
        q2, q3 = obs.q_flip[2:].tolist()
        a = (q2 + q3) / 2  # rear flipper angle (> 0 lifts the tip) (np.mean's value for two)
        pul = (-r.pulley_x, -r.pulley_r)
        tip = (-r.pulley_x - r.flipper_len * math.cos(a), r.flipper_len * math.sin(a) - r.flipper_tip_r)
        cp, sp = math.cos(obs.pitch), math.sin(obs.pitch)
        return tip if tip[1] * cp + tip[0] * sp < pul[1] * cp + pul[0] * sp else pul

    def _climb_nose(self, obs) -> None:
        """The climb of the paper's Fig. 9 (eqs. 28-29; ``nose_climb``, the default).

        Crawlers: ``climb_track_speed`` into and up the riser; beyond ``guard_pitch`` (the stability
        monitor) they stop. Front booms: their tip targets in {R} move down by ``lift_dz`` a tick
        while the pitch is below ``climb_pitch`` (the nose rises about the rear crawlers; x turned
        with the measured pitch change, z not: see the comment below), until the front pulley's
        bottom is ``lift_margin`` over the top (``over``; the top from the rear tips + H_EST); then
        they unload at ``lift_dz`` a tick to a ``climb_press`` press and lift clear. Rear arms: a
        bounded press (``climb_press`` below the sensed tip, z turned about the rear ground contact,
        :meth:`_rear_pivot`) until ``over``, then they lift the rear (eq. 28) until H exceeds H_EST
        by ``lift_margin`` or the body is back at its pitch before the climb (level, for a climb
        the nose-up trigger started: ``mount_level``); an arm whose foothold
        leaves its range lifts clear (A_B). Footholds move by the crawler travel (eqs. 22-27) only
        once the rear is up (``up``, latched: H within ``lift_margin`` of H_EST, or the front over
        and the body level); before that the crawlers push on the riser and odometry would count
        slip. Flippers (eq. 29, torque-limited lead ``flip_lead``, quasi-static ``release_d_f``):
        the front ones wait until their tips clear the edge, come down while the nose is below
        ``climb_pitch``, and lie level on the top once over (back to ``flipper_start`` when the nose
        rises on a next riser); the rear ones push once the nose is up or the front over, and come
        back to 0 once the rear is up. S (eq. 5) counts from ``up``; release at S > L with the nose
        below ``mount_pitch`` (not while it is up on the next riser of a short tread).
        """
        cfg, c, r = self.cfg, self.cmd, self.robot
        v = cfg.climb_track_speed
        why = self._stalled_alone(obs)
        if why:
            # the arms are placed again (the walk, whose guard backs the crawlers off) and the next
            # climb starts from four sensed tips
            self._replace(obs, f"{why} with every arm lifted clear: arms placed again")
            return
        if obs.pitch > cfg.guard_pitch:
            # the stability monitor: the crawlers stop (backing off on the rolling rear tips would
            # only roll the pitched robot away from the step) while the rear booms bring the nose down
            v = 0.0
            if not self.guarding:
                self.machine.note(obs.t, "climb", "climb", f"pitch {obs.pitch:.2f} rad > {cfg.guard_pitch}: "
                                  "crawlers stop")
        self.guarding = obs.pitch > cfg.guard_pitch
        c.track[0], c.track[1] = steer(v, self.heading, cfg.heading_gain, cfg.heading_dv)
        h = self._h_over()
        # H (eqs. 10-12) from both rear tips, a lifted-clear one too (it reads the robot lower than
        # it stands; from the supporting tips only, the rear is "up" sooner and the releases come
        # early: docs/octopus.md, "Tracks stopped")
        h_rear = cog_height(self.tip_c[2:], cfg.h2)
        # the front crawlers on the top: the track bottom reaches the top's level (H = H_EST) when
        # the rear is up, not above it, so "H >= H_EST" is read within lift_margin
        # latched (the rear arms may lift clear): H within lift_margin of H_EST, or the front on the
        # top and the body back to its pitch before the climb (the rear pulley then within
        # lift_margin of the front's level: the rear is up too, whatever ground the rear tips are on)
        level = self.over and obs.pitch - self.pitch0 < cfg.lift_margin / (2 * r.pulley_x)
        self.up = self.up or h_rear >= self.h_est - cfg.lift_margin or level
        up = self.up
        if up:
            self.s = travel(self.s, cfg.climb_track_speed, obs.pitch, self.dt)
        # the front is over the top once the front pulley's bottom is above it ({C}: encoders + IMU)
        # the top's height in {C}: the rear ground (the lower rear tip still down there) + H_EST,
        # which holds when the front tips are off the top
        z = self.tip_c[:, 2].tolist()
        rear = [] if self.up else [z[j] for j in (2, 3) if not self.lifted[j]]
        top = min(rear) - r.tip_r + self.h_est if rear else self._front_mid_z() - r.tip_r
        pulley_bottom = r.pulley_x * math.sin(obs.pitch) - r.pulley_r
        if pulley_bottom > top + cfg.lift_margin and not self.over:
            self.over = True
            self.machine.note(obs.t, "climb", "climb", f"front pulley {pulley_bottom - top:.3f} m over the top: "
                              "front arms unload")
        # eqs. 22-27 for every support: rotation by the pitch change about the rear contact (or the
        # body's centre against the face, climb_face_pivot), then travel
        dth = obs.pitch - self.prev_pitch
        self.prev_pitch = obs.pitch
        piv = self._rear_pivot(obs)
        cs, sn = math.cos(dth), math.sin(dth)
        a = self.pitch0 - obs.pitch
        lx, lz = v * self.dt * math.cos(a), v * self.dt * math.sin(a)
        px, pz = piv
        face = cfg.climb_face_pivot and not self.over
        if face:
            px, pz = face_centre(px, pz, obs.pitch, r.pulley_x)
        lift_front = obs.pitch < cfg.climb_pitch and h < cfg.lift_margin
        lift_rear = h_rear < self.h_est + cfg.lift_margin and obs.pitch > self.pitch0
        out = _climb_supports(self.lift_tgt, self.lifted, self.tip_r, self.over, cfg.climb_hold, px, pz, cs, sn,
                              lx, lz, lx if up else 0.0, lift_front, lift_rear, cfg.roll_level * obs.roll,
                              cfg.lift_dz, cfg.climb_press, cfg.front_support, self._ikc, self._rmin, self._mount,
                              cfg.reach_max, c.arm, face)
        if out:  # feet out of range (rare): those arms lift clear, in arm order (their events)
            for i, k in enumerate(ARMS):
                if out >> i & 1:
                    # the lift-clear pose is set once; _lead then holds the command within max_lead of
                    # the encoders and the lifted arm is not revisited, so its boom stays where the first
                    # clamp left it: as the body moves the arm presses instead (terrace2-front seed 1: LF
                    # at 275 of 300 N m 3 s after its lift, the front on its tip, the crawlers in the air
                    # for 2.4 s). Re-issuing the pose every tick keeps the crawlers loaded but the nose
                    # then rises to guard_pitch and the terraces fail 0/5 (docs/octopus.md, "Load share")
                    self.lifted[i] = True
                    self._lift_clear(obs, i, k, "climb: foothold out of range, lifted clear")
        self._climb_flippers(obs, top, up)
        # released on the top, not while the nose is up on the next riser (a short tread): the
        # crawlers drive on up it (a riser below the flippers' reach) before the release
        if self.s > self.s_release and up and obs.pitch < cfg.mount_pitch:
            self.release_pitch = obs.pitch
            # "up" is latched (H reached H_EST within lift_margin, or the front over the top with the
            # body level): H itself may read below H_EST now, so the event states both
            self.machine.go(obs.t, RELEASE, f"rear up (H = {h_rear:.3f} m, H_EST = {self.h_est:.3f} m), "
                                            f"S = {self.s:.3f} m > {self.s_release:.2f} m")

    def _climb_flippers(self, obs, top: float, up: bool) -> None:
        """The nose climb's flippers, eq. 29 (A' - dF) with a torque-limited lead: the front ones wait
        below the edge, come down while the nose is below ``climb_pitch`` and lie level on the top once
        over; the rear ones push once the nose is up or the front over, and come back once the rear is
        up (``top``: the top's height in {C}; ``up``: the rear-up latch)."""
        cfg, c, r = self.cfg, self.cmd, self.robot
        # the front flipper tip clears the edge when, a pulley radius ahead of its pivot (the pulley
        # against the riser), its tip pulley's bottom is above the top
        pivot_z = r.pulley_x * math.sin(obs.pitch)
        reach = pivot_z + math.sqrt(r.flipper_len ** 2 - r.pulley_r ** 2) - r.flipper_tip_r > top
        for f in range(4):
            if f < 2 and not (reach or self.over):
                continue  # the front flipper tips are still below the edge: they stay raised against the riser
            if f < 2 and self.over:
                # on the top: level there (-pitch, as CCM's press), pressing it would stand the nose up;
                # the nose up again with the rear over the edge: the next riser (a short tread), the
                # flippers go back to their cruise angle so their undersides meet its edge
                goal = cfg.flipper_start if (up and obs.pitch > cfg.mount_pitch) else max(-obs.pitch, cfg.flip_min)
                c.flip[f] += min(max(goal - c.flip[f], -cfg.release_d_f), cfg.release_d_f)  # np.clip's value
            elif f < 2:
                if obs.pitch > cfg.climb_pitch:
                    c.flip[f] = max(c.flip[f], obs.q_flip[f])  # the nose is up enough: hold
                    continue
                # onto the top at the release's quasi-static rate: a pressing flipper levers the nose up
                c.flip[f] = max(c.flip[f] - cfg.release_d_f, obs.q_flip[f] - cfg.flip_lead, cfg.flip_min)
            elif up:
                # the rear over the top's level: the rear flippers come back up (pushing on, they
                # would stand the rear up on the top)
                c.flip[f] = min(c.flip[f] + cfg.release_d_f, 0.0)
            elif obs.pitch > cfg.climb_pitch or self.over:
                # the rear flippers push the rear up once the nose is up (before, they would pitch it down)
                c.flip[f] = max(c.flip[f] - cfg.release_d_f, obs.q_flip[f] - cfg.flip_lead, cfg.flip_min)

    def _climb(self, obs) -> None:
        """Eqs. 28-29 with a vertical lift and the crawlers loaded (docs/assumptions-octopus.md).

        Lift: every tip target in {R} moves straight down by ``lift_dz`` a tick (IK), so the
        chassis rises vertically on its rolling tips; a boom-only lift (eq. 28 read literally)
        also swings the chassis along the arm planes, backward here, with nothing to stop it.
        The lift holds once H > H_EST + ``lift_margin`` (the track bottom just above the top),
        the front booms hold while the nose is above ``pitch_cap`` (the rear ones below minus it).
        Flippers: eq. 29, all down; the front ones press onto the top with a torque-limited
        lead, so the front crawlers carry load and drive; the rear ones push on the ground.
        S (eq. 5, track odometry) counts from the moment H reaches H_EST: before that the
        crawler front is against the riser and cannot advance. Release (S > L and H > H_EST):
        booms up by dE a tick to their rest angle, flippers up by dF to 0, then walk.
        """
        cfg, c = self.cfg, self.cmd
        if cfg.nose_climb and self.state == CLIMB:
            self._climb_nose(obs)
            return
        c.track[:] = cfg.climb_track_speed
        h = cog_height(self.tip_c[2:], cfg.h2)
        if self.state == CLIMB:
            if h >= self.h_est:
                self.s = travel(self.s, cfg.climb_track_speed, obs.pitch, self.dt)
                if cfg.climb_hold:
                    # arm moving while driving on the lifted body: each tip keeps its foothold
                    # (it does not roll forward into the next riser)
                    self.lift_tgt[:, 0] -= cfg.climb_track_speed * self.dt * math.cos(self.tp - obs.pitch)
            if h < self.h_est + cfg.lift_margin:
                for i in range(len(ARMS)):
                    front = i < 2
                    if (front and obs.pitch > cfg.pitch_cap) or (not front and obs.pitch < -cfg.pitch_cap):
                        continue
                    self.lift_tgt[i, 2] -= cfg.lift_dz if front else cfg.lift_dz * cfg.lift_rear
            for i in range(len(ARMS)):
                c.arm[i] = ak.ik_f(*self.lift_tgt[i].tolist(), self._ikc[i])
            for f in range(4):
                # eq. 29 (A' - dF), the command kept within flip_lead of the measured angle:
                # a flipper that meets the top (front) or the ground (rear) presses with kp * lead
                front = f < 2
                if front and h < cfg.flip_wait * self.h_est:
                    continue  # the tip is still below the edge: it stays raised against the riser
                c.flip[f] = max(c.flip[f] - cfg.d_f, obs.q_flip[f] - cfg.flip_lead, cfg.flip_min)
            if self.s > self.s_release and h > self.h_est:
                self.release_pitch = obs.pitch
                self.machine.go(obs.t, RELEASE, f"H = {h:.3f} m > H_EST, S = {self.s:.3f} m > {self.s_release:.2f} m")
        else:  # RELEASE (eqs. 28-29 second cases), at quasi-static rates
            if obs.pitch - self.release_pitch > cfg.release_tilt and self.resumes < cfg.max_resumes:
                self.resumes += 1
                # the nose rises while the booms come up: the rear is dropping, the COG is not yet
                # over the top (odometry counted slip): lift again and drive on
                self.s_release = self.s + cfg.release_more
                self.lift_tgt = self.tip_r.copy()
                self._nose_start(obs, resume=True)
                self.machine.go(obs.t, CLIMB, f"pitch rose {obs.pitch - self.release_pitch:.2f} rad > "
                           f"{cfg.release_tilt} while releasing: drive {cfg.release_more} m more")
                return
            for i in range(4):
                if (cfg.release_unload and cfg.nose_climb and i < 2 and not self.lifted[i]
                        and self.contact[i]):
                    # a front support on the top unloads at lift_dz a tick (the front crawlers settle
                    # onto the top) and, its target up at the sensed tip (no press left), lifts clear
                    t = self.lift_tgt[i]
                    t[2] += cfg.lift_dz
                    if t[2] >= self.tip_z[i]:
                        self.lifted[i] = True
                        self._lift_clear(obs, i, ARMS[i], "release: unloaded, lifted clear")
                    else:
                        c.arm[i] = ak.ik_f(*t.tolist(), self._ikc[i])
                if c.arm[i, 1] > cfg.release_boom:
                    c.arm[i, 1] = max(c.arm[i, 1] - cfg.release_d_e, cfg.release_boom)
            for f in range(4):
                if c.flip[f] < 0.0:
                    c.flip[f] = min(c.flip[f] + cfg.release_d_f, 0.0)
            if all(c.arm[i, 1] <= cfg.release_boom + 1e-9 for i in range(4)) and (c.flip >= -1e-9).all():
                # back to walking on the top: arms re-placed, front flippers to their cruise angle
                self._replace(obs, "booms and flippers released")

    def _stalled_alone(self, obs) -> str:
        """Why a climb on the crawlers alone (every arm lifted clear) cannot go on, or "": stopped
        at the guard (no arm is left to bring the nose down) or stalled (past its release distance,
        the pitch held within 0.02 rad for ``stall_time``: the crawlers slip); called every climb tick."""
        cfg = self.cfg
        alone = all(self.lifted.tolist())  # (np.all's value; Python bools are cheaper a tick)
        if abs(obs.pitch - self.still_pitch) > 0.02 or not alone or self.s <= self.s_release:
            self.still_pitch, self.still_t = obs.pitch, 0.0
        self.still_t += self.dt
        if not alone:
            return ""
        if obs.pitch > cfg.guard_pitch:
            return f"pitch {obs.pitch:.2f} rad > {cfg.guard_pitch}"
        if self.still_t > cfg.stall_time:
            return f"pitch held at {obs.pitch:.2f} rad for {cfg.stall_time:g} s past S = {self.s_release:.2f} m"
        return ""

    def _replace(self, obs, reason: str) -> None:
        """Back to walking with the four arms placed again (the crawlers wait for them while the body
        is pitched, ``place_pitch``), front flippers at their cruise angle, rear ones not pushing."""
        self.machine.go(obs.t, WALK, reason)
        self.queue = list(GAIT_ORDER)
        self.cmd.flip[:2] = self.cfg.flipper_start
        np.maximum(self.cmd.flip[2:], 0.0, out=self.cmd.flip[2:])
        self.contact[:] = [False] * 4
        self.placing = True

    # ---------------------------------------------------------------- main
    def __call__(self, obs) -> Command:
        cfg, c = self.cfg, self.cmd
        if not self.started:
            self._start(obs)
        # one forward-kinematics pass a tick: the tips in {R} (encoders), into tip_r's buffer (nothing
        # keeps a tick's tips past it but copies), and in {C} (+ IMU) on first use this tick (tip_c)
        ak.tips_into(obs.q_arm, ak.SIGNS, self._fkc, self.tip_r)
        self._tip_c, self._att = None, (obs.roll, obs.pitch)
        self.prev_tip_z, self.tip_z = self.tip_z, self.tip_r[:, 2].tolist()
        self.heading += obs.yaw_rate * self.dt
        state = self.machine.state  # (the branch's; c.mode reads self.state after a transition)
        if state == INIT:
            c.track[:] = 0.0
            self._support(obs, 0.0)
            i = self._transfer(obs)
            if i < 0 and not self.queue and not any(self.phase.values()) and not any(self.landing):
                self.machine.go(obs.t, WALK, "four arms placed")
            c.mode, c.moving_arm, c.stage = self.state, i, self._stage()
            self._lead(obs)
            return c
        if state == WALK:
            # the crawlers wait while a foothold is out of its arm's range (its transfer is due)
            # after a release the arms are re-placed; with the body still pitched (the rear below the
            # edge, the front already at the next riser of a short tread) the crawlers wait for them
            if self.placing and self._all_down():
                self.placing = False
            hold = self.placing and obs.pitch > cfg.place_pitch
            v = 0.0 if self.out_of_reach or hold else cfg.track_speed
            # paced on its way (gait_pace), not at a sensed up-step (the climb wants fresh footholds;
            # the riser stops the body anyway) nor while the arms are placed again after a release
            # (placing): there the fixed cycle is kept
            if v > 0.0 and cfg.gait_pace and self.last_case != UP and not self.placing:
                v = min(v, self._pace(obs.t))
            if obs.pitch > cfg.guard_pitch:
                # the paper's stability monitor: nose up toward the tip-back angle (~0.93 rad on the
                # rear flippers, ccm.tip_back_angle): the crawlers back off instead of pushing on
                v = -cfg.track_speed
                if not self.guarding:
                    self.machine.note(obs.t, "walk", "walk", f"pitch {obs.pitch:.2f} rad > "
                                      f"{cfg.guard_pitch}: crawlers back off")
            self.guarding = obs.pitch > cfg.guard_pitch
            c.track[0], c.track[1] = steer(v, self.heading, cfg.heading_gain, cfg.heading_dv)
            self.out_of_reach = self._support(obs, v, self._feel(obs) if cfg.flipper_feel else math.inf)
            q_flip, tau_flip = obs.q_flip.tolist(), obs.tau_flip.tolist()
            for f in (0, 1):
                c.flip[f], _ = flipper_rule(q_flip[f], tau_flip[f], cfg.t0, cfg.d_a, cfg.a0, cfg.d_b_flip)
            # a supporting arm pushed hard (collision): it is transferred next
            te, tr = obs.tau_elbow.tolist(), self.tau_ref.tolist()
            for i, k in enumerate(ARMS):
                if (self.phase[k] == 0 and self.contact[i] and k not in self.queue
                        and contact_detected(te[i], tr[i], cfg.hit_torque)):
                    self.queue.insert(0, k)
                    self.queue_reason[k] = (f"collision: elbow torque {obs.tau_elbow[i] - self.tau_ref[i]:+.0f} N m"
                                            f" > {cfg.hit_torque:g}")
            i = self._transfer(obs)
            # a tip held at full stretch (the pit check) holds its foothold but is no exploration
            # point: its arm has no travel left to press or lift with, so no climb starts on it
            all_down = self._all_down() and not any(self.stretched_on)
            if all_down:  # the four-tip exploration (z: the tips' heights in {C}, read below too)
                self.tp = terrain_angles(self.tip_c)[0]
                z = self.tip_c[:, 2]
                self.last_case = terrain_case(z, cfg.sigma)
            at_limit = max(q_flip[0], q_flip[1]) > cfg.a0 - 0.1
            # a low riser presses near the flipper pivot: the torque rule stalls below the limit,
            # so a front flipper raised this steep in the level frame (encoder + IMU pitch) that
            # has stopped rising for edge_time also means an edge ahead
            qf = max(q_flip[0], q_flip[1])
            self.flip_still = self.flip_still + self.dt if abs(qf - self.flip_prev) < 0.02 else 0.0
            if self.flip_still == 0.0:
                self.flip_prev = qf
            steep = qf + obs.pitch > cfg.edge_angle and self.flip_still > cfg.edge_time
            # the nose pitched up this much with an up-step sensed: the crawlers are mounting an
            # edge with the rear below it (the next terrace after a release): lift the rear too
            mounting = obs.pitch > cfg.mount_pitch
            # a climb does not start while a rear foothold is out of range (its arm is re-placed
            # first, the crawlers waiting): it would be lifted clear at once and the rear pushed up
            # by the other arm alone (step-400 seed 1's roll, 5 of 10 step-400 seeds stuck)
            rear_out = self.out_of_reach and self.out_arm[1] == "R"
            if all_down and not rear_out and self.last_case == UP and (at_limit or steep or mounting):
                # per terrace: the nearer (lower) front tip's height over the rear tips
                self.h_est = min(z[0], z[1]) - 0.5 * (z[2] + z[3])
                self.s, self.s_release, self.resumes = 0.0, cfg.climb_distance, 0
                self.lift_tgt = np.array([ak.fk(obs.q_arm[i], self.robot, k) for i, k in enumerate(ARMS)])
                self._nose_start(obs, mounted=mounting)
                why = ("front flippers at the limit" if at_limit else
                       f"a front flipper steep ({qf + obs.pitch:.2f} rad) and still" if steep else
                       f"nose up {obs.pitch:.2f} rad")
                self.machine.go(obs.t, CLIMB, f"up-step, H_EST = {self.h_est:.3f} m, {why}")
            c.mode, c.moving_arm, c.stage = self.state, i, self._stage()
            self._lead(obs)
            return c
        # CLIMB / RELEASE: eqs. 28-29 (lift, drive, release); see _climb
        self._climb(obs)
        c.mode, c.moving_arm, c.stage = self.state, -1, self._stage()
        self._lead(obs)
        return c

    def _stage(self) -> int:
        """The climb's stage after this tick's step (:data:`STAGE_NAMES`; 0 outside a climb)."""
        if self.state == RELEASE:
            return RELEASING
        if self.state != CLIMB:
            return 0
        if self.cfg.nose_climb:
            return DRIVE_ON if self.up else REAR_LIFT if self.over else LIFT
        # the vertical climb: S counts from H >= H_EST, the drive on
        return DRIVE_ON if self.s > 0.0 else LIFT
