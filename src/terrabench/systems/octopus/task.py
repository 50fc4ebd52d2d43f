"""One OCTOPUS episode as a hallway :class:`~terrabench.systems.base.Task`.

The scene is a floor plus box pieces from :mod:`terrabench.terrain.pieces`; the robot starts
behind the first edge. Ground truth used only here (never by controllers): progress along the
approach axis, the stability margin from MuJoCo contacts, the stop checks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numba
import numpy as np

from terrabench.sim.checks import Stalled, turned_over
from terrabench.sim.episode import Timing
from terrabench.systems.base import TaskBase
from terrabench.systems.octopus.config import OctopusConfig
from terrabench.systems.octopus.robot import ARMS, FLIPPERS, Names, actuated_joints, add_robot
from terrabench.systems.octopus.rules import Command
from terrabench.systems.octopus.sensing import Observation, roll_pitch_f
from terrabench.systems.octopus.stability import Footprint, least_depth, signed_margin
from terrabench.terrain import pieces
from terrabench.terrain.mjcf import GROUND_BIT

COLUMNS = ("s", "lat", "z", "roll", "pitch", "margin", "mode", "moving_arm", "tip_contact",
           "flip_front", "flip_rear", "tau_elbow_LF", "tau_elbow_RF", "tau_elbow_LR", "tau_elbow_RR",
           "margin_all", "quasi", "track_share", "track_power",
           "RF_swing", "RF_boom", "RF_elbow", "RR_swing", "RR_boom", "RR_elbow",
           "margin_sensed", "tip_slip", "track_cmd", "tip_slip_mode", "crawlers_in_tips",
           "margin_crawlers", "climb_stage")
#: the supporting tips widen the crawlers' margin (Fig. 7's conclusion) when they add more than this
#: (m): far above the hull's rounding (~1e-15 m), a millimetre is no stability a robot could use
GAIN_EPS = 0.001
#: a contact counts in the support polygon if its geom carried this normal force (N) ...
SUPPORT_LOAD = 20.0
#: ... within this long (s)
SUPPORT_MEMORY = 0.5
#: quasi-static instants: chassis speed (m/s), angular speed (rad/s) and the normal ground load
#: within this fraction of the weight
QS_SPEED, QS_RATE, QS_LOAD = 0.15, 0.3, 0.2
#: tip-back (status ``tipped_back``, :meth:`OctopusTask._tip_back`): the COG's ground projection
#: behind the rearmost contact loaded > SUPPORT_LOAD N on the stored row, along the heading, that
#: contact on a rear end of the robot (rear flipper, rear track pulley, rear arm tip; a pivot under
#: the track run is an edge it seesaws over), with the nose up and rising, on consecutive stored
#: rows spanning this long (s). Nothing is then behind
#: the COG to hold it: the weight's moment about the rear contact line turns the robot backwards,
#: and the nose still rising says it does. A contact unloaded for an instant (a bounce, a rebound:
#: tens of ms at these contact stiffnesses) resets the run once it carries load again; the fall it
#: flags, from the COG over the rear flipper tips (pitch ~0.9 rad) to the robot on its tail on the
#: rear arm tips (~1.45 rad), took 0.6-0.7 s on step-400, so 0.2 s (two more stored rows) leaves the
#: run three times over before the landing puts a loaded contact behind the COG again.
TIP_BACK_HOLD = 0.2
#: ... and the COG passes behind that contact: the rearmost loaded contact moves less than this (m)
#: from one stored row to the next, through the run and into it from the row before (the COG then
#: ahead of it). Rolling back over a flipper tip or a track pulley moves the contact by ~1 cm a row
#: (0.1 s at <= 1 rad/s), crawling at 0.1 m/s by 1 cm; a rearmost contact that jumps by more is
#: another contact carrying the load while the rear one is off it for an instant (CCM's press on
#: step-400: for one row at 6.2 s only the front flippers on the edge, 0.42 m ahead of the COG)
TIP_BACK_JUMP = 0.05
#: last-resort attitude guard (``turned_over``): nose up or down beyond this (rad), past the vertical
#: (pi/2), the robot is on its back or its nose whatever its contacts. A backward fall is told by
#: the tip-back rule first; |roll| stays on ``protocol.turn_over``.
TURN_OVER_PITCH = 1.6
#: rough-ground instances (beyond the paper): id -> normalised sine-sum height (heights 20 x this m)
ROUGH_LEVELS = {"rough-1": 0.01, "rough-2": 0.02, "rough-3": 0.04}
#: rough ground: start this far behind the origin, succeed this far past it (m): 1.5 m of travel
ROUGH_GOAL = 0.75


@numba.njit(cache=True)
def _contact_pass(ncon, geom, efc_address, dim, friction, frame, pos, efc_force, ground, tip_of, side_of,
                  sel, rg, f, side, fr, xy):  # pragma: no cover
    """One pass over the ``ncon`` contacts (compiled: the per-tick contact work, no Python per contact).

    Writes the robot-ground contacts' indices into ``data.contact`` (``sel``), their robot geoms
    (``rg``), the crawler side of each (``side``, from ``side_of``; -1 not a crawler surface),
    their contact frames (``fr``, rows of 9), their ground points' x, y (``xy``, from ``pos``)
    and their contact-frame forces (normal, two
    tangential) (``f``, N): pyramidal cones
    of dimension 3 (this model's), the normal force the sum of the four pyramid-edge forces
    ((e0 + e1) + e2) + e3, a tangential one mu x (f+ - f-), as ``mj_contactForce`` gives them.
    Returns (count, bits of the arm tips touching anything (``tip_of``: geom -> tip index or -1),
    whether every selected contact has dimension 3).
    """
    k, bits, dim3 = 0, 0, True
    for j in range(ncon):
        g1, g2 = geom[j, 0], geom[j, 1]
        if tip_of[g1] >= 0:
            bits |= 1 << tip_of[g1]
        if tip_of[g2] >= 0:
            bits |= 1 << tip_of[g2]
        if ground[g1] == ground[g2]:
            continue
        sel[k] = j
        r = g2 if ground[g1] else g1
        rg[k] = r
        side[k] = side_of[r]
        for i in range(9):
            fr[k, i] = frame[j, i]
        xy[k, 0], xy[k, 1] = pos[j, 0], pos[j, 1]
        if dim[j] != 3:
            dim3 = False
        a = efc_address[j]
        e0 = e1 = e2 = e3 = 0.0
        if a >= 0:
            e0, e1, e2, e3 = efc_force[a], efc_force[a + 1], efc_force[a + 2], efc_force[a + 3]
        f[k, 0] = ((e0 + e1) + e2) + e3
        f[k, 1] = (e0 - e1) * friction[j, 0]
        f[k, 2] = (e2 - e3) * friction[j, 1]
        k += 1
    return k, bits, dim3


#: the longest sum :func:`_pairwise_sum` replicates (numpy's ``PW_BLOCKSIZE``: beyond it numpy
#: splits the sum in halves, recursively)
PW_BLOCK = 128


@numba.njit(cache=True)
def _pairwise_sum(a, n):  # pragma: no cover
    """numpy's sum of the first ``n`` <= PW_BLOCK values of ``a`` in numpy's order (``pairwise_sum``
    of its float loops: under 8 values one after the other, up to 128 from eight partial sums
    and the rest one after the other), 0.0 + that (the reduction starts from add's identity);
    checked against ``np.sum`` in tests/octopus/test_octopus_perf.py."""
    if n < 8:
        res = -0.0
        for i in range(n):
            res += a[i]
        return 0.0 + res
    r0, r1, r2, r3, r4, r5, r6, r7 = a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]
    i = 8
    while i < n - n % 8:
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[i]
        i += 1
    return 0.0 + res


@numba.njit(cache=True)
def _loads(k, f, side, xy, rg, load_min, fn, on, now, now_g):  # pragma: no cover
    """The normal loads of the pass's ``k`` contacts, compiled: returns (the robot's normal load,
    the crawlers' part of it (``side`` >= 0), the number of crawler contacts, the number of
    contacts loaded > ``load_min``), the two loads as numpy's ``fn.sum()`` and
    ``fn[side >= 0].sum()`` give them (the same values in the same order, :func:`_pairwise_sum`;
    NaN beyond PW_BLOCK values: the caller sums ``fn[:k]`` and ``on[:count]`` with numpy), and
    writes the loaded contacts' ground points and robot geoms into ``now`` and ``now_g``
    (``xy[fn > load_min]``, ``rg[fn > load_min]``)."""
    c = m = 0
    for a in range(k):
        x = f[a, 0]
        fn[a] = x
        if side[a] >= 0:
            on[c] = x
            c += 1
        if x > load_min:
            now[m, 0], now[m, 1] = xy[a, 0], xy[a, 1]
            now_g[m] = rg[a]
            m += 1
    if k > PW_BLOCK:
        return math.nan, math.nan, c, m
    return _pairwise_sum(fn, k), _pairwise_sum(on, c), c, m


@numba.njit(cache=True)
def _side_traction(k, f, d1, d2, side, out):  # pragma: no cover
    """Each crawler side's traction (N): |f1 (t1 . x) + f2 (t2 . x)| summed over the side's
    contacts in contact order (``side`` -1: not a crawler surface)."""
    out[0] = 0.0
    out[1] = 0.0
    for a in range(k):
        s = side[a]
        if s >= 0:
            out[s] += abs(f[a, 1] * d1[a] + f[a, 2] * d2[a])


@numba.njit(cache=True)
def _drive_power(fx, v):  # pragma: no cover
    """The crawlers' drive power (W): each side's traction force ``fx`` x its commanded speed ``v``,
    ``|fx0 v0| + |fx1 v1|``."""
    return abs(fx[0] * v[0]) + abs(fx[1] * v[1])


@numba.njit(cache=True)
def _power_parts(force, vel, ax, ay, fx, v):  # pragma: no cover
    """``ax[:] = |force|``, ``ay[:] = |vel|`` (np.abs's values: the sign bit cleared) for the
    servos' power, and returns :func:`_drive_power` of ``fx``, ``v``: one call a tick."""
    for i in range(force.shape[0]):
        ax[i] = abs(force[i])
        ay[i] = abs(vel[i])
    return _drive_power(fx, v)


#: the stored row's columns that change on the sampled rows only (:meth:`OctopusTask.row`): they
#: wait in the row's template between them (the evaluation figures, ``_sample``, the tip bits,
#: ``_mech``); :func:`_row_fill` writes the others
_SAMPLE_COLS = (5, 15, 16, 17, 18)
_TIPS_COL = 8
_MECH_COLS = (25, 26, 27, 28, 29, 30)
_STAGE_COL = 31
assert [COLUMNS[i] for i in _SAMPLE_COLS + (_TIPS_COL,) + _MECH_COLS] == [
    "margin", "margin_all", "quasi", "track_share", "track_power", "tip_contact", "margin_sensed", "tip_slip",
    "track_cmd", "tip_slip_mode", "crawlers_in_tips", "margin_crawlers"]
assert COLUMNS[_STAGE_COL] == "climb_stage"


@numba.njit(cache=True)
def _row_fill(tmpl, flat, s, lat, z, roll, pitch, mode, mov, stage):  # pragma: no cover
    """A fresh stored row: the template's sampled figures (margins, tips, mechanism) and this
    tick's values (position, attitude, command, flipper means, elbow torques, right arms' joints,
    the climb's stage) from the observation's one buffer ``flat`` (flippers, arms LF, RF, LR, RR,
    flipper torques, elbow torques): :meth:`OctopusTask.row`'s tuple, value for value."""
    out = tmpl.copy()
    out[0], out[1], out[2], out[3], out[4] = s, lat, z, roll, pitch
    out[6], out[7], out[_STAGE_COL] = mode, mov, stage
    out[9] = 0.5 * (flat[0] + flat[1])
    out[10] = 0.5 * (flat[2] + flat[3])
    for i in range(4):
        out[11 + i] = flat[20 + i]
    for i in range(3):
        out[19 + i] = flat[7 + i]
        out[22 + i] = flat[13 + i]
    return out


@numba.njit(cache=True)
def _rearmost(loaded, geoms, rear_end, hx, hy):  # pragma: no cover
    """The rearmost of the (m >= 1, 2) ``loaded`` points along the heading (hx, hy) and whether its
    robot geom (``geoms``) is one of the ``rear_end``: (``min(along)``, ``rear_end[geoms[k]]``)
    with ``along`` the Python list ``[x * hx + y * hy ...]`` and ``k = along.index(min(along))``
    (:meth:`OctopusTask._tip_back`'s formula: Python's min keeps the first of equals and never
    leaves a NaN it starts from; index finds that one)."""
    rs = loaded[0, 0] * hx + loaded[0, 1] * hy
    k = 0
    for a in range(1, loaded.shape[0]):
        v = loaded[a, 0] * hx + loaded[a, 1] * hy
        if v < rs:
            rs, k = v, a
    return rs, rear_end[geoms[k]]


@numba.njit(cache=True)
def _mech_geometry(gx, sensed, tip_geoms, support, foot, cx, cy, tp):  # pragma: no cover
    """The geometry of :meth:`OctopusTask._mechanism` in one compiled call, from the geoms' world
    positions ``gx``: (the sensed margin of the ``sensed`` geoms' x, y about (cx, cy), the least
    depth of the ``foot`` geoms inside the supporting tips' hull (``support``: 1 where a tip
    supports; NaN with fewer than three), the margin of the ``foot`` geoms alone); writes the
    tips' positions into ``tp`` (4, 3). The same point arrays and the same compiled margin as
    ``stability_margin(gx[sensed, :2], cog)``, ``least_depth(gx[tips[support], :2], gx[foot, :2])``
    and ``stability_margin(gx[foot, :2], cog)``."""
    n = sensed.shape[0]
    pts = np.empty((n, 2))
    for a in range(n):
        pts[a, 0], pts[a, 1] = gx[sensed[a], 0], gx[sensed[a], 1]
    sensed_m = signed_margin(pts, cx, cy)
    nf = foot.shape[0]
    fp = np.empty((nf, 2))
    for a in range(nf):
        fp[a, 0], fp[a, 1] = gx[foot[a], 0], gx[foot[a], 1]
    crawlers = signed_margin(fp, cx, cy)
    ns = 0
    for i in range(tip_geoms.shape[0]):
        g = tip_geoms[i]
        tp[i, 0], tp[i, 1], tp[i, 2] = gx[g, 0], gx[g, 1], gx[g, 2]
        if support[i]:
            ns += 1
    inside = math.nan
    if ns >= 3:
        sup = np.empty((ns, 2))
        a = 0
        for i in range(tip_geoms.shape[0]):
            if support[i]:
                sup[a, 0], sup[a, 1] = tp[i, 0], tp[i, 1]
                a += 1
        inside = least_depth(sup, fp)
    return sensed_m, inside, crawlers


@numba.njit(cache=True)
def _phase_drift(tp, start, on, i):  # pragma: no cover
    """Tip ``i``'s distance (m) from where its support phase began (``start[i]``, ``on[i]``): 0 on
    the phase's first row, which sets the start. The distance is np.linalg.norm's value (the
    square root of a sequential dot product; tests/octopus/test_octopus_perf.py)."""
    if not on[i]:
        on[i] = True
        start[i, 0], start[i, 1], start[i, 2] = tp[i, 0], tp[i, 1], tp[i, 2]
        return 0.0
    x, y, z = tp[i, 0] - start[i, 0], tp[i, 1] - start[i, 1], tp[i, 2] - start[i, 2]
    return math.sqrt(x * x + y * y + z * z)


@numba.njit(cache=True)
def _tip_drifts(tips, moving, reset_mode, tp, st, st_on, sm, sm_on):  # pragma: no cover
    """The tip drifts of :meth:`OctopusTask._mechanism`, compiled: the supporting arms (tip bit on
    in ``tips``, not ``moving``) keep where their support phase began (``st``, ``st_on``) and
    where it began in this controller mode (``sm``, ``sm_on``; all restarted first when
    ``reset_mode``); returns (the largest drift, the largest within the mode) (m), each as
    Python's ``max(drift, d)`` of the :func:`_phase_drift` values (d taken only when greater)."""
    if reset_mode:
        for i in range(sm_on.shape[0]):
            sm_on[i] = False
    drift = drift_mode = 0.0
    for i in range(tp.shape[0]):
        if (tips >> i) & 1 and i != moving:
            d = _phase_drift(tp, st, st_on, i)
            if d > drift:
                drift = d
            d = _phase_drift(tp, sm, sm_on, i)
            if d > drift_mode:
                drift_mode = d
        else:
            st_on[i] = False
            sm_on[i] = False
    return drift, drift_mode


@numba.njit(cache=True)
def _apply_command(track, force, pmax, v, sv, lin_ids, lin_side, lin_sign, rot_ids, rot_side, rot_gain,
                   flip, arm, ctrl, dq):  # pragma: no cover
    """The command's limits and model changes in one compiled pass (see :meth:`OctopusTask.apply`):
    the crawler power limit, the moving surfaces' velocities, the servo references clipped to
    ``ctrl`` +- ``dq`` (numpy's clip: a NaN command stays NaN)."""
    for i in range(2):
        vi, fi = track[i], force[i]
        if fi > 1e-6 and abs(vi) * fi > pmax:
            vi = math.copysign(pmax / fi, vi)
        v[i] = vi
    for a in range(lin_ids.shape[0]):
        sv[lin_ids[a], 0] = -(v[lin_side[a]] * lin_sign[a])
    for a in range(rot_ids.shape[0]):
        sv[rot_ids[a], 5] = v[rot_side[a]] * rot_gain[a]
    n = flip.shape[0]
    for i in range(n + arm.shape[0]):
        x = flip[i] if i < n else arm[i - n]
        lo, hi = ctrl[i] - dq[i], ctrl[i] + dq[i]
        y = x if (x != x or x > lo) else lo
        ctrl[i] = y if (y != y or y < hi) else hi


@dataclass(frozen=True)
class Layout:
    """An instance's terrain and goal.

    Attributes:
        kind: ``step`` | ``terrace`` | ``block``.
        boxes: the terrain pieces.
        edge: along-axis position of the last edge to get past (m) (block: the block's far end).
        top: height of the top (m) (block: 0).
        axis_yaw: yaw of the approach axis (rad).
        start: chassis start (x, y) (m) and start_yaw (rad).
    """

    kind: str
    boxes: tuple
    edge: float
    top: float
    axis_yaw: float
    start: tuple[float, float]
    start_yaw: float
    terrain: object = None  # rough ground: the sine-sum parameters (terrain.sine_sum), centred at 0


#: across-axis extent of terrace2-side's terraces (m): the robot crosses them at side_yaw_deg to
#: their normal, so its path drifts across the axis (0.85 m at 25 deg) and its arms reach ~0.8 m
#: beyond the tracks
SIDE_TERRACE_WIDTH = 6.0


def layout(instance: str, cfg: OctopusConfig, seed: int) -> Layout:
    """The terrain pieces and start of an instance id (``step-400``, ``terrace2-front``, ...)."""
    sc = cfg.scene
    rng = np.random.default_rng(seed)
    off, dyaw = pieces.jitter(rng, sc.jitter_offset, sc.jitter_yaw_deg) if seed else (0.0, 0.0)
    d = sc.start_distance
    if instance == "step-400" or instance.startswith("sweep-h"):
        h = sc.step_height if instance == "step-400" else int(instance[len("sweep-h"):]) / 1000.0
        if not 0 < h <= sc.max_step_height:
            raise ValueError(f"step height {h} m outside (0, {sc.max_step_height}] m")
        boxes = pieces.step(h, edge_x=0.0)
        return Layout("step", boxes, 0.0, h, 0.0, (-d, off), dyaw)
    if instance in ("terrace2-front", "terrace2-side"):
        side = instance.endswith("side")
        yaw = math.radians(sc.side_yaw_deg) if side else 0.0
        # from the side the terraces are turned by yaw and the robot is not: it drives along world
        # x and meets the edges at yaw to their normal, one crawler before the other ("the heights
        # of terrace under left side and right side crawlers are not same" [P]); the 2.0 m drive
        # along x drifts ~0.85 m across the axis, so the terraces are wider there
        boxes = pieces.terraces(sc.terrace_heights, (sc.terrace_tread,), edge_x=0.0, yaw=yaw,
                                width=SIDE_TERRACE_WIDTH if side else 3.0)
        top = float(sum(sc.terrace_heights))
        # the robot starts on the approach axis d behind the first edge (the front task: facing it)
        sx, sy = -d * math.cos(yaw) - off * math.sin(yaw), -d * math.sin(yaw) + off * math.cos(yaw)
        return Layout("terrace", boxes, sc.terrace_tread, top, yaw, (sx, sy), dyaw if side else yaw + dyaw)
    if instance in ROUGH_LEVELS:
        # beyond the paper: rough ground from the shared sine-sum generator (MRS-CWC's family),
        # one terrain per seed at the level's normalised height, centred on the origin
        from terrabench.terrain import sine_sum

        hgt = ROUGH_LEVELS[instance]
        params = sine_sum.random_params(np.random.default_rng(1000 + seed), height_range=(hgt, hgt))
        return Layout("rough", (), ROUGH_GOAL - cfg.protocol.success_past, 0.0, 0.0, (-ROUGH_GOAL, off), dyaw,
                      params)
    if instance == "block-500":
        r = cfg.robot
        # the gap is from the robot's outermost contact surface: the flipper pulley capsules'
        # rounded ends reach pulley_r beyond the flipper's side face
        y_edge = -(r.flipper_y + r.flipper_w / 2 + r.pulley_r) - sc.block_gap
        boxes = pieces.block(sc.block_height, sc.block_length, sc.block_width, x0=0.0,
                             y_center=y_edge - sc.block_width / 2)
        return Layout("block", boxes, sc.block_length, 0.0, 0.0, (-d, off), dyaw)
    raise ValueError(f"unknown octopus instance {instance!r}")


def _least_run_mean(mode: np.ndarray, rows: np.ndarray, values: np.ndarray) -> float:
    """The least mean of the finite ``values`` over the runs of consecutive ``rows`` (bool) with one
    ``mode``; NaN without such a run."""
    best = math.inf
    k, n = 0, len(mode)
    while k < n:
        if not rows[k]:
            k += 1
            continue
        j = k
        while j + 1 < n and rows[j + 1] and mode[j + 1] == mode[k]:
            j += 1
        v = values[k:j + 1]
        v = v[np.isfinite(v)]
        if len(v):
            best = min(best, float(np.mean(v)))
        k = j + 1
    return best if best < math.inf else math.nan


class OctopusTask(TaskBase):
    """The robot driven by one controller on one instance's terrain."""

    columns = COLUMNS

    def __init__(self, method: str, instance: str, cfg: OctopusConfig, seed: int = 0):
        self.method, self.instance, self.cfg, self.seed = method, instance, cfg, seed
        pr = cfg.protocol
        self.physics = cfg.physics
        self.timing = Timing(pr.control_period, pr.timeout, pr.check_period, pr.log_period)
        self.layout = layout(instance, cfg, seed)
        # renders of step tasks look from the robot's right side, across the approach axis, so
        # the robot's front and the edge stay in view (the default view looks through the step)
        yaw = math.degrees(self.layout.axis_yaw)
        self.camera = {"azimuth": 90.0 + yaw, "elevation": -12.0} if self.layout.kind in ("step", "terrace") else {}

    # ------------------------------------------------------------------ scene
    def build(self, spec: mujoco.MjSpec) -> None:
        lay, r = self.layout, self.cfg.robot
        spec.modelname = f"octopus_{self.instance}"
        z0 = 0.0
        if lay.terrain is None:
            spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[20, 20, 0.1],
                                    friction=[self.cfg.scene.friction, 0.005, 0.0001], contype=GROUND_BIT,
                                    conaffinity=0, rgba=[0.5, 0.5, 0.5, 1])
        else:
            from terrabench.terrain import sine_sum
            from terrabench.terrain.mjcf import add_heightfield

            p = lay.terrain
            x, y = sine_sum.vertex_xy(p)
            cx, cy = sine_sum.CENTRE_XY
            add_heightfield(spec, sine_sum.heights(p), x - cx, y - cy, name="floor", friction=self.cfg.scene.friction)
            # the robot starts above the highest ground under its footprint
            around = np.linspace(-0.6, 0.6, 13)
            gx, gy = np.meshgrid(around + lay.start[0] + cx, around + lay.start[1] + cy)
            z0 = float(np.max(sine_sum.point_height(p, gx, gy)))
        pieces.add_boxes(spec, lay.boxes, friction=self.cfg.scene.friction)
        spec.worldbody.add_light(pos=[0, 0, 4], dir=[0, 0, -1])
        add_robot(spec, (lay.start[0], lay.start[1], z0 + r.pulley_r + 0.01), lay.start_yaw, r)
        # start pose of the arms: out to the sides, tips just above the ground
        self._q0 = {Names.arm_joint(k, "swing"): (0.9 if k[1] == "F" else -0.6) for k in ARMS}
        self._q0.update({Names.arm_joint(k, "boom"): -0.3 for k in ARMS})
        self._q0.update({Names.arm_joint(k, "elbow"): 1.0 for k in ARMS})

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> Observation:
        self.model, self.data = model, data
        for j, q in self._q0.items():
            data.qpos[model.joint(j).qposadr[0]] = q
        mujoco.mj_forward(model, data)
        self.act = np.array([model.actuator(Names.act(j)).id for j in actuated_joints()])
        data.ctrl[self.act] = [data.qpos[model.joint(j).qposadr[0]] for j in actuated_joints()]
        self.chassis = model.body(Names.CHASSIS).id
        # moving surfaces: (geom id, side index, kind 0 = linear run / 1 = pulley of radius, sign)
        surf = []
        for si, side in enumerate(Names.SIDES):
            for nm in Names.track_geoms(side):
                surf.append((model.geom(nm).id, si, nm.endswith("_run"), 1.0))
        for k in FLIPPERS:
            sign = 1.0 if k[1] == "F" else -1.0  # rear flippers' frames are turned about z
            for nm in Names.flipper_geoms(k):
                surf.append((model.geom(nm).id, 0 if k[0] == "L" else 1, nm.endswith("_run"), sign))
        self.surf_id = np.array([s[0] for s in surf])
        self.surf_side = np.array([s[1] for s in surf])
        self.surf_lin = np.array([s[2] for s in surf])
        self.surf_sign = np.array([s[3] for s in surf])
        self.surf_r = model.geom_size[self.surf_id, 0]
        self.ground = np.zeros(model.ngeom, bool)
        for g in range(model.ngeom):
            if model.geom_bodyid[g] == 0:
                self.ground[g] = True
        self.tip_geoms = np.array([model.geom(Names.tip(k)).id for k in ARMS])
        self.robot_geom = ~self.ground
        self.obs = Observation(model, data)
        pr = self.cfg.protocol
        self._stall = Stalled(pr.stuck_time, pr.stuck_progress)
        self._hold_n = int(round(pr.success_hold / pr.control_period))
        self._on_top_n = 0
        # the stop check's thresholds (:meth:`check`), once: the goal line along the approach axis
        # (the block: its far end + block_past; else the last edge + success_past) and, on a step
        # or terrace, the chassis height that says it is on the top
        lay = self.layout
        self._goal = lay.edge + (pr.block_past if lay.kind == "block" else pr.success_past)
        self._top_z = None if lay.kind in ("block", "rough") else lay.top + self.cfg.robot.pulley_r - 0.05
        self._turn_over, self._success_tilt = pr.turn_over, pr.success_tilt
        # views of the chassis' pose and of the actuators' forces and velocities (MjData's fixed
        # arrays: the views stay valid)
        self._xpos, self._xquat = data.xpos[self.chassis], data.xquat[self.chassis]
        self._act_force, self._act_vel = data.actuator_force, data.actuator_velocity
        self._com_xy, self._geom_xpos = data.subtree_com[self.chassis, :2], data.geom_xpos  # the COG (x, y)
        c, s = math.cos(self.layout.axis_yaw), math.sin(self.layout.axis_yaw)
        self._axis_f = ((c, s), (-s, c))
        self._prog_t, self._prog = -1.0, (0.0, 0.0, 0.0)
        self._att_t, self._att = -1.0, (0.0, 0.0)
        # the evaluation-only columns (margin, tip contacts) are computed on the rows the store
        # keeps (every log period, and the last): the same stored series at a fifth of the cost
        self._row_k = 0
        self._row_stride = max(1, int(round(pr.log_period / pr.control_period)))
        self._tips = 0.0
        lin = self.surf_lin.astype(bool)
        self._lin_ids, self._rot_ids = self.surf_id[lin], self.surf_id[~lin]
        self._lin_sel = (self.surf_side[lin], self.surf_sign[lin])
        self._rot_sel = (self.surf_side[~lin], self.surf_sign[~lin] / self.surf_r[~lin])
        # physics limits: servo commands rate-limited to the joint speed limits, crawler power
        rc = self.cfg.robot
        w = np.array([rc.joint_speed[0]] * 4 + list(rc.joint_speed[1:]) * 4)
        self._dq = w * pr.control_period
        self._ctrl = data.ctrl[self.act].copy()
        self._ctrl_view = data.ctrl if np.array_equal(self.act, np.arange(model.nu)) else None
        self._side_of = np.full(model.ngeom, -1)
        self._side_of[self.surf_id] = self.surf_side
        self._pa, self._pb = np.empty(model.nu), np.empty(model.nu)  # |actuator force|, |velocity| (power)
        self._weight = float(model.body_subtreemass[self.chassis]) * float(-model.opt.gravity[2])
        self._footprint = Footprint(SUPPORT_MEMORY)
        self._behind: tuple[float, ...] | None = None  # tip-back run: (t, pitch, COG, contact) at its start
        self._rear_prev = (math.nan, False)  # the last stored row's rearmost loaded contact (m), COG behind it
        # the robot's rear ends (tip-back pivots, :meth:`_tip_back`): the rear flippers, the main
        # tracks' rear pulleys, the rear arm tips
        rear_end = [nm for k in FLIPPERS if k[1] == "R" for nm in Names.flipper_geoms(k)]
        rear_end += [Names.track_geoms(side)[2] for side in Names.SIDES] + [Names.tip(k) for k in ARMS if k[1] == "R"]
        self._rear_end = np.zeros(model.ngeom, bool)
        self._rear_end[[model.geom(nm).id for nm in rear_end]] = True
        self._tipped: dict | None = None  # the tip-back event once the run held (:meth:`_tip_back`)
        self._f6 = np.zeros(6)
        self._track_force = np.zeros(2)
        self._v = np.zeros(2)
        # the contact pass (_contacts): once per instant, into these buffers (grown with ncon)
        self._tip_of = np.full(model.ngeom, -1)
        self._tip_of[self.tip_geoms] = np.arange(len(self.tip_geoms))
        self._pyramid = model.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL
        self._con_t, self._con, self._k = -1.0, (np.empty(0, int), np.empty(0, int), np.empty((0, 3)), 0), 0
        self._buf = self._buffers(64)
        self._ax = data.xmat[self.chassis].reshape(3, 3)[:, 0]  # the chassis x axis (a view)
        self._lin_side = np.ascontiguousarray(self._lin_sel[0])
        self._lin_sign = np.ascontiguousarray(self._lin_sel[1], dtype=float)
        self._rot_side = np.ascontiguousarray(self._rot_sel[0])
        self._rot_gain = np.ascontiguousarray(self._rot_sel[1], dtype=float)
        self._sample = (float("nan"),) * 5
        # the stored row's template (:func:`_row_fill`): the sampled columns, NaN until the first
        self._row_tmpl = np.full(len(COLUMNS), np.nan)
        self._tp = np.empty((len(ARMS), 3))  # the tips' positions on a stored row (:func:`_mech_geometry`)
        self._support = np.zeros(len(ARMS), np.bool_)
        # the sensed margin's points: the four track pulleys (the track footprint's ends)
        self._foot = np.array([model.geom(nm).id for side in Names.SIDES
                               for nm in Names.track_geoms(side) if not nm.endswith("_run")])
        # per bit pattern of the tips in contact: the geoms whose points the sensed margin takes
        # (those tips, then the pulleys), one fancy index a stored row
        self._sensed_geoms = [np.concatenate((self.tip_geoms[[i for i in range(len(ARMS)) if b >> i & 1]],
                                              self._foot)) for b in range(1 << len(ARMS))]
        # tip slip: where each tip's current contact run (support phase) began, and whether it is
        # in one (:func:`_tip_drifts`)
        self._tip_start = (np.zeros((len(ARMS), 3)), np.zeros(len(ARMS), np.bool_))
        # the same, restarted when the controller's mode changes (walk, climb, release)
        self._tip_start_mode = (np.zeros((len(ARMS), 3)), np.zeros(len(ARMS), np.bool_))
        self._mech_mode = float("nan")
        self._mech = (float("nan"),) * 5
        self.apply_tracks(np.zeros(2))
        return self.obs

    # ------------------------------------------------------------------ loop
    def observe(self) -> Observation:
        return self.obs.refresh()

    def progress(self) -> tuple[float, float]:
        """(along, across) the approach axis (m); computed once per instant (check and row share it)."""
        return self._position()[:2]

    def _position(self) -> tuple[float, float, float]:
        """(along, across) the approach axis and the chassis height (m), once per instant."""
        t = self.data.time
        if t != self._prog_t:
            x, y, z = self._xpos.tolist()
            (ca, sa), (cp, sp) = self._axis_f
            self._prog, self._prog_t = (x * ca + y * sa, x * cp + y * sp, z), t
        return self._prog

    def attitude(self) -> tuple[float, float]:
        """The chassis' true (roll, pitch) (rad); computed once per instant (check and the stored
        row's tip-back rule share it)."""
        t = self.data.time
        if t != self._att_t:
            self._att, self._att_t = roll_pitch_f(*self._xquat.tolist()), t
        return self._att

    def check(self, obs: Observation, slow: bool) -> tuple[str, str] | None:
        roll, pitch = self.attitude()
        turn_over = self._turn_over
        if abs(roll) > turn_over or abs(pitch) > TURN_OVER_PITCH:  # (turned_over's test, its reason)
            return turned_over(roll, pitch, turn_over, TURN_OVER_PITCH)
        if self._tipped is not None:
            return "tipped_back", self._tipped["reason"]
        s, lat, z = self._position()
        goal = self._goal
        if slow:
            stuck = self._stall(self.data.time, s, lat, abs(goal - s), f"at s = {s:.2f} m")
            if stuck is not None:
                return stuck
        tilt = self._success_tilt
        stable = abs(roll) < tilt and abs(pitch) < tilt
        # past the goal line (the block: past its far end; a step or terrace: on the top too)
        past = s > goal and (self._top_z is None or z > self._top_z)
        self._on_top_n = self._on_top_n + 1 if (past and stable) else 0
        if self._on_top_n >= self._hold_n:
            pr, lay = self.cfg.protocol, self.layout
            where = {"block": "past the block", "rough": "1.5 m over the rough ground"}.get(
                lay.kind, f"on the {lay.top:.2f} m top")
            return "success", f"{where}, stable for {pr.success_hold} s"
        return None

    def apply_tracks(self, v: np.ndarray) -> None:
        sv = self.model.geom_surfacevel
        side, sign = self._lin_sel
        sv[self._lin_ids, 0] = -(v[side] * sign)
        side, gain = self._rot_sel
        sv[self._rot_ids, 5] = v[side] * gain

    def apply(self, cmd: Command) -> None:
        """The command's limits: the crawler power limit (a side's speed is cut so that its
        traction force now, every control tick, times the speed stays within
        ``robot.track_power``), the crawler surface speeds, and the joint speed limits (a servo
        reference moves at most joint_speed x period a tick)."""
        f = self._traction()
        track, flip = np.asarray(cmd.track, dtype=float), np.asarray(cmd.flip, dtype=float)
        arm = np.asarray(cmd.arm, dtype=float).reshape(-1)
        ctrl = self._ctrl_view
        if ctrl is not None:  # actuators 0..15 in order: one compiled pass, clipped in place
            _apply_command(track, f, float(self.cfg.robot.track_power), self._v, self.model.geom_surfacevel,
                           self._lin_ids, self._lin_side, self._lin_sign, self._rot_ids, self._rot_side,
                           self._rot_gain, flip, arm, ctrl, self._dq)
            return
        v, pmax = self._v, self.cfg.robot.track_power
        for i in (0, 1):
            vi, fi = float(track[i]), float(f[i])
            if fi > 1e-6 and abs(vi) * fi > pmax:
                vi = math.copysign(pmax / fi, vi)
            v[i] = vi
        self.apply_tracks(self._v)
        c = self._ctrl
        c[:4] = flip
        c[4:] = arm
        prev = self.data.ctrl[self.act]
        np.clip(c, prev - self._dq, prev + self._dq, out=c)
        self.data.ctrl[self.act] = c

    def sample(self) -> tuple[float, float, float, float, float]:
        """Ground-truth figures of the current contacts (evaluation only, on the stored rows):
        (static margin over the load-filtered support polygon at a quasi-static instant, else
        NaN; margin over every contact at any other instant, else NaN; quasi-static flag;
        tracks' share of the normal load; crawler drive power W).

        The support polygon holds the contacts of geoms that carried > SUPPORT_LOAD N within
        the last SUPPORT_MEMORY s (a grazing or bouncing contact is no support); quasi-static:
        chassis speed < QS_SPEED m/s, angular speed < QS_RATE rad/s and the normal ground load
        within QS_LOAD of the weight (no impact, no fling). The crawler power is that of this
        tick's traction (:meth:`_traction`, updated in :meth:`apply`).
        """
        d = self.data
        t = float(d.time)
        nan = float("nan")
        sel, rg, f, _ = self._contacts()
        power = self._track_power()
        if not len(sel):
            self._behind, self._rear_prev = None, (math.nan, False)  # no contact: nothing to be behind (tip-back)
            return nan, nan, 0.0, nan, power
        b = self._buf
        k = len(sel)
        total, on_crawlers, n_loaded = self._load_sums(k, f, rg)
        v = d.qvel[:6].tolist()  # Python floats: x ** 2 is numpy's scalar power (libm's pow) too
        quasi = (math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2) < QS_SPEED and
                 math.sqrt(v[3] ** 2 + v[4] ** 2 + v[5] ** 2) < QS_RATE and
                 abs(total - self._weight) < QS_LOAD * self._weight)
        pts = b[7][:k]  # the pass's ground points (x, y)
        cog = self._com_xy
        # the footprint: the ground points of the contacts that carried > SUPPORT_LOAD N on the
        # stored rows of the last SUPPORT_MEMORY s (a track resting on the ground touches it
        # along its length, but MuJoCo reports a few chattering points of it at any one instant)
        now = b[10][:n_loaded]  # the loaded contacts' ground points (a view: add copies it)
        self._footprint.add(t, now)
        self._tip_back(t, now, b[11][:n_loaded], cog)
        # the static margin at quasi-static instants, the margin over every contact at the others
        cx, cy = cog.tolist()  # stability_margin's arithmetic, one compiled call
        if quasi:
            foot = self._footprint.points()
            m_load, m_all = (signed_margin(foot, cx, cy) if len(foot) else nan), nan
        else:
            m_load, m_all = nan, signed_margin(pts, cx, cy)
        share = on_crawlers / total if total > 0 else nan
        return m_load, m_all, float(quasi), share, float(power)

    def _tip_back(self, t: float, loaded: np.ndarray, geoms: np.ndarray, cog: np.ndarray) -> None:
        """The tip-back rule (ground truth, on the stored rows; ``check`` ends the episode on the
        next tick once it holds): the COG's ground projection ``cog`` passes behind the rearmost
        contact of ``loaded`` (this row's contacts that carried > SUPPORT_LOAD N: the newest entry
        of the footprint, :meth:`sample`) along the heading (the chassis x axis, horizontal), and
        stays behind that contact (it moves < TIP_BACK_JUMP a row) with the nose up and rising
        for TIP_BACK_HOLD s, the contact on one of the robot's rear ends (``geoms``: the robot
        geom of each ``loaded`` contact; rear flippers, rear track pulleys, rear arm tips).

        The rear end: turning back about it, no crawler surface is left behind the COG to land
        on (step-400: the pivot is the rear flipper tips, and the robot lands on its lifted rear
        arms at 1.45 rad). A pivot under the track run is an edge the robot seesaws over (CCM on
        terrace2 backing off over the first edge, pitch 0: the track behind lands on the floor).

        The newest entry, not the whole SUPPORT_MEMORY: the footprint keeps world points, and
        while the robot crawls (0.1 m/s) a point loaded 0.5 s ago lies up to 5 cm behind the
        contact now, under nothing: on step-400 it put the COG behind the footprint 0.5 s (0.35
        rad) late. A contact off the ground for an instant is what the continuity and the hold
        are for.
        """
        if self._tipped is not None:
            return
        ax, ay, _ = self._ax.tolist()
        n = math.hypot(ax, ay)
        prev, self._rear_prev = self._rear_prev, (math.nan, False)
        if not len(loaded) or n < 1e-6:
            self._behind = None
            return
        pitch = self.attitude()[1]
        hx, hy = ax / n, ay / n
        cx, cy = cog.tolist()
        cs = cx * hx + cy * hy  # the COG along the heading (m)
        # the rearmost loaded contact (m); the first of equals, as np.argmin; on a rear end?
        rs, rear = _rearmost(loaded, geoms, self._rear_end, hx, hy)
        behind = rs > cs and bool(rear)
        self._rear_prev = (rs, behind)
        same = abs(rs - prev[0]) < TIP_BACK_JUMP  # the same contact as on the last row (NaN: no)
        run = self._behind
        if not (behind and same and pitch > 0.0):
            self._behind = None  # ahead, another contact (a jump), or nose down: no run
            return
        if run is None or pitch < run[1]:
            # a run starts where the COG passes the contact (on the last row it was ahead of it),
            # and starts over where the nose fell back
            self._behind = None if run is None and prev[1] else (t, pitch, cs, rs)
            return
        t0, p0, cs0, rs0 = run
        if t - t0 >= TIP_BACK_HOLD - 1e-9 and pitch > p0:
            self._tipped = {
                "t": t0, "pitch": p0, "behind_m": rs0 - cs0, "t_held": t, "pitch_held": pitch,
                "behind_held_m": rs - cs,
                "reason": (f"COG {100 * (rs0 - cs0):.1f} cm behind the rearmost loaded contact along the heading "
                           f"from t = {t0:.2f} s (COG at {cs0:.3f} m, contact at {rs0:.3f} m; pitch {p0:.2f} rad), "
                           f"nose still rising at t = {t:.2f} s (pitch {pitch:.2f} rad, {100 * (rs - cs):.1f} cm "
                           f"behind)")}

    def normal_load(self) -> tuple[float, float]:
        """The robot's normal ground load now and the crawlers' part of it (tracks and flippers)
        (N): the one track-share computation (the stored ``track_share`` column, the walking probe)."""
        return self._loads()[:2]

    def _loads(self) -> tuple[float, float, int]:
        """(:meth:`normal_load`, the number of contacts loaded > SUPPORT_LOAD N now); their ground
        points and robot geoms are then ``self._buf[10][:n]`` and ``self._buf[11][:n]``."""
        sel, rg, f, _ = self._contacts()
        k = len(sel)
        if not k:
            return 0.0, 0.0, 0
        return self._load_sums(k, f, rg)

    def _load_sums(self, k: int, f: np.ndarray, rg: np.ndarray) -> tuple[float, float, int]:
        """:meth:`_loads` of this instant's ``k`` > 0 contacts (their forces ``f``, robot geoms
        ``rg``, from :meth:`_contacts`)."""
        b = self._buf
        total, crawlers, c, m = _loads(k, f, b[3], b[7], rg, SUPPORT_LOAD, b[8], b[9], b[10], b[11])
        if k > PW_BLOCK:  # numpy's own pairwise sum of long sums
            total, crawlers = float(b[8][:k].sum()), float(b[9][:c].sum())
        return total, crawlers, m

    def _buffers(self, n: int) -> tuple[np.ndarray, ...]:
        """Room for ``n`` contacts: indices, robot geoms, forces, sides, frames, the frames' two
        tangential rows as (n, 3) views (what numpy's matmul then takes), ground points (x, y);
        then :func:`_loads`' normal forces, crawler forces, loaded points and their geoms."""
        fr = np.empty((n, 9))
        f3 = fr.reshape(-1, 3, 3)
        return (np.empty(n, np.int64), np.empty(n, np.int64), np.empty((n, 3)), np.empty(n, np.int64), fr,
                f3[:, 1], f3[:, 2], np.empty((n, 2)),
                np.empty(n), np.empty(n), np.empty((n, 2)), np.empty(n, np.int64))  # :func:`_loads`' room

    def _contacts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
        """The contacts now, computed once per instant (apply, the stored row and the last row
        share it): (indices of the robot-ground contacts into ``data.contact``, the robot geom of
        each, their (k, 3) contact-frame forces (N), bits of the arm tips touching anything)."""
        d = self.data
        if d.time == self._con_t:
            return self._con
        n = d.ncon
        if n > len(self._buf[0]):
            self._buf = self._buffers(2 * n)
        sel, rg, f, side, fr, _, _, xy = self._buf[:8]
        c = d.contact
        k, bits, dim3 = _contact_pass(n, c.geom, c.efc_address, c.dim, c.friction, c.frame, c.pos, d.efc_force,
                                      self.ground, self._tip_of, self._side_of, sel, rg, f, side, fr, xy)
        self._k = k
        sel, rg, f = sel[:k], rg[:k], f[:k]
        if k and not (self._pyramid and dim3):  # other cones or dimensions: MuJoCo's own decoding
            f6 = self._f6
            for a, j in enumerate(sel.tolist()):
                mujoco.mj_contactForce(self.model, d, j, f6)
                f[a] = f6[:3]
        self._con_t, self._con = d.time, (sel, rg, f, bits)
        return self._con

    def _traction(self) -> np.ndarray:
        """Each crawler side's traction force now (N): the tangential ground-contact force along
        the chassis x axis, summed over the side's track and flipper contacts. Kept for the power
        limit and the crawler power in ``energy``, so both follow the control period, not the
        logging period."""
        f = self._contacts()[2]
        k = self._k
        if not k:
            self._track_force[:] = 0.0
            return self._track_force
        # the frames' tangential rows projected on the chassis x axis by numpy's matmul, as (k, 3)
        # rows 9 apart (the BLAS kernel's rounding is part of the stored results)
        b, ax = self._buf, self._ax
        _side_traction(k, f, b[5][:k] @ ax, b[6][:k] @ ax, b[3], self._track_force)
        return self._track_force

    def _track_power(self) -> float:
        """The crawlers' drive power (W): this tick's traction force x the commanded track speed."""
        return _drive_power(self._track_force, self._v)

    def tip_contacts(self) -> int:
        """Bits (1 << arm index, arms LF, RF, LR, RR) of the arm tips touching anything now."""
        return self._contacts()[3]

    def row(self, obs: Observation, cmd: Command | None) -> tuple[float, ...]:
        s, lat, z = self._position()
        if cmd is None or self._row_k % self._row_stride == 0:
            self._sample, self._tips = self.sample(), float(self.tip_contacts())
            self._mech = self._mechanism(int(self._tips), cmd)
            tm = self._row_tmpl  # item by item (sampled rows only): cheaper than fancy indexing
            for c, v in zip(_SAMPLE_COLS, self._sample):
                tm[c] = v
            tm[_TIPS_COL] = self._tips
            for c, v in zip(_MECH_COLS, self._mech):
                tm[c] = v
        self._row_k += 1
        # Python floats (the same IEEE arithmetic as numpy scalars, without their per-item cost)
        mode = float(cmd.mode) if cmd is not None else np.nan
        mov = float(cmd.moving_arm) if cmd is not None else np.nan
        stage = float(cmd.stage) if cmd is not None else np.nan
        flat = obs._flat
        if flat is not None:  # the observation's one buffer: one compiled fill of a fresh row
            return _row_fill(self._row_tmpl, flat, s, lat, z, obs.roll, obs.pitch, mode, mov, stage)
        m_load, m_all, quasi, share, tpow = self._sample
        te, qa, qf = obs.tau_elbow.tolist(), obs.q_arm.tolist(), obs.q_flip.tolist()
        rf, rr = qa[1], qa[3]
        return (s, lat, z, obs.roll, obs.pitch, m_load, mode, mov, self._tips,
                0.5 * (qf[0] + qf[1]), 0.5 * (qf[2] + qf[3]),
                te[0], te[1], te[2], te[3],
                m_all, quasi, share, tpow, *rf, *rr, *self._mech, stage)

    def _mechanism(self, tips: int, cmd: Command | None) -> tuple[float, float, float, float, float, float]:
        """Mechanism figures on a stored row (evaluation only): (the sensed margin, the largest
        tip drift within the current support phases (m), the commanded crawler speed (m/s), the
        largest tip drift within the current support phases and controller mode (m), how deep the
        crawlers lie inside the supporting tips' polygon (m), the crawlers' own sensed margin (m)).

        The paper's Fig. 7 sentence ("there are at least three arms support robot at any time. The
        polygon constituted by support points were illustrated in blue lines in Fig. 7. Four
        crawler are included in the blue polygon, which means that robot in CLM always has bigger
        stability margin than CCM") has two readings, both stored. As the issue reads it, the
        polygon is the supporting tips' alone: the least signed distance of the four track pulley
        centres from the edge of the hull of the supporting tips (in contact, not the arm in
        transfer), in the horizontal plane; positive when every pulley is inside, NaN with fewer
        than three supporting tips. As its conclusion reads it, the support points are the tips
        and the crawlers together, whose polygon always contains the crawlers': the claim is then
        that the margin of that polygon (the sensed margin) is larger than the crawlers' own (the
        last figure: the four pulleys' hull about the same COG, what CCM's support would give in
        this pose); the hull of more points is never smaller, so the question is where the tips
        widen it on the COG's nearest side.

        The sensed margin is the one the robot can compute itself: the supporting tips (those
        whose foot switch, the tip-contact bit, is on) by forward kinematics plus the track
        footprint (the four track pulley centres), levelled by the IMU, about the COG of the
        robot's own mass model. Levelling by
        roll and pitch leaves only the yaw, which does not change distances, so its horizontal
        geometry is that of the same points' world x, y (the model's frames are the FK of the
        encoder angles). A support phase is a run of stored rows with the tip in contact and its
        arm not the one in transfer (``cmd.moving_arm``); the drift is the 3-D distance of the tip
        from where the run began. The per-mode drift restarts
        its runs where the controller's mode changes, so the walk's arm moving (eqs. 22-27, the
        footholds held) is read apart from the climb, where the paper does "not try to keep the
        position of the endpoint of arms consistent" (Fig. 9e).
        """
        mode = float(cmd.mode) if cmd is not None else self._mech_mode
        reset = mode != self._mech_mode
        if reset:
            self._mech_mode = mode
        # the arm in transfer is not a support, whatever it touches (a swing that grazes the
        # block's face and slides down it is a collision, not a foothold)
        moving = cmd.moving_arm if cmd is not None else -1
        sup = self._support  # the supporting arms: tip in contact, not the arm in transfer
        for i in range(len(ARMS)):
            sup[i] = tips >> i & 1 and i != moving
        cx, cy = self._com_xy.tolist()
        # the sensed margin, the crawlers' depth in the supporting tips' hull, their own margin
        sensed, inside, crawlers = _mech_geometry(self._geom_xpos, self._sensed_geoms[tips], self.tip_geoms, sup,
                                                  self._foot, cx, cy, self._tp)
        drift, drift_mode = _tip_drifts(tips, int(moving), reset, self._tp, *self._tip_start, *self._tip_start_mode)
        if cmd is not None:
            a, b = cmd.track.tolist()
            v = max(abs(a), abs(b))  # the crawlers' commands are finite (steer)
        else:
            v = float("nan")
        return sensed, drift, v, drift_mode, inside, crawlers

    def power(self, obs: Observation) -> float:
        """Servo power |tau qdot| summed, plus the crawlers' drive power (this tick's traction
        force x the commanded track speed)."""
        a, b = self._pa, self._pb
        # np.abs of both and the crawlers' power (:meth:`_track_power`), one call
        tp = _power_parts(self._act_force, self._act_vel, a, b, self._track_force, self._v)
        return float(np.dot(a, b)) + tp

    def metrics(self, log) -> dict[str, float]:
        """Extremes of attitude; the static margin (load-filtered polygon) at quasi-static
        instants and, apart, the dynamic events (runs of non-quasi-static rows whose margin over
        every contact is negative); the tracks' mean share of the normal load; the crawlers'
        part of the energy."""
        roll, pitch, s = log.column("roll"), log.column("pitch"), log.column("s")
        ip, ir = int(np.nanargmax(np.abs(pitch))), int(np.nanargmax(np.abs(roll)))
        # figures on the sampled rows only (every stored row), skipping the first second: the
        # robot settles and places its arms
        stride = self._row_stride
        k0 = min(int(round(1.0 / log.period)), len(s) - 1)
        idx = np.arange(k0 - k0 % stride + stride, len(s), stride)
        margin, m_all = log.column("margin")[idx], log.column("margin_all")[idx]
        quasi = log.column("quasi")[idx] > 0.5
        share = log.column("track_share")[idx]
        mq = margin[quasi & np.isfinite(margin)]
        dyn = (~quasi) & (m_all < 0)
        events = int(np.sum(dyn[1:] & ~dyn[:-1]) + (dyn[0] if len(dyn) else 0))
        tp = log.column("track_power")
        md = m_all[~quasi]
        mech = self._mechanism_metrics(log, idx, pitch, margin[quasi], share)
        return {**mech,
            "max_pitch": float(pitch[ip]), "max_roll": float(roll[ir]),
            "min_margin": float(mq.min()) if len(mq) else float("nan"),
            "quasi_frac": float(quasi.mean()) if len(quasi) else float("nan"),
            "dyn_events": float(events),
            "min_margin_dyn": float(np.nanmin(md)) if np.isfinite(md).any() else float("nan"),
            "track_share": float(np.nanmean(share)) if np.isfinite(share).any() else float("nan"),
            "progress": float(s[-1] - s[0]), "energy": log.energy,
            "track_energy": float(np.nansum(tp) * log.period),
        }

    def _mechanism_metrics(self, log, idx, pitch, m_static, share) -> dict[str, float]:
        """The climb-mechanism figures (issue 28) on the stored rows after the first second:
        ``max_pitch_rad`` (largest |pitch|), ``crawler_load_share_min`` (the crawlers' least share
        of the normal load over the climb rows: CLM climb/release, CCM press/push/flatten),
        ``crawler_load_share_phase_min`` (the least, over the climb phases, of the crawlers' mean
        share through the phase: a phase is a run of rows in one climb mode, CLM's climb and its
        release, CCM's press, push and flatten), ``crawler_load_share_lift``,
        ``crawler_load_share_rear_lift``, ``crawler_load_share_drive_on`` (the same least mean over
        the runs of one stage of CLM's climbs, :data:`.clm.STAGE_NAMES`: the nose lift of Fig. 9e,
        the rear lift of eq. 28, the drive on over the top; NaN where there is none),
        ``tip_slip_max_m`` (largest tip drift within one
        support phase), ``tip_slip_walk_max_m`` and
        ``tip_slip_climb_max_m`` (the same within one support phase and controller mode: CLM's walk,
        its climb and release; NaN where there is none), ``tracks_stopped_share``
        (share of CLM walking rows with the crawlers commanded < 1 mm/s; NaN for CCM, which has
        no walk), ``walk_speed_mean_mps`` (the crawlers' mean commanded speed over those rows: a
        walk slowed for its arms, ``clm.gait_pace``, reads here), ``margin_min_m`` (the static
        margin, as ``min_margin``),
        ``margin_sensed_min_m`` (least sensed margin, :meth:`_mechanism`) and
        ``crawlers_enclosed_share`` (share of CLM's walking rows with the crawlers inside the
        supporting tips' polygon, the paper's Fig. 7 as the issue reads it; NaN for CCM),
        ``walk_three_supports_share`` (share of CLM's walking rows with at least three supporting
        tips, Fig. 7's premise), ``margin_gain_walk_min_m`` (the least, over CLM's walking rows, of
        the sensed margin less the crawlers' own: what the supporting tips add, Fig. 7 as the paper
        concludes from it) and
        ``margin_gained_share`` (the share of walking rows where the tips add more than
        ``GAIN_EPS``)."""
        from terrabench.systems.octopus import ccm, clm

        nan = float("nan")
        mode = log.column("mode")[idx]
        climb_modes = {"clm": (clm.CLIMB, clm.RELEASE), "ccm": (ccm.PRESS, ccm.PUSH, ccm.FLATTEN)}.get(self.method, ())
        climb = np.isin(mode, climb_modes) & np.isfinite(share)
        slip, sensed, vcmd = (log.column(c)[idx] for c in ("tip_slip", "margin_sensed", "track_cmd"))
        depth = log.column("crawlers_in_tips")[idx]
        enclosed = np.nan_to_num(depth, nan=-1.0)
        gain = sensed - log.column("margin_crawlers")[idx]
        slip_mode = log.column("tip_slip_mode")[idx]
        walk = mode == clm.WALK if self.method == "clm" else np.zeros(len(mode), bool)
        in_climb = np.isin(mode, climb_modes)
        stage = log.column("climb_stage")[idx]
        fin = lambda a, f: float(f(a[np.isfinite(a)])) if np.isfinite(a).any() else nan  # noqa: E731
        return {
            "max_pitch_rad": fin(np.abs(pitch), np.max),
            "crawler_load_share_min": float(share[climb].min()) if climb.any() else nan,
            "crawler_load_share_phase_min": _least_run_mean(mode, in_climb, share),
            **{f"crawler_load_share_{clm.STAGE_NAMES[k]}": _least_run_mean(stage, stage == k, share)
               for k in (clm.LIFT, clm.REAR_LIFT, clm.DRIVE_ON)},
            "tip_slip_max_m": fin(slip, np.max),
            "tip_slip_walk_max_m": fin(slip_mode[walk], np.max),
            "tip_slip_climb_max_m": fin(slip_mode[in_climb], np.max),
            "tracks_stopped_share": float(np.mean(vcmd[walk] < 1e-3)) if walk.any() else nan,
            "walk_speed_mean_mps": fin(vcmd[walk], np.mean),
            "margin_min_m": fin(m_static, np.min),
            "margin_sensed_min_m": fin(sensed, np.min),
            # Fig. 7: the walking rows whose crawlers lie inside the supporting tips' polygon (a row
            # with fewer than three supporting tips does not count as inside)
            "crawlers_enclosed_share": float(np.mean(enclosed[walk] > 0.0)) if walk.any() else nan,
            # Fig. 7's premise, "at least three arms support robot at any time" (the depth is
            # NaN with fewer)
            "walk_three_supports_share": float(np.mean(np.isfinite(depth[walk]))) if walk.any() else nan,
            # Fig. 7's conclusion: the tips and crawlers' polygon gives a larger margin than the
            # crawlers' alone
            "margin_gain_walk_min_m": fin(gain[walk], np.min),
            "margin_gained_share": float(np.mean(gain[walk] > GAIN_EPS)) if walk.any() else nan,
        }

    def info(self) -> dict:
        out = {"kind": self.layout.kind, "edge": self.layout.edge, "top": self.layout.top}
        if self._tipped is not None:  # the tip-back event (:meth:`_tip_back`): times s, pitches rad, distances m
            out["tip_back"] = {k: round(v, 4) for k, v in self._tipped.items() if k != "reason"}
        return out
