"""Physics and contract tests of the beam-traversal system (fast; long runs are marked slow)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from terrabench.benchmark.trial import STATUSES, TrialSpec
from terrabench.config import override
from terrabench.systems.beams import SYSTEM, register
from terrabench.systems.beams.config import TrialConfig
from terrabench.systems.beams.control import energy_cost
from terrabench.systems.beams.estimation import (
    EstimatorConfig,
    SensingConfig,
    estimate,
    nelder_mead_batch,
    sense,
    sense_clean,
)
from terrabench.systems.beams.geometry import _quad_form
from terrabench.systems.beams.model import (
    Beam,
    BeamLayout,
    ModelConfig,
    RobotParams,
    contact_scalar,
    critical_stiffness,
    deflection_vec,
    generalized_forces,
    potential_energy,
    simulate,
)

ROBOT, LAYOUT = RobotParams(), BeamLayout()
POSES = [(-0.05, 0.0, 0.0), (-0.03, 0.2, 0.3), (0.0, 0.1, 0.5), (0.05, -0.3, 0.2), (-0.02, 0.4, -0.1)]


@pytest.fixture(autouse=True)
def _tmp_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("TERRABENCH_CACHE", str(tmp_path))


def zero(t, q, v, c):
    return (0.0, 0.0, 0.0)


def test_no_contact_constant_speed():
    log = simulate(ModelConfig(), (-0.5, 0.0, 0.0), (0.05, 0.0, 0.0), 1.0, zero)
    assert math.isnan(log.t_contact)
    np.testing.assert_allclose(log.v[:, 0], 0.05, atol=1e-12)
    np.testing.assert_allclose(log.q[-1, 0], -0.5 + 0.05 * log.t[-1], atol=1e-9)
    assert np.all(log.force == 0)


@pytest.mark.parametrize("q", POSES)
def test_contact_force_along_normal_and_on_surface(q):
    Q = _quad_form(q[1], q[2], ROBOT)[0]
    qm = np.array([[Q[0], Q[1], Q[2]], [Q[1], Q[3], Q[4]], [Q[2], Q[4], Q[5]]])
    for i in range(2):
        cs = contact_scalar(q, Beam(0.25), i, ROBOT, LAYOUT)
        assert cs.in_contact and cs.theta > 0
        r = np.array(cs.point) - np.array([q[0], 0.0, ROBOT.height])
        assert r @ qm @ r == pytest.approx(1.0, abs=1e-8)  # contact point on the ellipsoid
        n = qm @ r  # eq. 5 in the world frame
        f = np.array(cs.force)
        cos = -f @ n / (np.linalg.norm(f) * np.linalg.norm(n))
        assert cos == pytest.approx(1.0, abs=1e-9)  # pushes into the robot along the normal


def test_zero_force_when_not_touching():
    for q in [(-0.2, 0.0, 0.0), (-0.03, math.radians(60), 0.0)]:
        for i in range(2):
            cs = contact_scalar(q, Beam(0.25), i, ROBOT, LAYOUT)
            assert not cs.in_contact and cs.theta == 0 and cs.force == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("q", POSES)
def test_beam_torque_equilibrium(q):
    for i, k in enumerate((0.25, 0.01)):
        cs = contact_scalar(q, Beam(k), i, ROBOT, LAYOUT)
        hinge = np.array([0.0, cs.point[1], 0.0])
        torque = np.cross(np.array(cs.point) - hinge, -np.array(cs.force))[1]  # force on the beam
        assert torque == pytest.approx(k * cs.theta, rel=1e-9)  # eq. 4


@pytest.mark.parametrize("q", POSES)
def test_contact_forces_are_energy_gradient(q):
    beams = (Beam(0.25, 0.002), Beam(0.27))
    cs = [contact_scalar(q, b, i, ROBOT, LAYOUT) for i, b in enumerate(beams)]
    gen = np.array(generalized_forces(q, cs, ROBOT))
    h = 1e-6
    grad = []
    for j in range(3):
        dq = np.zeros(3)
        dq[j] = h
        grad.append((potential_energy(np.add(q, dq), beams, ROBOT, LAYOUT)
                     - potential_energy(np.subtract(q, dq), beams, ROBOT, LAYOUT)) / (2 * h))
    np.testing.assert_allclose(gen, -np.array(grad), rtol=1e-4, atol=1e-7)


def test_scalar_and_vectorised_deflection_agree():
    for q in POSES:
        for i in range(2):
            ts = contact_scalar(q, Beam(0.1, 0.003), i, ROBOT, LAYOUT).theta
            tv = float(deflection_vec(q[0], q[1], q[2], 0.003, i, ROBOT, LAYOUT))
            assert ts == pytest.approx(tv, abs=1e-9)


def test_energy_conserved_without_inputs():
    cfg = ModelConfig()
    log = simulate(cfg, (-0.08, 0.1, 0.05), (0.05, 0.0, 0.0), 1.5, zero)
    r = cfg.robot
    e = [0.5 * r.mass * v[0] ** 2 + 0.5 * r.inertia[0] * v[1] ** 2 + 0.5 * r.inertia[1] * v[2] ** 2
         + potential_energy(q, cfg.beams, r, cfg.layout) for q, v in zip(log.q[::250], log.v[::250])]
    assert not math.isnan(log.t_contact)
    kinetic0 = 0.5 * r.mass * 0.05 ** 2  # the energy that is exchanged with the springs
    assert np.ptp(e) < 0.01 * kinetic0


def test_energy_cost_nonnegative_and_positive_power_only():
    rng = np.random.default_rng(0)
    u, v = rng.normal(size=(100, 3)), rng.normal(size=(100, 3))
    e = energy_cost(u, v, 0.002)
    assert e >= 0
    assert e == pytest.approx(np.clip(u * v, 0, None).sum() * 0.002)
    assert energy_cost(u, -v, 0.002) + e == pytest.approx(np.abs(u * v).sum() * 0.002)


def test_critical_stiffness():
    assert critical_stiffness() == pytest.approx(0.028, abs=5e-4)


@pytest.mark.parametrize("n", [4, 3, 2])
def test_noise_free_estimation_recovers_truth(n):
    cfg = ModelConfig()
    clean = sense_clean(cfg, SensingConfig(sensing_time=0.1))
    rng = np.random.default_rng(3)
    data = sense(cfg, SensingConfig(sensing_time=0.1, sigma=0.0), rng, clean)
    est = estimate(data, cfg, EstimatorConfig(n_unknowns=n, n_starts=30), rng)
    assert est.params["k1"] == pytest.approx(0.25, rel=2e-3)
    assert est.params["k2"] == pytest.approx(0.27, rel=2e-3)
    assert abs(est.params["hb1"]) < 2e-5 and abs(est.params["hb2"]) < 2e-5


def test_nelder_mead_batch_finds_minimum():
    def f(p):
        return (p[:, 0] - 1) ** 2 + 10 * (p[:, 1] + 2) ** 2
    xb, fb, _ = nelder_mead_batch(f, np.random.default_rng(0).uniform(-5, 5, (8, 2)), 400, 1e-8, 1e-12)
    np.testing.assert_allclose(xb, np.tile([1.0, -2.0], (8, 1)), atol=1e-4)


def _quick_spec(seed=0, **kw):
    cfg = override(TrialConfig(kind="estimation"), {"sensing.sensing_time": 0.1, "estimator.n_starts": 20,
                                                    "estimator.n_unknowns": 3, "sensing.sigma": 0.2, **kw})
    return TrialSpec("beams", "beams/estimation-v1", "estimate-3", "sigma20-ts100", seed, cfg.to_dict())


def test_run_trial_deterministic_with_seed():
    a, b, c = SYSTEM.run_trial(_quick_spec(1)), SYSTEM.run_trial(_quick_spec(1)), SYSTEM.run_trial(_quick_spec(2))
    assert a.status == "done" and a.status in STATUSES
    assert a.metrics == b.metrics  # wall-clock times live in info, not in metrics
    assert a.metrics["k1_hat"] != c.metrics["k1_hat"]
    for k in ("t", "fx", "fx_clean"):
        np.testing.assert_array_equal(a.timeseries[k], b.timeseries[k])


@pytest.mark.parametrize("make", [
    lambda: Beam(k=-0.1),
    lambda: RobotParams(mass=-0.2),
    lambda: SensingConfig(sigma=-0.05),
    lambda: override(TrialConfig(), {"case.k1": -1.0}),
    lambda: override(TrialConfig(), {"robot.mass": 0.0}),
    lambda: override(TrialConfig(), {"sensing.sigma": -0.1}),
    lambda: override(TrialConfig(), {"layout.gap_reading": "middle"}),
    lambda: BeamLayout(gap=0.04, gap_reading="centre"),
    lambda: EstimatorConfig(n_unknowns=5),
])
def test_bad_parameters_raise(make):
    with pytest.raises(ValueError):
        make()


def test_window_longer_than_contact_raises():
    cfg = ModelConfig(beams=(Beam(0.01), Beam(0.01)))  # 1 N pushes over flimsy beams in ~0.26 s
    with pytest.raises(ValueError, match="longer than the contact lasts"):
        sense_clean(cfg, SensingConfig(sensing_time=0.6, push_force=1.0))


def test_untouched_beams_raise():
    cfg = ModelConfig(layout=BeamLayout(gap=0.3))
    with pytest.raises(ValueError, match="never touched"):
        sense_clean(cfg, SensingConfig(sensing_time=0.1, max_approach_time=3.0))


def test_bad_trial_is_an_error_row_and_bad_ids_raise():
    spec = _quick_spec()
    bad = TrialSpec(spec.system, spec.scenario, spec.method, spec.instance, 0,
                    {**spec.config, "sensing": {**spec.config["sensing"], "sigma": -1.0}})
    assert SYSTEM.run_trial(bad).status == "error"
    for kw in ({"group": "nope"}, {"methods": ["nope"]}, {"instances": ["nope"]}, {"overrides": {"nope": 1}}):
        with pytest.raises(ValueError):
            SYSTEM.plan(seeds=1, **kw)


def test_plan_and_registry():
    from terrabench.registry import Registry
    reg = Registry()
    register(reg)
    assert reg.get("system", "beams").load() is SYSTEM
    assert "beams/estimation-v1" in reg.ids("scenario", "beams")
    assert {"interact", "avoid", "estimate-4"} <= set(reg.ids("method", "beams"))
    specs = SYSTEM.plan(group="estimation", seeds=3)
    assert len(specs) == 3 * 7 * 3 and len({s.key for s in specs}) == len(specs)
    assert len(SYSTEM.plan(group="traversal", instances=["stiff"], seeds=2)) == 3  # 2 interact + 1 avoid
    s = SYSTEM.plan(group="open-loop", overrides={"beams.dt": 1e-4})[0]
    assert s.config["physics"]["dt"] == 1e-4
    s = SYSTEM.plan(group="open-loop", overrides={"physics.dt": 1e-4})[0]
    assert s.config["physics"]["dt"] == 1e-4


def test_landscape_and_avoid_plan_is_contact_free():
    from terrabench.systems.beams.landscape import LandscapeConfig, build_landscape
    from terrabench.systems.beams.planning import PlannerConfig, plan_path
    grid = LandscapeConfig(dx=0.004, dangle_deg=3.0)
    ls = build_landscape((Beam(0.25), Beam(0.27)), grid=grid)
    mid = grid.angles.size // 2
    assert ls.energy[0, mid, mid] == pytest.approx(ROBOT.mass * 9.81 * (ROBOT.height - ROBOT.h_c))
    assert ls.energy.min() >= ls.energy[0, mid, mid] - 1e-12  # level pose is the global minimum
    np.testing.assert_allclose(ls.theta[1], ls.theta[0][:, ::-1, :])  # mirror symmetry
    plan = plan_path(ls, (-0.08, 0.0, 0.0), PlannerConfig(forbid_contact=True))
    idx = [ls.index(p) for p in plan.path]
    assert not any(ls.contact_mask()[i] for i in idx)
    assert plan.mode == "roll" and plan.path[-1][0] == pytest.approx(0.12)
    assert np.all(np.abs(np.diff(np.array(idx), axis=0)).sum(axis=1) == 1)  # six-neighbour moves


def test_open_loop_flimsy_push_traverses():
    spec = SYSTEM.plan(group="open-loop", instances=["flimsy-f1"])[0]
    res = SYSTEM.run_trial(spec)
    assert res.status == "success"


@pytest.mark.slow
def test_interact_traversal_succeeds():
    for inst in ("stiff", "flimsy"):
        spec = SYSTEM.plan(group="traversal", instances=[inst], methods=["interact"], seeds=1)[0]
        res = SYSTEM.run_trial(spec)
        assert res.status == "success", res.info
        assert res.metrics["energy_mJ"] > 0


# --------------------------------------------------------------------------- nested config, timeout, readings

def test_stored_config_round_trips_and_holds_every_section():
    for spec in SYSTEM.plan(group="all", seeds=2):
        cfg = TrialConfig.from_dict(spec.config)
        assert cfg.to_dict() == spec.config
        assert {"robot", "layout", "case", "sensing", "estimator", "landscape", "planner", "control", "physics",
                "protocol", "check", "experiment"} <= set(spec.config)


def test_changing_a_landscape_default_changes_the_key():
    from dataclasses import replace

    from terrabench.systems.beams.landscape import LandscapeConfig
    spec = SYSTEM.plan(group="traversal", instances=["stiff"], methods=["avoid"])[0]
    cfg = TrialConfig.from_dict(spec.config)
    other = replace(cfg, landscape=LandscapeConfig(dx=0.004))
    spec2 = TrialSpec(spec.system, spec.scenario, spec.method, spec.instance, spec.seed, other.to_dict())
    assert spec2.key != spec.key
    assert SYSTEM.plan(group="traversal", instances=["stiff"], methods=["avoid"],
                       overrides={"landscape.dx": 0.004})[0].key == spec2.key


def test_unknown_or_bad_override_names_the_key():
    with pytest.raises(ValueError, match="landscape.nope"):
        SYSTEM.plan(group="open-loop", overrides={"landscape.nope": 1})
    with pytest.raises(ValueError, match="protocol.delay"):
        SYSTEM.plan(group="open-loop", overrides={"protocol.delay": "soon"})


def test_timeout_key_caps_simulated_time():
    assert SYSTEM.timeout_key == "protocol.timeout"
    spec = SYSTEM.plan(group="open-loop", instances=["flimsy-f1"], overrides={SYSTEM.timeout_key: 0.1})[0]
    assert SYSTEM.run_trial(spec).status == "timeout"
    est = _quick_spec(**{"protocol.timeout": 0.2})
    assert SYSTEM.run_trial(est).status == "timeout"


def test_gap_reading_places_the_plates_and_is_hashed():
    edge, centre = BeamLayout(), BeamLayout(gap_reading="centre")
    assert edge.y_range(0) == pytest.approx((0.06, 0.11)) and edge.inner_gap == pytest.approx(0.12)
    assert centre.y_range(0) == pytest.approx((0.035, 0.085)) and centre.inner_gap == pytest.approx(0.07)
    assert centre.y_range(1) == pytest.approx((-0.085, -0.035))
    a = SYSTEM.plan(group="open-loop", instances=["stiff-f1"])[0]
    b = SYSTEM.plan(group="open-loop", instances=["stiff-f1"], overrides={"layout.gap_reading": "centre"})[0]
    assert a.key != b.key and b.config["layout"]["gap_reading"] == "centre"


def test_start_follows_the_layout():
    from terrabench.systems.beams.model import first_contact_x
    edge = TrialConfig()
    centre = override(TrialConfig(), {"layout.gap_reading": "centre"})
    assert edge.x_start() == -0.08  # the pre-port constant, bitwise
    for cfg in (edge, centre):
        x0 = cfg.x_start()
        assert not any(contact_scalar((x0, 0.0, 0.0), Beam(1.0), i, cfg.robot, cfg.layout).in_contact
                       for i in range(2))
        assert first_contact_x(cfg.robot, cfg.layout) - x0 == pytest.approx(0.018, abs=6e-4)
    assert centre.x_start() < -0.1


def test_landscape_cache_key_includes_the_reading():
    from terrabench.systems.beams.landscape import LandscapeConfig, _key
    grid = LandscapeConfig()
    assert _key(ROBOT, BeamLayout(), grid, 0.0, 0) != _key(ROBOT, BeamLayout(gap_reading="centre"), grid, 0.0, 0)


def test_centre_reading_flips_the_mode_choice_between_k_low_and_k_high():
    """Under the centre reading the roll barrier exceeds the pitch barrier at k = 0.01 (pitch
    over flimsy beams) and not at k = 0.25 (roll through stiff ones); under the edge reading the
    roll barrier is below the pitch barrier at both."""
    from terrabench.systems.beams.landscape import LandscapeConfig, pitch_roll_barriers
    grid = LandscapeConfig(dx=0.004, dangle_deg=3.0)
    centre = BeamLayout(gap_reading="centre")
    low, high = (pitch_roll_barriers(k, ROBOT, centre, grid) for k in (0.01, 0.25))
    assert low["roll"] > low["pitch"]
    assert high["roll"] < high["pitch"]
    edge_low = pitch_roll_barriers(0.01, ROBOT, BeamLayout(), grid)
    assert edge_low["roll"] < edge_low["pitch"]
    mgh = ROBOT.mass * 9.81 * ROBOT.h_c
    assert edge_low["roll"] < 0.3 * mgh < low["roll"] < mgh  # 7.5 mJ vs ~28 mJ of the 39 mJ roll-up
    from terrabench.systems.beams.landscape import critical_stiffness_landscape
    k_centre = critical_stiffness_landscape(ROBOT, centre, grid)
    k_edge = critical_stiffness_landscape(ROBOT, BeamLayout(), grid)
    assert 0.01 < k_centre < 0.25 and k_edge < 0.01  # only the centre reading puts k_low and k_high apart
