"""The chain model and whole trials: pinned counts, physics, protocol, determinism."""


import mujoco
import numpy as np
import pytest

from terrabench.config import override
from terrabench.systems.mrs_cwc import task as trial
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import METHODS, get_method
from terrabench.systems.mrs_cwc.robot import ChainConfig, add_chain
from terrabench.terrain import dataset

# variant -> (nq, nv, nu, nbody): pinned so a model change is a deliberate one
PINNED = {"spring": (34, 33, 12, 30), "motor": (29, 28, 17, 25), "none": (54, 48, 12, 20)}


def build(variant):
    spec = mujoco.MjSpec()
    add_chain(spec, variant, (0, 0, 1.0))
    return spec.compile()


@pytest.mark.parametrize("variant", sorted(PINNED))
def test_model_counts_are_pinned(variant):
    m = build(variant)
    assert (m.nq, m.nv, m.nu, m.nbody) == PINNED[variant]


def test_masses_follow_the_spec():
    cfg = ChainConfig()
    unit = cfg.body_mass + 2 * cfg.wheel_mass
    m = build("spring")
    assert m.body_subtreemass[0] == pytest.approx(6 * unit + cfg.bumper_mass + 5 * 2 * 0.4)
    m = build("motor")
    assert m.body_subtreemass[0] == pytest.approx(6 * unit + cfg.bumper_mass + 5 * 1.3)
    m = build("none")
    assert m.body_subtreemass[0] == pytest.approx(6 * unit + cfg.bumper_mass)


def test_centre_of_mass_sits_below_the_wheel_axles():
    m = build("none")
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    unit1 = m.body("unit1").id
    # the unit's own body (not its wheels) has its CoM 0.10 m below the capsule centre
    assert d.xipos[unit1][2] == pytest.approx(1.0 - 0.10)


@pytest.mark.parametrize("mid", list(METHODS))
def test_every_method_runs_two_seconds_without_trouble(mid, flat_terrain):
    # the flat test terrain has no released waypoints: the A* methods plan their own
    cfg = override(MRSConfig(), {"protocol.timeout": 2.0, "waypoint_source": "planner"})
    r = trial.run(get_method(mid), flat_terrain, cfg)
    status, metrics, series, info = r.status, r.metrics, r.timeseries, r.info
    assert status == "timeout" and info["control_steps"] == 80
    assert list(series) == list(trial.TIMESERIES)
    assert np.all(np.diff(series["energy"]) >= 0) and metrics["energy"] > 0


def test_flat_straight_run_reaches_the_target_with_nef_near_one(flat_terrain):
    cfg = override(MRSConfig(), {"protocol.target_xy": [3.0, 0.0], "protocol.timeout": 60.0})
    r = trial.run(get_method("cwc-tdt"), flat_terrain, cfg)
    status, m, series, _info = r.status, r.metrics, r.timeseries, r.info
    assert status == "success"
    assert m["NCR"] == 1.0
    # the 0.5 m drop at the start adds ~0.5 m to a ~2.5 m journey
    assert m["NEF"] == pytest.approx(3.0 / (2.5 + 0.5), rel=0.05)
    # nominal speed 1.5 rad/s x 0.05 m = 0.075 m/s: 2.5 m take ~33 s
    assert m["sim_time"] == pytest.approx(2.5 / 0.075, rel=0.1)
    assert abs(series["y"]).max() < 0.05


def test_the_yaw_stiffness_reaches_the_model_and_bends_follow_the_law(flat_terrain):
    cfg = override(MRSConfig(), {"protocol.target_xy": [0.0, 5.0], "protocol.timeout": 20.0})
    r = trial.run(get_method("cwc-tdt"), flat_terrain, cfg)
    _status, _m, series, _info = r.status, r.metrics, r.timeseries, r.info
    k = series["K"][np.isfinite(series["K"])]
    assert k[0] == pytest.approx(0.03 * 5 + 0.97 * 0.1, rel=1e-6)
    assert np.all((k > 0) & (k <= 100))
    # target to the left: the leader turns toward +y
    assert series["y"][-1] > 0.1


def test_same_spec_same_numbers(flat_terrain):
    cfg = override(MRSConfig(), {"protocol.timeout": 5.0})
    a = trial.run(get_method("cs-tdt"), flat_terrain, cfg)
    b = trial.run(get_method("cs-tdt"), flat_terrain, cfg)
    assert a.metrics == b.metrics
    for k in a.timeseries:
        np.testing.assert_array_equal(a.timeseries[k], b.timeseries[k])


