"""The stored row's compiled pieces (task._row_fill, _mech_geometry, _power_parts, _rearmost) give
the bits of the Python formulas they replaced (contracts, no timing)."""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.octopus.robot import ARMS
from terrabench.systems.octopus.stability import least_depth, stability_margin
from terrabench.systems.octopus.task import COLUMNS, _mech_geometry, _power_parts, _rearmost, _row_fill


def _bits(a) -> np.ndarray:
    return np.asarray(a, float).view(np.uint64)


def test_row_fill_is_the_tuple_row(walking):
    """The compiled row (the observation's one buffer) is the tuple row of its fields, bit for
    bit, with a command and with NaN command columns."""
    task, _, _, obs, cmd = walking
    assert obs._flat is not None
    task._row_k = 1  # not a sampled row: the calls change nothing
    row = task.row(obs, cmd)
    assert isinstance(row, np.ndarray) and row.shape == (len(COLUMNS),)
    flat, obs._flat = obs._flat, None
    try:
        task._row_k = 1
        ref = task.row(obs, cmd)
    finally:
        obs._flat = flat
    assert isinstance(ref, tuple) and np.array_equal(_bits(row), _bits(ref))
    s, lat, z = task._position()
    empty = _row_fill(task._row_tmpl, flat, s, lat, z, obs.roll, obs.pitch, np.nan, np.nan, np.nan)
    want = _bits(ref).copy()
    want[[COLUMNS.index("mode"), COLUMNS.index("moving_arm"), COLUMNS.index("climb_stage")]] = _bits([np.nan] * 3)
    assert np.array_equal(_bits(empty), want)
    assert empty is not row  # a fresh row each call


def _mech_python(gx, sensed, tip_geoms, support, foot, cog):
    """The old formulas of OctopusTask._mechanism's geometry."""
    sup = [i for i in range(len(tip_geoms)) if support[i]]
    s_m = stability_margin(gx[sensed, :2], cog)
    inside = float("nan")
    if len(sup) >= 3:
        inside = least_depth(gx[tip_geoms[sup], :2], gx[foot, :2])
    return float(s_m), float(inside), float(stability_margin(gx[foot, :2], cog)), gx[tip_geoms].tolist()


def test_mech_geometry_is_the_python_formulas(walking):
    task = walking[0]
    rng = np.random.default_rng(5)
    tg, foot = task.tip_geoms, task._foot
    states = [np.array(task._geom_xpos)]
    for _ in range(300):
        gx = np.array(task._geom_xpos) + rng.normal(scale=rng.choice([0.001, 0.05, 0.3]), size=task._geom_xpos.shape)
        if rng.random() < 0.1:  # collinear / coincident tips
            gx[tg[1]] = gx[tg[0]]
            gx[tg[2], :2] = 0.5 * (gx[tg[0], :2] + gx[tg[3], :2])
        states.append(gx)
    tp = np.empty((len(ARMS), 3))
    for gx in states:
        cog = gx[task.chassis, :2] + rng.normal(scale=0.05, size=2)
        cx, cy = cog.tolist()
        for bits in range(1 << len(ARMS)):
            support = np.array([bits >> i & 1 for i in range(len(ARMS))], np.bool_)
            tips = int(rng.integers(1 << len(ARMS)))
            got = _mech_geometry(gx, task._sensed_geoms[tips], tg, support, foot, cx, cy, tp)
            want = _mech_python(gx, task._sensed_geoms[tips], tg, support, foot, cog)
            assert np.array_equal(_bits(got), _bits(want[:3]))
            assert tp.tolist() == want[3]


def test_power_parts_are_abs_and_the_track_power():
    rng = np.random.default_rng(6)
    for _ in range(500):
        f, v = rng.normal(size=16) * 100, rng.normal(size=16)
        f[rng.integers(16)], v[rng.integers(16)] = -0.0, np.nan
        fx, tv = rng.normal(size=2) * 300, rng.normal(size=2) * 0.2
        a, b = np.empty(16), np.empty(16)
        tp = _power_parts(f, v, a, b, fx, tv)
        assert np.array_equal(_bits(a), _bits(np.abs(f))) and np.array_equal(_bits(b), _bits(np.abs(v)))
        f0, f1 = fx.tolist()
        v0, v1 = tv.tolist()
        assert _bits(tp) == _bits(abs(f0 * v0) + abs(f1 * v1))
        assert _bits(tp) == _bits(abs(fx[0] * tv[0]) + abs(fx[1] * tv[1]))  # the numpy scalars' value


def test_rearmost_is_pythons_min_and_index():
    rng = np.random.default_rng(8)
    rear_end = rng.random(40) < 0.5
    for _ in range(3000):
        m = int(rng.integers(1, 12))
        pts = rng.normal(size=(m, 2)) if rng.random() < 0.7 else rng.integers(-1, 2, size=(m, 2)).astype(float)
        if rng.random() < 0.1:
            pts[rng.integers(m), rng.integers(2)] = np.nan
        geoms = rng.integers(0, 40, m)
        ang = rng.uniform(-math.pi, math.pi)
        hx, hy = math.cos(ang), math.sin(ang)
        along = [x * hx + y * hy for x, y in pts.tolist()]
        rs = min(along)
        k = along.index(rs)
        got_rs, got_rear = _rearmost(pts, geoms, rear_end, hx, hy)
        assert _bits(got_rs) == _bits(rs) and bool(got_rear) == bool(rear_end[geoms[k]])


def test_tip_drifts_are_the_python_loop():
    """_tip_drifts keeps the support phases' starts and gives the drifts of the old loop (lists,
    None out of contact, the distance on Python floats and Python's max), over random sequences of
    rows."""
    from terrabench.systems.octopus.task import _tip_drifts

    def tip_drift(p, q):  # the old loop's distance, on Python floats
        x, y, z = p[0] - q[0], p[1] - q[1], p[2] - q[2]
        return math.sqrt(x * x + y * y + z * z)

    rng = np.random.default_rng(9)
    n = len(ARMS)
    for _ in range(200):
        st_py, sm_py = [None] * n, [None] * n
        st = (np.zeros((n, 3)), np.zeros(n, np.bool_))
        sm = (np.zeros((n, 3)), np.zeros(n, np.bool_))
        for _ in range(30):
            tp = rng.normal(size=(n, 3))
            if rng.random() < 0.05:
                tp[rng.integers(n), rng.integers(3)] = np.nan
            tips, moving, reset = int(rng.integers(1 << n)), int(rng.integers(-1, n)), bool(rng.random() < 0.2)
            if reset:
                sm_py[:] = [None] * n
            tl = tp.tolist()
            drift = drift_mode = 0.0
            for i in range(n):
                if tips >> i & 1 and i != moving:
                    if st_py[i] is None:
                        st_py[i] = tl[i]
                    else:
                        drift = max(drift, tip_drift(tl[i], st_py[i]))
                    if sm_py[i] is None:
                        sm_py[i] = tl[i]
                    else:
                        drift_mode = max(drift_mode, tip_drift(tl[i], sm_py[i]))
                else:
                    st_py[i] = sm_py[i] = None
            got = _tip_drifts(tips, moving, reset, tp, *st, *sm)
            assert _bits(got[0]) == _bits(drift) and _bits(got[1]) == _bits(drift_mode)
