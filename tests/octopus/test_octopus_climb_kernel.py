"""The nose climb's compiled arm moving (clm._climb_supports) and the per-tick kinematics written into
the controller's buffers (arm_kinematics.tips_into, rotation_rc_into) give the bits of the Python
formulas they replaced (contracts, no timing)."""

import math

import numpy as np

from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus.clm import _climb_supports
from terrabench.systems.octopus.robot import ARMS
from terrabench.systems.octopus.scenarios import SYSTEM


def _climb_supports_python(tgt, lifted, tip_z, over, climb_hold, px, pz, cs, sn, lx, lz, up, pitch, h, h_rear,
                           h_est, pitch0, roll, cfg, ikc, rmin, mount, arm, rear_turn=False):
    """The loop of CLMController._climb_nose as it was written on Python floats (before the kernel):
    returns the arms lifted clear, in order; ``tgt`` and ``arm`` are updated in place."""
    cleared = []
    for i in range(4):
        if lifted[i]:
            continue
        t = tgt[i]
        tx, ty, tz = t.tolist()
        front = i < 2
        if front and not over:
            if climb_hold:
                tx = px + (tx - px) * cs + (tz - pz) * sn
            if pitch < cfg.climb_pitch and h < cfg.lift_margin:
                tz -= cfg.lift_dz
            tz = min(tz, tip_z[i] - cfg.climb_press)
            t[:] = tx, ty, tz
            arm[i] = ak.ik_f(tx, ty, tz, ikc[i])
            continue
        x0 = tx
        dx, dz = tx - px, tz - pz
        tx, tz = px + dx * cs + dz * sn - lx, pz - dx * sn + dz * cs - lz
        if not front and rear_turn:
            tx = tx + lx - (lx if up else 0.0)
        elif not front:
            tx = x0 - (lx if up else 0.0)
        if not front and over:
            if h_rear < h_est + cfg.lift_margin and pitch > pitch0:
                tz -= cfg.lift_dz
            tz += cfg.roll_level * roll * ty
        else:
            tz = min(tz + cfg.lift_dz, tip_z[i] - cfg.climb_press)
        t[:] = tx, ty, tz
        (mx, my), behind = mount[i].tolist(), not (front and not over)
        beyond = (behind and tx < rmin[i]) or math.hypot(tx - mx, ty - my) > cfg.reach_max
        beyond = beyond or (front and not cfg.front_support and tz >= tip_z[i] - cfg.climb_press - 1e-6)
        if beyond and (not front or over):
            cleared.append(i)
            continue
        arm[i] = ak.ik_f(tx, ty, tz, ikc[i])
    return cleared


def test_compiled_climb_supports_are_the_python_loop():
    """clm._climb_supports: the tip targets, the joints and the arms lifted clear of the Python loop,
    bit for bit, over random ticks (lifting fronts, pressing and lifting rears, roll levelling,
    out-of-range feet, front_support on and off, the rear tips turned or held)."""
    spec = SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1)[0]
    cfg = SYSTEM.load_config(spec.config)
    ctl = SYSTEM.make_controller(spec, cfg, None)
    ikc, rmin, mount = ctl._ikc, ctl._rmin, ctl._mount
    rng = np.random.default_rng(21)
    cleared_seen = 0
    for n in range(3000):
        c = cfg.clm if n % 2 else cfg.clm.__class__(**{**cfg.clm.__dict__, "front_support": False,
                                                         "climb_hold": n % 4 != 1})
        tgt = np.column_stack([mount[:, 0] + rng.normal(0, 0.5, 4), mount[:, 1] + rng.normal(0, 0.4, 4),
                               rng.normal(-0.3, 0.2, 4)])
        tip_r = tgt + rng.normal(0, 0.02, (4, 3))
        lifted = rng.random(4) < 0.2
        over, up = bool(rng.random() < 0.5), bool(rng.random() < 0.5)
        px, pz = float(rng.normal(-0.3, 0.1)), float(rng.normal(-0.1, 0.05))
        dth = float(rng.normal(0, 0.01))
        cs, sn = math.cos(dth), math.sin(dth)
        pitch, pitch0, roll = (float(v) for v in rng.normal(0.3, 0.3, 3))
        a = pitch0 - pitch
        lx, lz = 0.06 * 0.02 * math.cos(a), 0.06 * 0.02 * math.sin(a)
        h, h_rear, h_est = (float(v) for v in rng.normal(0.0, 0.05, 3))
        rear_turn = n % 3 == 0
        want_tgt, want_arm = tgt.copy(), np.zeros((4, 3))
        want = _climb_supports_python(want_tgt, lifted, tip_r[:, 2].tolist(), over, c.climb_hold, px, pz, cs, sn,
                                      lx, lz, up, pitch, h, h_rear, h_est, pitch0, roll, c, ikc, rmin, mount, want_arm,
                                      rear_turn)
        arm = np.zeros((4, 3))
        got = _climb_supports(tgt, lifted, tip_r, over, c.climb_hold, px, pz, cs, sn, lx, lz, lx if up else 0.0,
                              pitch < c.climb_pitch and h < c.lift_margin,
                              h_rear < h_est + c.lift_margin and pitch > pitch0, c.roll_level * roll, c.lift_dz,
                              c.climb_press, c.front_support, ikc, rmin, mount, c.reach_max, arm, rear_turn)
        assert [i for i in range(4) if got >> i & 1] == want
        assert tgt.tobytes() == want_tgt.tobytes() and arm.tobytes() == want_arm.tobytes()
        cleared_seen += len(want)
    assert cleared_seen > 200  # the lift-clear branch is exercised


def test_kinematics_into_buffers_are_the_formulas():
    """tips_into fills the buffer with tips' (fk_all's) bits; rotation_rc_into (rotation_rc) is the
    formula on Python's math."""
    rb = SYSTEM.load_config(SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1)[0].config).robot
    consts = ak.fk_constants(rb)
    rng = np.random.default_rng(22)
    out, rot = np.empty((4, 3)), np.empty((3, 3))
    for q in rng.uniform(-2.0, 2.0, (500, 4, 3)):
        ak.tips_into(q, ak.SIGNS, consts, out)
        assert out.tobytes() == ak.tips(q, ak.SIGNS, consts).tobytes()
        assert [out[i].tolist() for i in range(4)] == [ak.fk(q[i], rb, k).tolist() for i, k in enumerate(ARMS)]
    for roll, pitch in rng.normal(0, 0.6, (5000, 2)).tolist() + [(0.0, 0.0), (-0.0, -0.0)]:
        cr, sr = math.cos(roll), math.sin(roll)
        cp, sp = math.cos(-pitch), math.sin(-pitch)
        want = np.array([[cp, sp * sr, sp * cr], [0.0, cr, -sr], [-sp, cp * sr, cp * cr]])
        ak.rotation_rc_into(roll, pitch, rot)
        assert rot.tobytes() == want.tobytes() and ak.rotation_rc(roll, pitch).tobytes() == want.tobytes()
