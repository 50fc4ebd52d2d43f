"""OCTOPUS per-tick work, compiled: the contact pass, the traction, the command's limits and the
support hull give MuJoCo's own numbers and the numpy formulas they replaced (contracts, no timing)."""

import math

import mujoco
import numpy as np
import pytest

from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus.robot import ARMS, FLIPPERS, Names
from terrabench.systems.octopus.scenarios import SYSTEM
from terrabench.systems.octopus.stability import convex_hull, stability_margin


def test_contact_pass_is_mujocos_contact_force(walking):
    task, _, ep, _, _ = walking
    m, d = ep.model, ep.data
    task._con_t = -1.0  # a fresh pass
    sel, rg, f, bits = task._contacts()
    # the robot-ground contacts, in contact order, with the robot's geom of each
    want = [j for j in range(d.ncon) if task.ground[d.contact.geom[j, 0]] != task.ground[d.contact.geom[j, 1]]]
    assert sel.tolist() == want and len(want) >= 4
    f6 = np.zeros(6)
    for a, j in enumerate(want):
        g1, g2 = d.contact.geom[j]
        assert rg[a] == (g2 if task.ground[g1] else g1)
        mujoco.mj_contactForce(m, d, j, f6)
        np.testing.assert_allclose(f[a], f6[:3], rtol=1e-12, atol=1e-9)
    # the tip bits: every arm tip touching anything
    tips = [m.geom(Names.tip(k)).id for k in ARMS]
    ref = sum(1 << i for i, g in enumerate(tips) if (d.contact.geom[:d.ncon] == g).any())
    assert bits == ref == task.tip_contacts() and ref != 0
    # computed once per instant: the same result until the physics steps
    assert task._contacts() is task._contacts()


def test_normal_load_is_the_weight_and_the_crawlers_share(walking):
    task, _, ep, _, _ = walking
    m, d = ep.model, ep.data
    total, crawlers = task.normal_load()
    crawler_geoms = {m.geom(n).id for s in Names.SIDES for n in Names.track_geoms(s)}
    crawler_geoms |= {m.geom(n).id for k in FLIPPERS for n in Names.flipper_geoms(k)}
    f6, tot, on = np.zeros(6), 0.0, 0.0
    for j in range(d.ncon):
        g1, g2 = d.contact.geom[j]
        if task.ground[g1] == task.ground[g2]:
            continue
        mujoco.mj_contactForce(m, d, j, f6)
        tot += f6[0]
        on += f6[0] if (g1 in crawler_geoms or g2 in crawler_geoms) else 0.0
    assert total == pytest.approx(tot, rel=1e-12) and crawlers == pytest.approx(on, rel=1e-12)
    # physics: standing on flat ground, the normal load carries the weight (within the impacts
    # of walking) and the crawlers carry part of it
    assert 0.5 * task._weight < total < 1.5 * task._weight
    assert 0.0 < crawlers < total


def test_traction_is_the_numpy_formula_bitwise(walking):
    task, _, ep, _, _ = walking
    d = ep.data
    got = task._traction().copy()
    sel, rg, f, _ = task._contacts()
    fr = d.contact.frame[sel].reshape(-1, 3, 3)
    ax = d.xmat[task.chassis].reshape(3, 3)[:, 0]
    tx = np.abs(f[:, 1] * (fr[:, 1] @ ax) + f[:, 2] * (fr[:, 2] @ ax))
    sd = task._side_of[rg]
    ref = np.bincount(sd[sd >= 0], weights=tx[sd >= 0], minlength=2)
    assert np.array_equal(got, ref)
    assert (got > 0).all()  # both crawlers drive on the ground


def test_compiled_apply_is_the_numpy_apply_bitwise(octopus_episode):
    """The compiled command pass equals the plain numpy one (kept for actuator orders other than
    the builder's) on commands beyond the speed limits, with a power limit that binds."""
    runs = []
    for compiled in (True, False):
        task, ctl, ep, obs, cmd = octopus_episode(1.0, overrides={"robot.track_power": 2.0})
        if not compiled:
            task._ctrl_view = None
        rng = np.random.default_rng(3)
        out, cut = [], 0
        for _ in range(20):
            c = ctl(obs)
            c.track[:] = rng.uniform(-0.3, 0.3, 2)
            c.flip[:] += rng.uniform(-1, 1, 4)
            c.arm[:] += rng.uniform(-1, 1, (4, 3))
            obs, stop = ep.step(c)  # task.apply(c), then the physics (which leaves ctrl as set)
            out.append(np.concatenate([ep.data.ctrl, ep.model.geom_surfacevel.ravel(), task._v]))
            cut += int((np.abs(task._v) < np.abs(c.track) - 1e-9).any())
        runs.append(np.array(out))
        # the joint speed limit: no servo reference moved more than joint_speed x period a tick
        steps = np.abs(np.diff(runs[-1][:, :16], axis=0))
        assert (steps <= task._dq * (1 + 1e-12) + 1e-15).all()
        # the power limit binds (speeds cut) and holds: |v| x traction <= 2 W on both sides
        assert cut > 0
        assert (np.abs(task._v) * task._track_force <= 2.0 + 1e-9).all()
    assert np.array_equal(runs[0], runs[1])


