"""MC#1-#11 ratios, the DAQP-saturated IK, metrics and the soil calibration (pure functions)."""

import numpy as np
import pytest

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr import metrics as mt
from terrabench.systems.srwmr.ik import IKLimits, IKState, SaturatedIK, build_qp
from terrabench.systems.srwmr.robot import RobotConfig

CFG = RobotConfig()
SC = mc.Scales()


def test_mc1_allowed_and_forbidden_lifts():
    for lift in mc.ALLOWED_LIFTS:
        mc.mc1_check(lift)
    for bad in (("c1", "c5"), ("c1", "c3"), ("c1", "c2", "c3"), ("c2", "c6")):
        with pytest.raises(ValueError, match="violates MC#1.*allowed lifts: c1, c2"):
            mc.mc1_check(bad)
    with pytest.raises(ValueError, match="unknown wheel"):
        mc.mc1_check(("c9",))


def test_load_figures_and_ratios():
    w = [380, 380, 380, 380, 380, 380]
    assert mc.w_diff(w) == 0 and mc.w_fmr(w) == 0
    w = [0, 380, 570, 380, 570, 380]  # a lifted wheel: its load moves to the others
    assert mc.w_diff(w) == 570
    assert mc.w_fmr(w) == pytest.approx(np.mean(w))
    r10, r11 = mc.load_ratios(w, SC)
    assert r10 == pytest.approx(570 / 1300) and r11 == pytest.approx(np.mean(w) / 700)
    assert mc.eta_change(0.03, 0.02, 0.005) == pytest.approx(0.5)
    with pytest.raises(ValueError, match="valid: WRM"):
        mc.thresholds("WALK")


def test_every_scale_reaches_the_ratio_kernel():
    """A ``scales`` field a user can set must change a ratio: each one moves the constants the
    compiled kernel reads (``scales.wb_min`` was declared for MC#3 and read by nothing), and each
    constraint names a field that exists (MC#3 none: its normaliser is the robot's wheelbase)."""
    import dataclasses

    names = {f.name for f in dataclasses.fields(mc.Scales)}
    for c in mc.CONSTRAINTS:
        assert c.scale is None or c.scale in names, c
    assert [c.name for c in mc.CONSTRAINTS if c.scale is None] == ["MC3"]
    base = mc.ratio_consts(CFG, SC)
    for f in dataclasses.fields(mc.Scales):
        v = getattr(SC, f.name)
        other = "midrange" if v == "mean" else v * 1.5
        assert not np.array_equal(mc.ratio_consts(CFG, dataclasses.replace(SC, **{f.name: other})), base), f.name


def test_qp_passes_a_feasible_command_and_saturates_a_jump():
    ik = SaturatedIK(CFG, IKLimits(), SC, 0.01)
    st = IKState(np.array([0.1, 0.1]), np.array([0.02, 0.0, 0.0, 0.0, 0.0]))
    u = ik.solve(np.array([0.021, 0.0, 0.0, 0.0, 0.0]), st, mc.thresholds("RCLM"))
    assert np.allclose(u, [0.021, 0, 0, 0, 0], atol=1e-9)
    u = ik.solve(np.array([0.05, 0.0, 0.0, 0.0, 0.0]), st, mc.thresholds("RCLM"))  # MC#7 kappa 0.3
    assert u[0] == pytest.approx(0.02 * 1.3, abs=1e-8)
    G, h, lb, ub = build_qp(CFG, st, mc.thresholds("RCLM"), SC, IKLimits(), 0.01)
    assert G.shape == (16, 5) and np.all(G @ u <= h + 1e-9)


def test_qp_mc3_blocks_further_closing_past_its_threshold():
    ik = SaturatedIK(CFG, IKLimits(), SC, 0.01)
    st = IKState(np.array([1.05, 1.05]), np.zeros(5))  # wheelbase reduced by 0.567, beyond kappa 0.52
    u = ik.solve(np.array([0.0, 0.0, 0.0, 0.05, 0.05]), st, mc.thresholds("RCLM"))
    assert u is None or np.all(u[3:] <= 1e-9)


def test_qp_infeasible_is_none():
    lim = IKLimits(delta_range=(0.0, 0.1))
    ik = SaturatedIK(CFG, lim, SC, 0.01)
    st = IKState(np.array([0.5, 0.5]), np.zeros(5))  # outside the rocker range: no step back fits
    assert ik.solve(np.zeros(5), st, mc.thresholds("RCLM")) is None


def test_qp_solve_time():
    ik = SaturatedIK(CFG, IKLimits(), SC, 0.01)
    st = IKState(np.array([0.2, 0.2]), np.array([0.015, 0, 0.0, 0.0, 0.0]))
    for _ in range(300):
        ik.solve(np.array([0.05, 0.0, 0.02, 0.03, 0.03]), st, mc.thresholds("RCLM"))
    t = ik.timing()
    assert t["qp_n"] == 300
    assert t["qp_median_us"] < 500  # target 100 us; loose bound for a loaded 2-core machine


def test_metrics_on_synthetic_series():
    v = np.full(100, 0.015)
    vc = np.full(100, 0.025)
    assert mt.body_slip(v, vc) == pytest.approx(0.4)
    assert np.isnan(mt.body_slip(v, np.zeros(100)))
    assert mt.drawbar_coefficient([100, 50], [400, 400]) == pytest.approx(150 / 800)
    assert mt.traction_efficiency([200.0], [0.02], [8.0]) == pytest.approx(0.5)
    assert mt.energy(np.full(10, 50.0), 0.1) == pytest.approx(50.0)
    assert mt.path_length([0, 3], [0, 4]) == pytest.approx(5.0)
    wd, wf = mt.load_figures(np.array([[380] * 6, [0, 456, 456, 456, 456, 456]]))
    assert wd.tolist() == [0, 456] and wf[1] == pytest.approx(380)


