"""The linkage fit's geometry: the kernel, the MuJoCo model and the fit's targets agree."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from terrabench.systems.srwmr import linkage_fit as lf
from terrabench.systems.srwmr.kinematics import (
    axle_positions,
    chassis_clearance,
    geometry,
    level_zeta,
    rocker_jacobian,
)
from terrabench.systems.srwmr.robot import WHEELS, Names, RobotConfig, add_robot

FIT = lf.fitted_robot()
EARLIER = lf.earlier_robot()


def test_the_default_robot_is_the_fitted_linkage():
    d = RobotConfig()
    for k in (*lf.FREE, "body_drop"):
        assert getattr(d, k) == pytest.approx(getattr(FIT, k), abs=1e-6), k


@pytest.mark.parametrize("cfg", [EARLIER, FIT], ids=["earlier", "fitted"])
def test_the_kernel_matches_the_chain_and_its_derivative(cfg):
    for d in ([0.0, 0.0], [0.3, -0.2], [-0.25, 0.4]):
        P, J = geometry(cfg, d)
        np.testing.assert_allclose(P, axle_positions(cfg, d, level_zeta(cfg, d)), atol=1e-12)
        np.testing.assert_allclose(J, rocker_jacobian(cfg, d), atol=1e-6)


def test_the_built_model_puts_the_axles_where_the_kinematics_does():
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.1])
    add_robot(spec, [0, 0, 2.0], 0.0, FIT)
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    ch = d.body(Names.CHASSIS).xpos
    got = np.array([d.body(Names.wheel(c)).xpos - ch for c in WHEELS])
    np.testing.assert_allclose(got, axle_positions(FIT, [0.0, 0.0]), atol=1e-9)
    # the body box's CoM sits com_x ahead of the hinge line
    box = m.geom(Names.CHASSIS)
    assert box.pos[0] == pytest.approx(FIT.com_x) and box.pos[2] == pytest.approx(-FIT.body_drop)


def test_the_fitted_linkage_keeps_its_stated_geometry():
    assert FIT.wheelbase == pytest.approx(1.90, abs=0.02)  # [S] 2200 mm with r = 150
    assert chassis_clearance(FIT, [0.0, 0.0]) == pytest.approx(0.25, abs=1e-9)
    v = lf.evaluate(FIT)
    # lowering puts the middle support behind the CoM (rear lift), raising ahead of it (front lift)
    assert v["middle_ahead_at_150_m"] < -0.2 and v["middle_ahead_at_500_m"] > 0.02
    # the earlier geometry cannot: its middle axle stays within 3 mm of the hinge when lowered
    d = lf.evaluate(EARLIER)
    assert abs(d["middle_ahead_at_150_m"]) < 0.005
    # the wheelbase shrinks 3x faster per lift than on the earlier linkage (the paper's 7.0 / 3.6 is
    # not reached: the reach to 550 mm and the wheels' gap at 500 mm pull against it)
    assert v["shrink_per_lift"] > 2.5 * d["shrink_per_lift"] and v["shrink_per_lift"] < 7.0 / 3.6
    # the tested clearances are reachable (to 534 of 550 mm) without the front and middle wheels touching
    assert v["clearance_max_m"] > 0.52 and v["fm_at_500_m"] > 2 * FIT.wheel_radius + 0.02
    assert abs(sum(lf.side_loads(FIT)) - lf.SIDE_WEIGHT) < 1e-9


def test_the_fitted_values_are_the_fits_optimum_on_this_code():
    res = lf.residuals(lf.evaluate(FIT))
    assert 0.5 * float(res @ res) == pytest.approx(33.04, abs=0.05)


@pytest.mark.slow
def test_a_refit_finds_no_better_geometry():
    cfg, cost = lf.refit()
    assert cost >= 33.0


def test_the_middle_lift_share_is_the_levers_about_the_hinge():
    """Task 6: a middle wheel lifted, its clutched side splits its load between front and rear by
    their distances from the hinge (a pivot passing no moment). The earlier geometry (middle axle
    under the hinge, equal spacing) splits it equally, as the paper says; the fitted one puts the
    hinge 0.19 m ahead of the middle axle and the front takes ~0.6 (docs/srwmr.md)."""
    for cfg, share in ((lf.earlier_robot(), 0.5), (lf.fitted_robot(), 0.6)):
        p = axle_positions(cfg, [0.0, 0.0], level_zeta(cfg, [0.0, 0.0]))
        got = lf.evaluate(cfg)["middle_lift_front_share"]
        assert got == pytest.approx(share, abs=0.01)
        # the same from the lever rule written out: front load x front arm = rear load x rear arm
        front, rear = p[0, 0], -p[4, 0]
        assert got * front == pytest.approx((1 - got) * rear)