def test_hull_and_margin():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [1, 0.5], [0, 0]], float)
    h = convex_hull(sq)
    assert h.tolist() == [[0, 0], [1, 0], [1, 1], [0, 1]]  # ccw, interior and collinear dropped
    assert stability_margin(sq, np.array([0.5, 0.4])) == pytest.approx(0.4)
    assert stability_margin(sq, np.array([1.5, 0.5])) == pytest.approx(-0.5)
    assert stability_margin(sq[:2], np.array([0.5, 0.5])) == pytest.approx(-0.5)  # a segment: never > 0
    assert math.isnan(stability_margin(np.empty((0, 2)), np.zeros(2)))
    # random sets: every point inside or on the hull, the hull convex and counter-clockwise
    rng = np.random.default_rng(0)
    for _ in range(200):
        p = rng.normal(size=(int(rng.integers(3, 40)), 2))
        h = convex_hull(p)
        e = np.roll(h, -1, axis=0) - h
        cross = e[:, 0] * np.roll(e, -1, axis=0)[:, 1] - e[:, 1] * np.roll(e, -1, axis=0)[:, 0]
        assert (cross > 0).all()
        side = e[None, :, 0] * (p[:, None, 1] - h[None, :, 1]) - e[None, :, 1] * (p[:, None, 0] - h[None, :, 0])
        assert (side >= -1e-12).all()
        assert {tuple(q) for q in h.tolist()} <= {tuple(q) for q in p.tolist()}


def test_one_forward_kinematics():
    """fk (one arm) and fk_all (the controller's per-tick pass) are one formula, bit for bit."""
    cfg = SYSTEM.load_config(SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1)[0].config).robot
    rng = np.random.default_rng(1)
    for _ in range(500):
        q = rng.uniform(-1.5, 1.5, (4, 3))
        assert np.array_equal(ak.fk_all(q, cfg), np.array([ak.fk(q[i], cfg, k) for i, k in enumerate(ARMS)]))
    # geometry: arm straight out sideways and level (swing 0, boom 0, elbow 0) reaches l1 + l2
    tip = ak.fk(np.zeros(3), cfg, "RF")
    mx, my, mz = cfg.arm_mount
    assert tip.tolist() == pytest.approx([mx, -(my + cfg.l1 + cfg.l2), mz + 0.04])


def _margin_python(pts: np.ndarray, c: np.ndarray) -> float:
    """The margin as it was written on Python floats (the reference the compiled one keeps)."""
    hull = convex_hull(pts).tolist()
    cx, cy = float(c[0]), float(c[1])

    def seg(a, b):
        ex, ey = b[0] - a[0], b[1] - a[1]
        den = ex * ex + ey * ey
        u = 0.0 if den < 1e-18 else min(1.0, max(0.0, ((cx - a[0]) * ex + (cy - a[1]) * ey) / den))
        return math.hypot(cx - a[0] - u * ex, cy - a[1] - u * ey)
    if not hull:
        return math.nan
    if len(hull) == 1:
        return -math.hypot(cx - hull[0][0], cy - hull[0][1])
    if len(hull) == 2:
        return -seg(hull[0], hull[1])
    d, inside = math.inf, True
    for a, b in zip(hull, hull[1:] + hull[:1]):
        d = min(d, seg(a, b))
        if (b[0] - a[0]) * (cy - a[1]) - (b[1] - a[1]) * (cx - a[0]) < 0:
            inside = False
    return d if inside else -d


