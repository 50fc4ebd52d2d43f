"""OCTOPUS per-tick work, compiled: the contact pass, the traction, the command's limits and the
support hull give MuJoCo's own numbers and the numpy formulas they replaced (contracts, no timing)."""

import math

import mujoco
import numpy as np
import pytest

from terrabench.sim.episode import Episode
from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus.robot import ARMS, FLIPPERS, Names
from terrabench.systems.octopus.scenarios import SYSTEM
from terrabench.systems.octopus.stability import convex_hull, stability_margin


def _episode(seconds: float = 3.0, method: str = "clm", overrides: dict | None = None):
    """A CLM episode stepped ``seconds`` in (arms placed, tracks and tips on the ground)."""
    spec = SYSTEM.plan(methods=[method], instances=["step-400"], seeds=1,
                       overrides={"protocol.timeout": 30.0, **(overrides or {})})[0]
    cfg = SYSTEM.load_config(spec.config)
    task = SYSTEM.make_task(spec, cfg)
    ctl = SYSTEM.make_controller(spec, cfg, task)
    ep = Episode(task)
    obs, stop = ep.begin()
    cmd = None
    while obs.t < seconds and stop is None:
        cmd = ctl(obs)
        obs, stop = ep.step(cmd)
    assert stop is None
    return task, ctl, ep, obs, cmd


@pytest.fixture(scope="module")
def walking():
    return _episode()


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


def test_compiled_apply_is_the_numpy_apply_bitwise():
    """The compiled command pass equals the plain numpy one (kept for actuator orders other than
    the builder's) on commands beyond the speed limits, with a power limit that binds."""
    runs = []
    for compiled in (True, False):
        task, ctl, ep, obs, cmd = _episode(1.0, overrides={"robot.track_power": 2.0})
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
