"""The per-period fast paths equal their reference forms bitwise (the speed work moved no result)."""

import numpy as np
from srwmr_reference import (
    build_qp_reference,
    geometry_pair_reference,
    period_ratios_reference,
    refresh_reference,
    row_reference,
)

from terrabench.sim.episode import Episode
from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.ik import IKLimits, IKState, SaturatedIK, _qp_kernel, build_qp
from terrabench.systems.srwmr.kinematics import (
    geometry,
    geometry_pair,
    hinge_rise,
    inverse_kinematics,
    inverse_kinematics_reference,
    period_geometry,
)
from terrabench.systems.srwmr.robot import RobotConfig
from terrabench.systems.srwmr.scenarios import SYSTEM
from terrabench.systems.srwmr.task import COLUMNS

CFG = RobotConfig()


def _begun(method: str, instance: str):
    """(task, controller, episode, first observation) of ``method`` on ``instance``, seed 0, a 1 s
    limit: an episode a test steps itself."""
    _, task, ctl = SYSTEM.trial_parts(SYSTEM.trial_spec(method, instance, 0, {"protocol.timeout": 1.0}))
    ep = Episode(task)
    obs, _ = ep.begin()
    return task, ctl, ep, obs


def test_geometry_pair_is_geometry_twice_bitwise():
    rng = np.random.default_rng(1)
    for _ in range(500):
        d, mu = rng.uniform(-0.45, 1.15, 2), rng.uniform(-1.75, 1.75, 6)
        (p0, j0), (p, j) = geometry_pair(CFG, d, mu)
        (q0, k0), (q, k) = geometry(CFG, d), geometry(CFG, d, mu)
        assert all(np.array_equal(a, b) for a, b in ((p0, q0), (j0, k0), (p, q), (j, k)))


def test_compiled_period_geometry_equals_the_python_form_bitwise():
    rng = np.random.default_rng(11)
    for _ in range(500):
        d, mu = rng.uniform(-0.45, 1.15, 2), rng.uniform(-1.75, 1.75, 6)
        (p0, j0), (p, j), dz, wb = period_geometry(CFG, d, mu)
        (q0, k0), (q, k) = geometry_pair_reference(CFG, d, mu)
        assert all(np.array_equal(a, b) for a, b in ((p0, q0), (j0, k0), (p, q), (j, k)))
        assert np.array_equal(dz, hinge_rise(k0))
        assert np.array_equal(wb, [q0[0, 0] - q0[2, 0], q0[1, 0] - q0[3, 0]])


def test_compiled_inverse_kinematics_equals_the_numpy_form_bitwise():
    """Also across +-90 deg (the fold and its hysteresis), still wheels and lifted ones."""
    rng = np.random.default_rng(12)
    n_fold = 0
    for i in range(2000):
        d, mu = rng.uniform(-0.45, 1.15, 2), rng.uniform(-1.75, 1.75, 6)
        geom = period_geometry(CFG, d, mu)[1]
        u = rng.uniform(-0.05, 0.05, 5) * (rng.uniform(size=5) < 0.7)
        mu_prev = mu if i % 2 else rng.uniform(-0.3, 0.3, 6)
        lifted = (i % 6,) if i % 5 == 0 else ()
        ref = inverse_kinematics_reference(CFG, u, d, mu_prev=mu_prev, lifted=lifted, geom=geom)
        fast = inverse_kinematics(CFG, u, d, mu_prev=mu_prev, lifted=lifted, geom=geom)
        assert np.array_equal(ref[0], fast[0]) and np.array_equal(ref[1], fast[1])
        n_fold += bool((np.abs(ref[0]) > np.pi / 2).any())
    assert n_fold > 50  # the fold branch was exercised