def test_compiled_margin_is_the_python_margin_bitwise():
    """The compiled margin takes Python's hypot of the nearest edges only: the same bits as the
    all-Python margin, also where the COG is nearest a hull vertex (two edges, two roundings),
    on an edge, on rounded (duplicate, collinear) and tiny sets."""
    rng = np.random.default_rng(3)
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    cases = [(sq, np.array(c, float)) for c in ([0, 0], [1, 1], [0.5, 0], [2, 2], [0.5, 0.5], [1.5, 0.5])]
    # COGs outside near a vertex where the two edges' offsets round apart: the same squared
    # distance but hypots an ulp apart (the first), and a strictly smaller squared distance on the
    # edge whose hypot is the larger (the others; found by search): a margin that took the hypot
    # of the least squared distance alone fails here
    cases += [(np.array(p), np.array(c)) for p, c in (
        ([[0.5026828498748657, 0.989713033285805], [-0.1642945926252907, -1.0743648582284346],
          [0.8730421526217066, -1.2803939447145731]], [1.1835510793917559, -2.405464531501869]),
        ([[0.07538353749054373, -0.46568513805347683], [-0.6350006077789646, 1.4205826530958714],
          [0.20737640374994265, -1.0796009660974024]], [-0.6291704802820655, -1.4277316669736013]),
        ([[0.4431326461987734, 0.12408880336078919], [-0.3448791633186918, -0.8786591636129535],
          [0.8922948570521654, -0.39280802735410586]], [-0.5502952995527672, -0.9851676477819332]),
        ([[-0.7605604067216812, -1.4915671494867404], [0.9124352756987358, 0.11889433026950108],
          [-0.1185673226253151, -0.005134089996955464]], [1.1035223843336275, 0.5478638720124575]))]
    for _ in range(3000):  # triangles, the COG near a vertex
        p = rng.normal(size=(3, 2))
        cases.append((p, p[rng.integers(3)] + rng.normal(size=2) * 0.5))
    for _ in range(3000):
        n = int(rng.integers(1, 30))
        p = rng.normal(size=(n, 2)) * rng.choice([1e-3, 1.0, 10.0])
        if rng.random() < 0.3:
            p = np.round(p, 1)
        c = p[rng.integers(n)] + rng.normal(size=2) * rng.choice([1e-9, 1.0])
        cases.append((p, c))
    for p, c in cases:
        want, got = _margin_python(p, c), stability_margin(p, c)
        same = want == got and math.copysign(1, want) == math.copysign(1, got)
        assert (math.isnan(want) and math.isnan(got)) or same


def test_python_float_shortcuts_are_numpys_values():
    """The per-tick shortcuts on Python floats give numpy's bits: the tip drift (np.linalg.norm;
    compiled in _phase_drift), the IK on per-arm constants (the formula on the config), the compiled arm lead
    (np.minimum(np.maximum()))."""
    from terrabench.systems.octopus.clm import _within
    from terrabench.systems.octopus.task import _phase_drift

    cfg = SYSTEM.load_config(SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1)[0].config).robot
    rng = np.random.default_rng(4)
    for _ in range(2000):
        a, b = rng.normal(size=3) * 10.0 ** rng.uniform(-4, 0), rng.normal(size=3) * 0.1
        on = np.ones(1, np.bool_)  # a support phase that began at b
        assert _phase_drift(a.reshape(1, 3), b.reshape(1, 3).copy(), on, 0) == float(np.linalg.norm(a - b))
    for k in ARMS:
        c = ak.ik_constants(cfg, k)
        for p in rng.uniform(-1.2, 1.2, (500, 3)):
            px, py, pz = p.tolist()
            sx, sy = {"LF": (1, 1), "RF": (1, -1), "LR": (-1, 1), "RR": (-1, -1)}[k]
            mx, my, mz = cfg.arm_mount
            dx, dy = px - sx * mx, sy * py - my
            r, h = math.hypot(dx, dy), -(pz - mz - 0.04)
            d = min(math.hypot(r, h), cfg.l1 + cfg.l2 - 1e-6)
            el = math.acos(max(-1.0, min(1.0, (d * d - cfg.l1 * cfg.l1 - cfg.l2 * cfg.l2) / (2 * cfg.l1 * cfg.l2))))
            bm = math.atan2(h, r) - math.atan2(cfg.l2 * math.sin(el), cfg.l1 + cfg.l2 * math.cos(el))
            assert ak.ik_f(px, py, pz, c) == (math.atan2(dx, dy), bm, el)
    for _ in range(500):
        arm = rng.normal(size=(4, 3))
        q = arm + rng.normal(size=(4, 3)) * 0.3
        if rng.random() < 0.2:
            arm[rng.integers(4), rng.integers(3)] = np.nan
        want = np.minimum(np.maximum(arm, q - 0.15), q + 0.15)
        _within(arm, q, 0.15)
        assert np.array_equal(arm, want, equal_nan=True)