def test_w_fmr_about_the_midrange_reads_the_papers_own_pairs():
    """The two readings of W_fmr's lost equation on the paper's Task 7 figures [S]: with the front
    pair lifted W_diff ~1300 N and W_fmr ~640 N, with the rear pair lifted 1189 N and 612 N. A lifted
    wheel carries 0 N and the six loads sum to the weight (mean ~380 N [S]), so about the mean
    W_fmr is at least W_diff - 380 N (920 / 809 N, past MC#11's 700 N the paper's own lifts kept),
    while about the midrange of W_max and W_min it is W_diff / 2 (650 / 595 N)."""
    mean_load = 380.0
    for wdiff, paper_fmr in ((1300.0, 640.0), (1189.0, 612.0)):
        rest = (6 * mean_load - wdiff) / 3  # the other grounded wheels share the remainder
        w = [0.0, 0.0, wdiff, rest, rest, rest]
        assert mc.w_diff(w) == pytest.approx(wdiff)
        about_mean, about_mid = mc.w_fmr(w, "mean"), mc.w_fmr(w, "midrange")
        assert about_mean == pytest.approx(wdiff - mean_load) and about_mean > 700.0
        assert about_mid == pytest.approx(wdiff / 2) and abs(about_mid - paper_fmr) < 0.05 * paper_fmr
    sc = mc.Scales(w_fmr_centre="midrange")
    w = [0, 380, 570, 380, 570, 380]
    assert mc.load_ratios(w, sc)[1] == pytest.approx(285 / 700)
    wd, wf = mt.load_figures(np.array([w]), "midrange")
    assert wf[0] == pytest.approx(wd[0] / 2)
    # the compiled period ratios read the same centre as the oracle's functions
    k = mc.ratio_consts(CFG, sc)
    assert k[-1] == 1.0 and mc.ratio_consts(CFG, SC)[-1] == 0.0
    with pytest.raises(ValueError, match="valid: mean, midrange"):
        mc.w_fmr(w, "median")
    with pytest.raises(ValueError, match="valid: mean, midrange"):
        mt.load_figures(np.array([w]), "median")


def test_soil_fit_constants_reproduce_the_t1_targets():
    """The fitted soils give the T1 zero-pull slips they were fitted to (fails if the soil model changes)."""
    from terrabench.systems.srwmr.soils import LOOSE, TARGETS, VERY_LOOSE, zero_pull_slip

    assert zero_pull_slip(VERY_LOOSE) == pytest.approx(TARGETS["very_loose"], abs=0.02)
    assert zero_pull_slip(LOOSE) == pytest.approx(TARGETS["loose"], abs=0.02)


def test_each_term_s_qp_rows_and_ratio_are_one_definition():
    """A command on the boundary of a term's QP row gives that term's kappa as its ratio: the IK
    (rows) and the supervisor (ratios) read the same MC#k (constraints.CONSTRAINTS)."""
    from terrabench.systems.srwmr.kinematics import period_geometry

    lim = IKLimits()
    mode, ts = "RCLM", 0.01
    kappa = mc.qp_thresholds(mode)
    d = np.array([0.05, 0.03])
    (P0, J), _, dz, wb = period_geometry(CFG, d, np.zeros(6))
    u_prev = np.array([0.02, 0.0, 0.01, 0.0, 0.0])
    G, h, _, _ = build_qp(CFG, IKState(d, u_prev), kappa, SC, lim, ts, J, wb, dz)
    rows = sorted(c.qp_rows for c in mc.CONSTRAINTS if c.qp_rows)
    assert rows[0][0] == 0 and rows[-1][1] == G.shape[0]
    assert all(a[1] == b[0] for a, b in zip(rows, rows[1:]))  # every row belongs to one term
    checked = []
    for c in mc.CONSTRAINTS:
        if c.name not in ("MC6", "MC7", "MC8", "MC9"):  # the command ratios (MC3-MC5 read the state)
            continue
        j = c.qp_rows[0]
        base = u_prev.copy()
        var = int(np.flatnonzero(G[j])[0])
        base[var] = 0.0
        u = base.copy()
        u[var] = (h[j] - G[j] @ base) / G[j, var]
        r = mc.period_ratios(CFG, SC, u, u_prev, J, dz, wb, d, np.zeros(2), np.zeros(6), np.full(6, 380.0))
        assert r[c.ratio] == pytest.approx(c.kappa(mode), rel=1e-9), c.name
        assert mc.NAMES[c.ratio] == c.name
        checked.append(c.name)
    assert checked == ["MC6", "MC7", "MC8", "MC9"]
    assert [c.name for c in mc.CONSTRAINTS if c.halts] == ["MC4", "MC5", "MC10", "MC11"]


def test_the_limited_share_counts_the_periods_the_projection_changed():
    ik = SaturatedIK(CFG, IKLimits(), SC, 0.01)
    st = IKState(np.array([0.2, 0.2]), np.array([0.015, 0, 0.0, 0.0, 0.0]))
    inside = np.array([0.015, 0.0, 0.0, 0.0, 0.0])  # the previous command again: inside the set
    outside = np.array([0.05, 0.0, 0.02, 0.03, 0.03])  # a jump the rate rows must cut
    for u in (inside, inside, inside, outside):
        ik.solve(u, st, mc.thresholds("RCLM"))
    t = ik.timing()
    assert t["qp_inside"] == 3 and t["qp_n"] == 1
    assert t["qp_limited_share"] == pytest.approx(ik.active / 4) and ik.active == 1
