import mujoco
import numpy as np
import pytest

from terrabench.terrain import dataset, sine_sum
from terrabench.terrain.mjcf import add_heightfield
from terrabench.terrain.stats import slope_stats


def test_benchmark_has_100_named_terrains():
    ts = dataset.benchmark_terrains()
    assert len(ts) == 100
    assert list(ts)[0] == "A-01" and list(ts)[-1] == "B-50"
    assert dataset.get("b7").id == "B-07"


def test_grid_and_placement_follow_the_spec():
    p = dataset.get("A-01").params
    assert p.shape == (64, 64)
    assert p.side == pytest.approx(14.75)
    x, y = sine_sum.vertex_xy(p)
    assert x[0] == pytest.approx(-3.325) and x[-1] == pytest.approx(11.425)
    assert y[0] == pytest.approx(2.90) and y[-1] == pytest.approx(-11.85)  # j = 1 is the +Y edge
    assert sine_sum.spacing(p)[0] == pytest.approx(0.2341270, abs=1e-7)


def test_heights_are_a_pure_function_of_the_row():
    p = dataset.get("B-07").params
    h1, h2 = sine_sum.heights(p), sine_sum.heights(p)
    assert np.array_equal(h1, h2)
    # u = i/nx starts at 1/64: vertex (1, 1) evaluates the formula at u = v = 1/64
    u = 1 / 64
    expect = 0.0
    for w, wt, f, a, ph in zip((20, 60, 150), (1, 0.5, 0.1), p.freq, p.ampl, p.phase):
        expect += wt * 0.5 * a * 2 * np.sin(2 * np.pi * ph + w * f * u)
    assert h1[0, 0] == pytest.approx(p.z_scale * expect, abs=1e-12)


def test_point_height_snaps_to_the_vertex_grid():
    p = dataset.get("A-05").params
    # u = (x - 4.05 + L/2)/L snapped to k/64; at u = 32/64 and v = 32/64 it equals vertex (32, 32)
    L = p.side
    x = 4.05 - L / 2 + 32 / 64 * L
    y = -4.475 + L / 2 - 32 / 64 * L
    assert float(sine_sum.point_height(p, x, y)) == pytest.approx(sine_sum.heights(p)[31, 31], abs=1e-12)


def test_groups_separate_at_30_degrees_of_mean_axis_slope():
    a = [dataset.get(f"A-{k:02d}").stats() for k in range(1, 51)]
    b = [dataset.get(f"B-{k:02d}").stats() for k in range(1, 51)]
    assert max(s["mean_axis_slope_deg"] for s in a) < 30 < min(s["mean_axis_slope_deg"] for s in b) + 1
    assert max(s["max_slope_deg"] for s in a + b) < 70


def test_slope_stats_of_a_plane():
    x = np.arange(10)[:, None] * 0.5
    h = np.repeat(x * np.tan(np.radians(20)), 8, axis=1)
    s = slope_stats(h, 0.5, 0.5)
    assert s["max_slope_deg"] == pytest.approx(20)
    assert s["mean_axis_slope_deg"] == pytest.approx(20 * 72 / 142)  # 72 x-edges at 20 deg, 70 y-edges at 0


def test_generator_respects_the_band_and_the_seed():
    a = dataset.generate(3, np.random.default_rng(7), slope_band_deg=(30, 45))
    b = dataset.generate(3, np.random.default_rng(7), slope_band_deg=(30, 45))
    assert a == b
    for p in a:
        s = slope_stats(sine_sum.heights(p), *sine_sum.spacing(p))
        assert 30 <= s["mean_axis_slope_deg"] < 45 and s["max_slope_deg"] <= 70


def test_mujoco_surface_matches_the_heights():
    p = dataset.get("B-12").params
    h = sine_sum.heights(p)
    x, y = sine_sum.vertex_xy(p)
    spec = mujoco.MjSpec()
    add_heightfield(spec, h, x, y)
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    geomid = np.zeros(1, np.int32)
    for i, j in [(5, 9), (40, 3), (20, 50), (63, 63)]:
        dist = mujoco.mj_ray(m, d, np.array([x[i], y[j], 50.0]), np.array([0, 0, -1.0]), None, 1, -1, geomid)
        assert 50.0 - dist == pytest.approx(h[i, j], abs=1e-3)


@pytest.mark.parametrize(
    "text, match",
    [
        ("Size,Height\n0.05,0.1\n", "missing column"),
        ("Size,XY Proportion,Height,Ch1 Freq,Ch1 Ampl,Ch1 Phase,Ch2 Freq,Ch2 Ampl,Ch2 Phase,"
         "Ch3 Freq,Ch3 Ampl,Ch3 Phase\n"
         "0.05,0.5,abc,1,1,1,1,1,1,1,1,1\n", "non-numeric"),
        ("Size,XY Proportion,Height,Ch1 Freq,Ch1 Ampl,Ch1 Phase,Ch2 Freq,Ch2 Ampl,Ch2 Phase,"
         "Ch3 Freq,Ch3 Ampl,Ch3 Phase\n"
         "-1,0.5,0.1,1,1,1,1,1,1,1,1,1\n", "size must be a positive"),
    ],
)
def test_bad_csv_gets_a_clear_error(text, match):
    with pytest.raises(ValueError, match=match):
        dataset.parse_rows(text, "x.csv")


def test_a_csv_path_that_is_a_folder_or_missing_says_which(tmp_path):
    with pytest.raises(ValueError, match="is a folder; give one CSV file"):
        dataset.load_csv(tmp_path)
    with pytest.raises(ValueError, match="terrain CSV not found"):
        dataset.load_csv(tmp_path / "none.csv")


def test_unknown_ids_and_groups_name_the_valid_ones():
    with pytest.raises(ValueError, match="A-01 ... A-50"):
        dataset.get("C-01")
    with pytest.raises(ValueError, match="valid: A, B, all"):
        dataset.select(group="Z")


def test_released_waypoints_end_at_the_target():
    for tid in ("A-01", "B-50"):
        wp = dataset.released_waypoints(tid)
        assert wp.shape[1] == 2 and np.allclose(wp[-1], (9, -9))