def test_instability_ends_the_trial_as_diverged(flat_terrain):
    # any speed above 0.01 is declared a blow-up: the wheels spin at 1.5 rad/s within a second
    cfg = override(MRSConfig(), {"physics.max_speed": 0.01, "protocol.timeout": 5.0})
    r = trial.run(get_method("cwc-tdt"), flat_terrain, cfg)
    status, _m, _series, info = r.status, r.metrics, r.timeseries, r.info
    assert status == "diverged" and "speed" in info["reason"]


def test_start_is_dropped_above_the_sampled_terrain():
    t = dataset.get("B-03")
    sc = trial.bound(get_method("cwc-tdt"), t, MRSConfig())
    from terrabench.terrain import sine_sum

    xs = np.array(MRSConfig().protocol.drop_probe_x)
    expect = sine_sum.point_height(t.params, xs, np.zeros_like(xs)).max() + 0.5
    assert sc.start_z == pytest.approx(expect)
    assert sc.data.body("unit0").xpos[2] == pytest.approx(expect)


def test_control_period_must_be_whole_physics_steps():
    with pytest.raises(ValueError, match="whole number of physics steps"):
        override(MRSConfig(), {"physics.timestep": 0.01})


def test_bad_timeout_is_rejected():
    with pytest.raises(ValueError, match=r"'protocol.timeout' = 0.0 is out of range; valid: a number > 0"):
        override(MRSConfig(), {"protocol.timeout": 0})


def test_a_unit_that_fell_off_the_world_stops_colliding_and_is_parked(flat_terrain):
    import mujoco

    sc = trial.bound(get_method("d-tdt"), flat_terrain, MRSConfig())
    m, d = sc.model, sc.data
    assert [len(g) for g in sc.unit_geoms] == [4, 3, 3, 3, 3, 3]  # body + 2 wheels (+ bumper)
    j = m.body_jntadr[sc.unit_bodies[3]]
    d.qpos[m.jnt_qposadr[j] + 2] = -70.0
    d.qvel[m.jnt_dofadr[j] + 2] = -40.0
    mujoco.mj_forward(m, d)
    sc.drop_fallen_units(-50.0)
    assert np.all(m.geom_contype[sc.unit_geoms[3]] == 0) and np.all(m.geom_conaffinity[sc.unit_geoms[3]] == 0)
    assert d.qpos[m.jnt_qposadr[j] + 2] == -60.0 and np.all(d.qvel[m.jnt_dofadr[j]:m.jnt_dofadr[j] + 6] == 0)
    assert np.all(m.geom_conaffinity[sc.unit_geoms[2]] != 0)  # the others still collide


# ---------------------------------------------------------------- the constraint wheel drive
def _one_unit_constraint_drive(**kw):
    """One free unit with the Bullet-like drive, no gravity; (model, data, wheel dof, ref dof)."""
    from dataclasses import replace

    from terrabench.systems.mrs_cwc.robot import Names

    spec = mujoco.MjSpec()
    spec.option.timestep = 0.005
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.gravity = [0, 0, 0]
    add_chain(spec, "none", (0, 0, 1.0), replace(ChainConfig(wheel_drive="constraint", **kw), n_units=1))
    m = spec.compile()
    return m, mujoco.MjData(m), m.jnt_dofadr[m.joint(Names.wheel(0, "left")).id], \
        m.jnt_dofadr[m.joint(Names.drive_ref(0, "left")).id]


@pytest.mark.parametrize("load", [0.0, 20.0, 60.0, 95.0])
def test_constraint_drive_holds_the_commanded_speed_up_to_its_torque_limit(load):
    m, d, w, ref = _one_unit_constraint_drive()
    free = m.jnt_dofadr[m.joint("unit0_free").id]
    for _ in range(400):  # 2 s, the unit's body held still
        d.qvel[ref:ref + 2] = -1.5
        d.qvel[free:free + 6] = 0.0
        d.qfrc_applied[w] = -load
        mujoco.mj_step(m, d)
    assert d.qvel[w] == pytest.approx(1.5, abs=3e-4 * load + 1e-6)  # ~4000 N m s/rad
    assert d.qfrc_constraint[ref] == pytest.approx(load, abs=1e-3)  # the reported wheel torque