def test_compiled_qp_rows_equal_the_row_by_row_reference_bitwise_and_place_u_nom_alike():
    rng = np.random.default_rng(13)
    lim, sc = IKLimits(), mc.Scales()
    ik = SaturatedIK(CFG, lim, sc, 0.01)
    seen = set()
    for i in range(1500):
        d, u = rng.uniform(-0.5, 1.2, 2), rng.uniform(-0.05, 0.05, 5)
        u_nom = u + rng.normal(0.0, 0.002, 5) * (rng.uniform(size=5) < 0.5)
        mode = mc.MODES[i % len(mc.MODES)]
        kappa = mc.qp_thresholds(mode) if i % 3 == 0 else mc.thresholds(mode)
        (_, J), _, dz, wb = period_geometry(CFG, d, np.zeros(6))
        ref = build_qp_reference(CFG, IKState(d, u), kappa, sc, lim, 0.01, J, wb)
        fast = (np.full((16, 5), np.nan), np.full(16, np.nan), np.full(5, np.nan), np.full(5, np.nan))
        where = _qp_kernel(J, d, wb, dz, kappa, u, u_nom, ik._consts, *fast)
        assert all(np.array_equal(a, b) for a, b in zip(ref, fast))
        G, h, lb, ub = ref
        inside = (G @ u_nom <= h + 1e-12).all() and (u_nom >= lb).all() and (u_nom <= ub).all()
        assert where == (0 if (lb > ub + 1e-12).any() else 1 if inside else 2)
        seen.add(where)
    assert seen >= {1, 2}


def test_compiled_ratios_equal_the_numpy_form_bitwise():
    rng = np.random.default_rng(14)
    for i in range(2000):
        sc = mc.Scales(w_fmr_centre="midrange" if i % 3 == 0 else "mean")
        d, mu = rng.uniform(-0.45, 1.15, 2), rng.uniform(-1.6, 1.6, 6)
        (_, J), _, dz, wb = period_geometry(CFG, d, np.zeros(6))
        u = rng.uniform(-0.05, 0.05, 5) * (rng.uniform(size=5) < 0.6)
        u_prev = rng.uniform(-0.05, 0.05, 5) * (rng.uniform(size=5) < 0.6)
        dd = rng.uniform(-1e-3, 1e-3, 2) * (rng.uniform(size=2) < 0.7)
        load, rim = rng.uniform(0.0, 900.0, 6), (rng.uniform(-0.05, 0.05, 6) if i % 4 else None)
        args = (CFG, sc, u, u_prev, J, dz, wb, d, dd, mu, load, rim)
        fast, ref = mc.period_ratios(*args), period_ratios_reference(*args)
        assert np.array_equal(fast, ref), (fast - ref)
        assert (ref[0] > 0) == (rim is not None and bool((np.abs(dd) > 1e-4).any()))


def test_build_qp_equals_the_row_by_row_reference_bitwise():
    rng = np.random.default_rng(2)
    lim, sc = IKLimits(), mc.Scales()
    for i in range(600):
        d, u = rng.uniform(-0.5, 1.2, 2), rng.uniform(-0.05, 0.05, 5)
        mode = mc.MODES[i % len(mc.MODES)]
        kappa = mc.qp_thresholds(mode) if i % 3 == 0 else mc.thresholds(mode)
        P, J = geometry(CFG, d)
        wb = np.array([P[0, 0] - P[2, 0], P[1, 0] - P[3, 0]])
        st = IKState(d, u)
        ref = build_qp_reference(CFG, st, kappa, sc, lim, 0.01, J, wb)
        fast = build_qp(CFG, st, kappa, sc, lim, 0.01, J, wb, hinge_rise(J) if i % 2 else None)
        assert all(np.array_equal(a, b) for a, b in zip(ref, fast))


def test_row_fills_every_column_from_its_source():
    task, ctl, ep, obs = _begun("wrm", "t1-loose")
    for _ in range(30):
        cmd = ctl(obs)
        obs, _ = ep.step(cmd)
    row = task.row(obs, cmd)
    assert row.shape == (len(COLUMNS),)
    col = dict(zip(COLUMNS, row))
    t, d = task.soil_wheels.truth, task.data
    assert col["x"] == d.xpos[task.chassis, 0] and col["v_cmd"] == cmd.u[0] and col["mode"] == cmd.mode
    assert col["slip"] == np.mean(t["slip"]) and col["sinkage"] == np.mean(t["sinkage"])
    assert [col[f"W_{c}"] for c in ("c1", "c2", "c3", "c4", "c5", "c6")] == list(t["Fn"])
    assert col["DP"] == np.sum(t["DP"]) and col["wz"] == d.qvel[5] and col["wz_cmd"] == cmd.u[2]
    assert [col[f"eta_{n}"] for n in mc.NAMES] == list(cmd.ratios)
    empty = task.row(obs, None)
    assert np.isnan(empty[COLUMNS.index("v_cmd")]) and np.isnan(empty[COLUMNS.index("eta_MC2")])