def test_footprint_window_is_the_stacked_rows():
    """The footprint's one buffer holds what the last SUPPORT_MEMORY s of rows stacked would:
    the same points in the same order, across expiry, empty rows, gaps and growth."""
    import collections

    from terrabench.systems.octopus.stability import Footprint

    rng = np.random.default_rng(5)
    for _ in range(50):
        fp, hist, t = Footprint(0.5, capacity=int(rng.integers(1, 40))), collections.deque(), 0.0
        for _ in range(150):
            t += float(rng.choice([0.02, 0.1, 0.1, 0.3, 0.6]))
            pts = rng.normal(size=(int(rng.integers(0, 30)), 2))
            fp.add(t, pts)
            hist.append((t, pts.copy()))
            while hist and t - hist[0][0] > 0.5 + 1e-9:
                hist.popleft()
            assert np.array_equal(fp.points(), np.vstack([p for _, p in hist]))


def test_compiled_loads_are_numpys_sums_and_masks():
    """The stored row's normal loads (``task._loads``): numpy's ``fn.sum()`` and
    ``fn[side >= 0].sum()`` bit for bit (numpy's pairwise order, up to PW_BLOCK values; numpy's own
    sum beyond), and the loaded contacts' points and geoms as the boolean masks pick them."""
    from terrabench.systems.octopus.task import PW_BLOCK, SUPPORT_LOAD, _loads, _pairwise_sum

    rng = np.random.default_rng(6)
    for n in list(range(0, 40)) + [63, 64, 65, 127, 128]:
        for _ in range(200):
            a = rng.normal(size=n) * 10.0 ** rng.uniform(-3, 3, n)
            for x in (a, np.abs(a), a[::-1].copy()):
                assert _pairwise_sum(x, n) == float(x.sum())
    assert math.copysign(1.0, _pairwise_sum(np.array([-0.0]), 1)) == math.copysign(1.0, float(np.array([-0.0]).sum()))
    for _ in range(3000):
        k = int(rng.integers(1, PW_BLOCK + 40))
        f = np.abs(rng.normal(size=(k, 3))) * 10.0 ** rng.uniform(-1, 3, (k, 1))
        side = rng.integers(-1, 2, k)
        xy, rg = rng.normal(size=(k, 2)), rng.integers(0, 50, k)
        fn, on, now, now_g = np.empty(k), np.empty(k), np.empty((k, 2)), np.empty(k, np.int64)
        total, crawl, c, m = _loads(k, f, side, xy, rg, SUPPORT_LOAD, fn, on, now, now_g)
        col = f[:, 0]
        if k > PW_BLOCK:  # the task sums these with numpy
            assert math.isnan(total) and math.isnan(crawl)
            total, crawl = float(fn[:k].sum()), float(on[:c].sum())
        assert total == float(col.sum()) and crawl == float(col[side >= 0].sum())
        loaded = col > SUPPORT_LOAD
        assert m == loaded.sum() and np.array_equal(now[:m], xy[loaded]) and np.array_equal(now_g[:m], rg[loaded])


def test_per_tick_float_shortcuts_are_the_old_formulas(walking):
    """``roll_pitch_f`` on ``tolist()`` floats is ``roll_pitch``; the compiled |x|, |y| are
    np.abs's; the stored row read from the observation's one buffer is the row read from its
    fields; the task's loads are the old numpy formulas on a live state."""
    from terrabench.sim.checks import roll_pitch, roll_pitch_f
    from terrabench.systems.octopus.task import _power_parts

    rng = np.random.default_rng(7)
    for q in rng.normal(size=(2000, 4)):
        q /= np.linalg.norm(q)
        assert roll_pitch_f(*q.tolist()) == roll_pitch(q)
    x, y = rng.normal(size=16) * 100, rng.normal(size=16)
    x[3], y[5] = -0.0, np.nan
    ax, ay = np.empty(16), np.empty(16)
    _power_parts(x, y, ax, ay, np.zeros(2), np.zeros(2))
    assert np.array_equal(ax, np.abs(x)) and np.array_equal(ay, np.abs(y), equal_nan=True)
    task, ctl, ep, obs, cmd = walking
    assert obs._flat is not None
    task._row_k = 1  # not a sampled row: the two calls change nothing
    row = task.row(obs, cmd)
    flat, obs._flat = obs._flat, None
    try:
        task._row_k = 1
        assert np.array_equal(np.array(task.row(obs, cmd)), np.array(row), equal_nan=True)
    finally:
        obs._flat = flat
    sel, rg, f, _ = task._contacts()
    fn = f[:, 0]
    assert task.normal_load() == (float(fn.sum()), float(fn[task._buf[3][:len(sel)] >= 0].sum()))