def test_constraint_drive_slips_at_its_torque_limit():
    m, d, w, ref = _one_unit_constraint_drive()
    free = m.jnt_dofadr[m.joint("unit0_free").id]
    for _ in range(40):
        d.qvel[ref:ref + 2] = -1.5
        d.qvel[free:free + 6] = 0.0
        d.qfrc_applied[w] = -130.0
        mujoco.mj_step(m, d)
    assert d.qvel[w] < 0  # 130 N m > 100 N m: the wheel is dragged backwards
    assert d.qfrc_constraint[ref] == pytest.approx(100.0, abs=1e-6)


def test_constraint_drive_six_free_units_in_the_air_track_their_command():
    """nv = 60 (MRS-D): MuJoCo's sparse Jacobian solved these tendons wrongly; we force dense."""
    from terrabench.systems.mrs_cwc.robot import Names

    spec = mujoco.MjSpec()
    spec.option.gravity = [0, 0, 0]
    add_chain(spec, "none", (0, 0, 10.0), ChainConfig(wheel_drive="constraint"))
    m = spec.compile()
    d = mujoco.MjData(m)
    ref = m.jnt_dofadr[m.joint(Names.drive_ref(0, "left")).id]
    wheels = [m.jnt_dofadr[m.joint(Names.wheel(k, s)).id] for k in range(6) for s in Names.SIDES]
    for _ in range(200):
        d.qvel[ref:ref + 12] = -1.5
        mujoco.mj_step(m, d)
    np.testing.assert_allclose(d.qvel[wheels], 1.5, atol=1e-3)


@pytest.mark.parametrize("mid", ["cwc-tdt", "mj-tdt", "d-tdt"])
def test_constraint_drive_is_stable_on_a03_for_30_s(mid):
    cfg = override(MRSConfig(), {"chain.wheel_drive": "constraint", "protocol.timeout": 30.0})
    r = trial.run(get_method(mid), dataset.get("A-03"), cfg)
    assert r.status == "timeout", r.info["reason"]
    assert r.metrics["NCR"] > 0.1  # it drives toward the target (2.25 m at 0.075 m/s = 0.18)
    power = r.metrics["energy"] / r.metrics["sim_time"]
    assert 0.5 < power < 100.0


# ---------------------------------------------------------------- the opt-in stall stop
def test_a_chain_that_cannot_move_stops_as_stuck_only_when_asked(flat_terrain):
    still = {"drive.wheel_speed": 0.0, "protocol.timeout": 20.0}
    r = trial.run(get_method("cs-tdt"), flat_terrain, override(MRSConfig(), still))
    assert r.status == "timeout"  # off by default
    cfg = override(MRSConfig(), {**still, "protocol.stall_time": 5.0})
    r = trial.run(get_method("cs-tdt"), flat_terrain, cfg)
    assert r.status == "stuck"
    assert 5.0 <= r.metrics["sim_time"] <= 6.0  # first slow check at t = 0, then every 0.5 s


def test_a_moving_chain_is_never_stuck(flat_terrain):
    cfg = override(MRSConfig(), {"protocol.timeout": 20.0, "protocol.stall_time": 5.0})
    assert trial.run(get_method("cwc-tdt"), flat_terrain, cfg).status == "timeout"


def test_stall_time_must_not_be_negative():
    with pytest.raises(ValueError, match="stall_time"):
        override(MRSConfig(), {"protocol.stall_time": -1.0})


RIGID = {"chain.wheel_drive": "constraint", "chain.noslip_iterations": 10,
         "chain.wheel_solref": [0.01, 1.0], "chain.wheel_solimp": [0.99, 0.999, 0.001, 0.5, 2.0]}


def test_rigid_contacts_make_linked_units_fight_but_not_free_units():
    """The released gentle-ground signature (docs/mrs-cwc-findings.md): on A-03 a linked
    chain spends ~18 W, six free units ~2 W; soft MuJoCo contacts give ~2-3 W to both."""
    def power(mid, sets):
        cfg = override(MRSConfig(), {**sets, "protocol.timeout": 40.0})
        r = trial.run(get_method(mid), dataset.get("A-03"), cfg)
        assert r.status == "timeout", r.info["reason"]
        return r.metrics["energy"] / r.metrics["sim_time"]

    assert power("cs-tdt", RIGID) > 10.0
    assert power("d-tdt", RIGID) < 4.0
    assert power("cs-tdt", {}) < 5.0


