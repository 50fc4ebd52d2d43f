"""The wheel-legged report's load table: the lifted side's share of the wheel loads beside the
paper's bound (Task 6)."""

import numpy as np
import pytest

from terrabench.systems.srwmr.report_legged import PAPER_SIDE_SHARE, load_lines, side_share
from terrabench.systems.srwmr.robot import WHEELS


def test_side_share_is_the_sides_part_of_the_six_loads():
    # c1..c6 = front L/R, middle L/R, rear L/R: a right front lift with the right rear suspended
    W = np.array([[380.0] * 6, [485.0, 0.0, 485.0, 826.0, 485.0, 0.0], [0.0] * 6])
    right = side_share(W, "R")
    assert right[0] == pytest.approx(0.5) and right[1] == pytest.approx(826.0 / 2281.0)
    assert np.isnan(right[2])  # nothing carried: no share
    assert side_share(W, "L")[1] == pytest.approx(1455.0 / 2281.0)


class _Store:
    def __init__(self, series):
        self.series = series

    def timeseries(self, key):
        return self.series[key]


def test_the_load_table_reads_the_lifted_sides_share_while_the_wheel_is_up():
    t = np.arange(0.0, 20.0, 0.5)
    up = (t >= 10.0) & (t <= 15.0)
    loads = {c: np.full(len(t), 380.0) for c in WHEELS}
    loads["c2"] = np.where(up, 0.0, 380.0)  # the right front lifted
    loads["c4"] = np.where(up, 700.0, 380.0)
    ts = {"t": t, **{f"Wft_{c}": v for c, v in loads.items()}}
    legged = [{"t": 9.0, "step": 0, "lift": "c2", "action": "clutch", "note": ""},
              {"t": 10.0, "step": 0, "lift": "c2", "action": "lift", "note": "lifted 180 of 180 mm"},
              {"t": 15.0, "step": 0, "lift": "c2", "action": "lower", "note": "lowered"}]
    row = {"instance": "t6-bricks", "method": "swlm", "seed": 0, "key": "k", "info": {"legged": legged}}
    (line,) = load_lines([row], _Store({"k": ts}))
    # the right side (0 + 700 + 380 N) of all six (4 x 380 + 700 N)
    assert line["lifted side's share of the load (up, median)"] == pytest.approx(1080.0 / 2220.0)
    assert line["paper: lifted side's share"] == PAPER_SIDE_SHARE[("t6-bricks", "front")]
    assert line["W_diff max N (up)"] == pytest.approx(700.0)
