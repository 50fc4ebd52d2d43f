"""The MuJoCo single-wheel rig against the analytic steady state, and the report."""

import numpy as np
import pytest

from terrabench.soil.presets import DRY_SAND, HIT_MRII_WHEEL, MARS_SOFT
from terrabench.soil.report import write_report
from terrabench.soil.testbed import analytic_sweep, sweep

WHEEL = HIT_MRII_WHEEL
SLIPS = [-0.2, 0.1, 0.3, 0.6]


@pytest.mark.parametrize("sp", [MARS_SOFT, DRY_SAND], ids=lambda s: s.name)
def test_rig_reproduces_analytic(sp):
    # Tolerance: DP and T/r within 1 % of the load, sinkage within 1 %, slip within 0.005.
    a = analytic_sweep(sp, WHEEL, [100.0], SLIPS)
    b = sweep(sp, WHEEL, [100.0], SLIPS)
    for x, y in zip(a, b):
        assert y["slip_measured"] == pytest.approx(x["slip"], abs=0.005)
        assert abs(y["DP_N"] - x["DP_N"]) < 0.01 * 100.0
        assert abs(y["torque_Nm"] - x["torque_Nm"]) < 0.01 * 100.0 * WHEEL.radius
        assert y["sinkage_m"] == pytest.approx(x["sinkage_m"], rel=0.01)


def test_rows_and_report(tmp_path):
    rows = analytic_sweep(MARS_SOFT, WHEEL, [60.0, 120.0], [0.0, 0.2, 0.4, 0.6])
    rows += sweep(MARS_SOFT, WHEEL, [60.0], [0.2, 0.4])
    keys = {"soil", "load_N", "slip", "DP_N", "torque_Nm", "sinkage_m", "DP_coeff", "efficiency", "source"}
    assert all(keys <= set(r) for r in rows)
    assert {r["source"] for r in rows} == {"analytic", "mujoco"}
    index = write_report(rows, tmp_path)
    assert index.exists() and (tmp_path / "mars_soft.png").stat().st_size > 10_000
    assert "DP/W @ s=0.4" in index.read_text()
    with pytest.raises(ValueError, match="rows"):
        write_report([], tmp_path)
