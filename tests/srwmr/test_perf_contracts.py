"""The per-period fast paths equal their reference forms bitwise (the speed work moved no result)."""

import numpy as np

from terrabench.sim.episode import Episode
from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.ik import IKLimits, IKState, build_qp, build_qp_reference
from terrabench.systems.srwmr.kinematics import geometry, geometry_pair, hinge_rise
from terrabench.systems.srwmr.robot import RobotConfig
from terrabench.systems.srwmr.scenarios import SYSTEM
from terrabench.systems.srwmr.task import COLUMNS

CFG = RobotConfig()


def test_geometry_pair_is_geometry_twice_bitwise():
    rng = np.random.default_rng(1)
    for _ in range(500):
        d, mu = rng.uniform(-0.45, 1.15, 2), rng.uniform(-1.75, 1.75, 6)
        (p0, j0), (p, j) = geometry_pair(CFG, d, mu)
        (q0, k0), (q, k) = geometry(CFG, d), geometry(CFG, d, mu)
        assert all(np.array_equal(a, b) for a, b in ((p0, q0), (j0, k0), (p, q), (j, k)))


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
    spec = SYSTEM.plan(methods=["wrm"], instances=["t1-loose"], overrides={"protocol.timeout": 1.0})[0]
    cfg = SYSTEM.load_config(spec.config)
    task = SYSTEM.make_task(spec, cfg)
    ctl = SYSTEM.make_controller(spec, cfg, task)
    ep = Episode(task)
    obs, _ = ep.begin()
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