def test_compiled_arm_moving_and_pace_are_the_python_formulas():
    """The walk's compiled passes (clm._hold: eqs. 22-27 for the supports; clm._pace_bound: the
    paced crawler speed) give the bits of their formulas on Python floats (Python's hypot, ``**``
    and min/max), beyond-range arms and landing casters included."""
    from terrabench.systems.octopus.clm import _hold, _pace_bound

    cfg = SYSTEM.load_config(SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1)[0].config)
    rb, cc = cfg.robot, cfg.clm
    mx, my, _ = rb.arm_mount
    signs = [{"LF": (1, 1), "RF": (1, -1), "LR": (-1, 1), "RR": (-1, -1)}[k] for k in ARMS]
    rmin = np.array([cc.reach_min[0 if sx > 0 else 1] for sx, _ in signs])
    mount = np.array([[sx * mx, sy * my] for sx, sy in signs])
    ikc = np.array([ak.ik_constants(rb, k) for k in ARMS])
    rmax = cc.reach_max
    rng = np.random.default_rng(11)
    beyond_seen = 0
    for _ in range(3000):
        foot = np.column_stack([mount + rng.normal(0, 0.3, (4, 2)), rng.normal(-0.3, 0.1, 4)])
        tip = rng.normal(0, 0.3, (4, 3))
        on, shift, landing = (int(v) for v in rng.integers(0, 16, 3))
        dx, press = float(rng.uniform(0, 0.01)), float(cc.press)
        want_foot, want_arm, want_bits = foot.tolist(), np.zeros((4, 3)), 0
        for i in range(4):
            if not on >> i & 1:
                continue
            f = want_foot[i]
            beyond = f[0] < rmin[i] or math.hypot(f[0] - signs[i][0] * mx, f[1] - signs[i][1] * my) > rmax
            want_bits |= beyond << i
            if shift >> i & 1 and not (landing >> i & 1 and beyond):
                f[0] -= dx
            f[2] = tip[i, 2] - press
            want_arm[i] = ak.ik_f(f[0], f[1], f[2], ikc[i])
        arm = np.zeros((4, 3))
        got = _hold(foot, on, shift, landing, dx, tip, press, ikc, rmin, mount, rmax, arm)
        assert got == want_bits and foot.tolist() == want_foot and np.array_equal(arm, want_arm)
        beyond_seen += bin(got).count("1")
        # the pace: the travels left, sorted, over the waits
        rem, period = float(rng.uniform(0, 2)), float(rng.uniform(0.5, 3))
        left = []
        for i in range(4):
            if on >> i & 1:
                fx, fy, _ = foot[i].tolist()
                sx, sy = signs[i]
                dy2 = (fy - sy * my) ** 2
                left.append(0.0 if dy2 >= rmax * rmax else
                            max(0.0, min(fx - rmin[i], fx - sx * mx + math.sqrt(rmax * rmax - dy2))))
        v = math.inf
        for n, d in enumerate(sorted(left)):
            if rem + n * period > 0.0:
                v = min(v, d / (rem + n * period))
        assert _pace_bound(foot, on, rem, period, rmin, mount, rmax, 2.0) == v
    assert beyond_seen > 100  # the beyond-range branch is exercised


def test_travel_left_squares_with_libms_pow():
    """clm._travel_left's square is Python's float ``**`` (libm's pow), not x * x, which LLVM would
    put in for a constant exponent: the exponent comes in at run time. Checked on values where the
    two squares differ."""
    from terrabench.systems.octopus.clm import _travel_left

    rng = np.random.default_rng(12)
    rmax, my, fx = 0.55, 0.17, 0.3
    found = 0
    for fy in rng.uniform(-0.7, 0.7, 400_000).tolist():
        if (fy - my) ** 2 == (fy - my) * (fy - my):
            continue
        found += 1
        want = max(0.0, min(fx - 0.05, fx - 0.2 + math.sqrt(rmax * rmax - (fy - my) ** 2))) \
            if (fy - my) ** 2 < rmax * rmax else 0.0
        assert _travel_left(fx, fy, 0.05, 0.2, my, rmax, 2.0) == want
    assert found > 20
