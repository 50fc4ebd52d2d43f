"""T4's buried start (``scene.burial``, issue 27): every wheel settled in its own rut.

The paper: "when all wheels are totally sunk in sandy soil, the RCM mode is utilized" [S Task 4].
T4 registers a burial of 150 mm (the wheel radius, the deepest sinkage the soil model represents):
the soil hook carves a rut of 150 mm less the static sinkage under each hub (the wheel's imprint,
walls at the soil's friction angle) and the robot stands that much lower, so after settling each
wheel's sinkage below the undisturbed surface is the burial. Every other instance keeps
``burial = 0``: no rut, the old sinkage (and the old bits: the golden digests)."""

import math

import numpy as np
import pytest

from terrabench.soil.mujoco_soil import _rut_at
from terrabench.systems.srwmr.scenarios import SYSTEM

R = 0.15


def test_rut_profile_is_the_wheel_imprint_then_walls_at_the_friction_angle():
    tw = math.tan(math.radians(30.0))
    d, half = 0.097, 0.06
    ruts = np.array([[1.0, 0.5, 1.0, 0.0, d, half, tw]])
    dep, gx, gy = _rut_at(1.0, 0.5, ruts, R)
    assert dep == pytest.approx(d) and gx == 0.0 and gy == 0.0
    a = R * math.sin(math.radians(30.0))  # the imprint meets the wall here, slope tan(30 deg)
    for u in (a - 1e-7, a + 1e-7):
        dep, gx, _ = _rut_at(1.0 + u, 0.5, ruts, R)
        assert gx == pytest.approx(-tw, rel=1e-4)  # the floor rises into the wall without a kink
    edge = a + (d - R * (1 - math.cos(math.radians(30.0)))) / tw
    assert _rut_at(1.0 + edge + 1e-6, 0.5, ruts, R)[0] == 0.0
    assert _rut_at(1.0 - edge + 1e-3, 0.5, ruts, R)[0] > 0.0
    assert _rut_at(1.0, 0.5 + half, ruts, R)[0] == pytest.approx(d)  # flat across the floor's width
    assert _rut_at(1.0, 0.5 + half + d / tw + 1e-6, ruts, R)[0] == 0.0
    assert _rut_at(1.0, 0.5, np.zeros((0, 7)), R) == (0.0, 0.0, 0.0)


def _settle(instance: str, method: str, seconds: float = 1.0, **overrides):
    spec = SYSTEM.plan(methods=[method], instances=[instance],
                       overrides={"protocol.timeout": seconds, **overrides})[0]
    rec, tasks = [], []

    def on_step(task, obs, cmd):
        t = task.soil_wheels.truth
        rec.append((obs.t, t["sinkage"].copy(), t["rut"].copy()))
        tasks[:] = [task]

    SYSTEM.run_trial(spec, on_step=on_step)
    task = tasks[0]
    t = np.array([x[0] for x in rec])
    i = np.flatnonzero(t >= 0.5)  # settled on the soil (the start is 2 mm above it)
    return spec, task, np.array([x[1] for x in rec])[i], np.array([x[2] for x in rec])[i]


def test_t4_wheels_start_buried_and_the_others_at_their_old_sinkage():
    spec, task, sink, rut = _settle("t4-sinkage", "wrm")
    assert spec.config["scene"]["burial"] == 0.15
    assert task.rut == pytest.approx(0.15 - task.z_sink) and task.rut > 0.09
    assert np.allclose(rut, task.rut, atol=1e-3), "each wheel sits in its own rut"
    # the wheel loads differ (front / middle / rear ~400 / 450 / 270 N: the fitted CoM), so does the
    # sinkage into the rut floor; measured 141-160 mm per wheel, 153 mm mean
    assert np.all(np.abs(sink - 0.15) < 0.02), f"T4 sinkage {sink.min() * 1e3:.0f}-{sink.max() * 1e3:.0f} mm"
    assert abs(sink.mean() - 0.15) < 0.01

    # unburied (the pit alone, the results before issue 27's buried start): the static sinkage
    _, task0, sink0, rut0 = _settle("t4-sinkage", "wrm", **{"scene.burial": 0.0})
    assert task0.rut == 0.0 and np.all(rut0 == 0.0)
    assert abs(sink0.mean() - task0.z_sink) < 0.01 and sink0.max() < 0.07

    # every other instance: burial 0 in its stored config, no rut, sinkage near the static one
    spec1, task1, sink1, rut1 = _settle("t1-loose", "wrm")
    assert spec1.config["scene"]["burial"] == 0.0 and task1.rut == 0.0 and np.all(rut1 == 0.0)
    assert abs(sink1.mean() - task1.z_sink) < 0.01
    for inst in SYSTEM.instances("all"):
        for m in SYSTEM.methods():
            if SYSTEM.applies(m, inst):
                want = 0.15 if inst == "t4-sinkage" else 0.0
                assert SYSTEM.plan(methods=[m], instances=[inst])[0].config["scene"]["burial"] == want, inst