def test_stall_watch_rule():
    from terrabench.sim.stall import StallWatch

    w = StallWatch(2.0, 0.05)
    assert not w.update(0.0, 0.0, 0.0, 10.0)
    assert not w.update(1.0, 0.01, 0.0, 10.0)  # within 5 cm: no progress
    assert w.update(2.0 - 1e-9, 0.02, 0.0, 10.0)  # the accumulated clock's rounding is tolerated
    w = StallWatch(2.0, 0.05)
    w.update(0.0, 0.0, 0.0, 10.0)
    assert not w.update(1.5, 0.0, 0.0, 9.9)  # closer to the goal by > 5 cm: progress
    assert not w.update(3.0, 0.0, 0.0, 9.9)
    assert w.update(3.5, 0.0, 0.0, 9.9)
    w = StallWatch(2.0, 0.05)
    w.update(0.0, 0.0, 0.0, 10.0)
    assert not w.update(1.9, 0.06, 0.0, 10.0)  # moved > 5 cm: progress, even if no closer
    assert not w.update(3.8, 0.06, 0.0, 10.0) and w.update(3.9, 0.06, 0.0, 10.0)
    with pytest.raises(ValueError, match="stall watch"):
        StallWatch(0.0, 0.05)


def test_sphere_wheels_keep_the_cylinder_mass_and_inertia():
    models = {}
    for shape in ("cylinder", "sphere"):
        t = trial.bound(get_method("cwc-tdt"), dataset.get("A-03"), override(MRSConfig(), {"chain.wheel_shape": shape}))
        b = t.model.body("unit0_wheel_left").id
        g = int(np.flatnonzero(t.model.geom_bodyid == b)[0])
        models[shape] = (t.model, b, g)
    (mc, bc, gc), (ms, bs, gs) = models["cylinder"], models["sphere"]
    assert mc.geom_type[gc] == mujoco.mjtGeom.mjGEOM_CYLINDER and ms.geom_type[gs] == mujoco.mjtGeom.mjGEOM_SPHERE
    assert ms.geom_size[gs][0] == mc.geom_size[gc][0]  # the wheel radius
    assert ms.body_mass[bs] == pytest.approx(mc.body_mass[bc])
    np.testing.assert_allclose(sorted(ms.body_inertia[bs]), sorted(mc.body_inertia[bc]), rtol=1e-9)
    np.testing.assert_allclose(ms.body_ipos[bs], mc.body_ipos[bc], atol=1e-12)
    assert ms.nv == mc.nv and ms.body_subtreemass[0] == pytest.approx(mc.body_subtreemass[0])
    with pytest.raises(ValueError, match="'chain.wheel_shape' = 'cube' is unknown; valid: cylinder, sphere"):
        override(MRSConfig(), {"chain.wheel_shape": "cube"})


def test_the_bumper_ground_switch_only_removes_bumper_terrain_contact():
    from terrabench.terrain.mjcf import GROUND_BIT

    for touches in (True, False):
        cfg = override(MRSConfig(), {"chain.bumper_touches_ground": touches})
        t = trial.bound(get_method("cwc-tdt"), dataset.get("A-03"), cfg)
        m = t.model
        g = int(np.flatnonzero(m.geom_bodyid == m.body("bumper").id)[0])
        assert bool(m.geom_conaffinity[g] & GROUND_BIT) == touches
        assert m.geom_contype[g] != 0  # still collides with the other units


def test_a_stored_series_replays_to_the_stop_the_episode_makes(flat_terrain):
    """benchmarks/stall_study.py predicts stops from stored series; the prediction must be the
    instant at which the episode, run with the stop on, really stops."""
    from terrabench.sim.stall import first_stall

    cfg = MRSConfig().protocol
    slow = {"drive.wheel_speed": 0.0, "protocol.timeout": 12.0}  # a chain that never moves
    r = trial.run(get_method("cs-tdt"), flat_terrain, override(MRSConfig(), slow))
    ts = r.timeseries
    predicted = first_stall(ts["t"], ts["x"], ts["y"], cfg.target_xy, period=cfg.control_period,
                            check_period=cfg.divergence_check_period, stall_time=4.0,
                            distance=cfg.stall_distance, check_last=r.status == "timeout")
    assert predicted is not None and 4.0 <= predicted < 12.0
    stopped = trial.run(get_method("cs-tdt"), flat_terrain, override(MRSConfig(), {**slow, "protocol.stall_time": 4.0}))
    assert stopped.status == "stuck" and stopped.metrics["sim_time"] == pytest.approx(predicted, abs=1e-9)
    with pytest.raises(ValueError, match="skips slow-check"):
        first_stall(ts["t"][::7], ts["x"][::7], ts["y"][::7], cfg.target_xy, period=cfg.control_period,
                    check_period=cfg.divergence_check_period, stall_time=4.0, distance=cfg.stall_distance)