def test_compiled_observation_read_equals_the_numpy_form_bitwise():
    from terrabench.systems.srwmr.sensing import FIELDS, Observation

    task, ctl, ep, obs = _begun("rclm", "t3-rclm")
    for noise in (5.0, 0.0):
        fast = Observation(task.model, task.data, np.random.default_rng(5), load_noise=noise)
        ref = Observation(task.model, task.data, np.random.default_rng(5), load_noise=noise)
        for _ in range(20):
            obs, _ = ep.step(ctl(obs))
            fast.refresh()
            refresh_reference(ref)
            for f in FIELDS:
                assert np.array_equal(getattr(fast, f), getattr(ref, f)), f
    assert obs.delta[0] != 0.0 and np.abs(obs.spin).max() > 0.0  # a state that moves


def test_compiled_log_row_equals_the_numpy_form_bitwise():
    task, ctl, ep, obs = _begun("rclm", "t3-rclm")
    for _ in range(40):
        cmd = ctl(obs)
        assert np.array_equal(task.row(obs, cmd), row_reference(task, obs, cmd), equal_nan=True)
        obs, _ = ep.step(cmd)
    assert np.array_equal(task.row(obs, None), row_reference(task, obs, None), equal_nan=True)
    assert np.abs(task.row(obs, cmd)[COLUMNS.index("P_drive")]) > 0.0


def test_compiled_supervisor_and_steering_checks_equal_the_numpy_expressions():
    MONITORED = mc.MONITORED
    from terrabench.systems.srwmr.kinematics import steering_wait

    rng = np.random.default_rng(15)
    halts = waits = 0
    for i in range(3000):
        r, kappa = rng.uniform(0.0, 1.3, 10), np.array(mc.THRESHOLDS[mc.MODES[i % len(mc.MODES)]])
        if i % 7 == 0:
            r[rng.integers(10)] = np.nan
        over = np.where(MONITORED, r / kappa, 0.0)
        ref = int(np.argmax(over)) if (over >= 1.0).any() else -1
        assert mc.halting_ratio(r, kappa, MONITORED) == ref
        halts += ref >= 0
        mu = rng.uniform(-1.0, 1.0, 6)
        meas = mu + rng.normal(0.0, 0.1, 6)
        u = rng.uniform(-0.05, 0.05, 5) * (rng.uniform(size=5) < 0.4)
        if i % 9 == 0:
            meas[rng.integers(6)] = np.nan
        if i % 11 == 0:
            u[rng.integers(3)] = np.nan
        ref_wait = bool(np.abs(mu - meas).max() > 0.15 and (np.abs(u[:3]) > 0).any())
        assert steering_wait(mu, meas, u, 0.15) == ref_wait
        waits += ref_wait
    assert 0 < halts < 3000 and 0 < waits < 3000


def test_compiled_power_equals_numpy_sum_bitwise():
    from terrabench.systems.srwmr.task import _abs_power_kernel

    rng = np.random.default_rng(16)
    for _ in range(3000):
        n = int(rng.integers(1, 129))  # numpy's two regimes the kernel covers: < 8, <= 128
        f, v = rng.normal(size=n) * 10 ** rng.uniform(-3, 3, n), rng.normal(size=n)
        assert _abs_power_kernel(f, v) == np.abs(f * v).sum()
    task, ctl, ep, obs = _begun("wrm", "t1-loose")
    for _ in range(30):
        obs, _ = ep.step(ctl(obs))
    d = task.data
    ref = float(np.abs(d.actuator_force * d.actuator_velocity).sum())
    assert ref > 0.0 and task.power(obs) == ref
