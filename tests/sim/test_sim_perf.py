"""perf's raw pass replays the loop's own commands: it must reproduce the loop's motion."""

import numpy as np
import pytest

from terrabench.sim.episode import run_episode
from terrabench.sim.perf import _record, _replay
from terrabench.systems.mrs_cwc.scenarios import SYSTEM

RIGID = {"chain.wheel_drive": "constraint", "chain.noslip_iterations": 10}


@pytest.mark.parametrize("overrides", [{}, RIGID], ids=["servo-drive", "constraint-drive"])
def test_the_replay_reproduces_the_loops_trajectory(overrides):
    (spec,) = SYSTEM.plan(methods=["cwc-tdt"], instances=["B-05"], overrides={"protocol.timeout": 3.0, **overrides})
    cfg = SYSTEM.load_config(spec.config)
    task = SYSTEM.make_task(spec, cfg)
    log = run_episode(task, SYSTEM.make_controller(spec, cfg, task))
    commands = _record(SYSTEM, spec, cfg)
    assert len(commands) == log.steps
    replayed = SYSTEM.make_task(spec, cfg)
    _replay(replayed, commands)
    # the constraint drive writes its reference speeds into qvel: replaying through task.apply
    # carries that too, so the leader ends where the loop's leader ended, bitwise
    np.testing.assert_array_equal(replayed.obs.pos[0], log.block(("x", "y", "z"))[-1])


def test_measure_times_a_config_variant_and_refuses_bad_repeats():
    from terrabench.sim.perf import measure

    (row,) = measure(SYSTEM, "cwc-tdt", ["B-05"], 0.5, repeats=1, overrides={"chain.wheel_shape": "sphere"})
    assert row["loop_steps_per_s"] > 0 and row["raw_steps_per_s"] > 0 and 0 < row["engine_share"] <= 1
    with pytest.raises(ValueError, match="repeats"):
        measure(SYSTEM, "cwc-tdt", ["B-05"], 0.5, repeats=0)
    with pytest.raises(ValueError, match="chain.wheel_shape.*cube.*valid: cylinder, sphere"):
        measure(SYSTEM, "cwc-tdt", ["B-05"], 0.5, overrides={"chain.wheel_shape": "cube"})


def test_parts_time_every_call_of_the_loop():
    """The parts table: every part timed (>= 0), mj_step the episode's own engine time and the
    largest part, the parts and the rest adding up to the loop, bad input refused as measure's."""
    from terrabench.sim.perf import PART_COLUMNS, parts

    (row,) = parts(SYSTEM, "cwc-tdt", ["B-05"], 0.5, repeats=1)
    assert set(PART_COLUMNS) <= set(row) and row["ticks"] >= 10
    assert all(row[c] >= 0.0 for c in PART_COLUMNS if c != "rest") and row["mj_step"] > 0
    assert row["mj_step"] == max(row[c] for c in PART_COLUMNS if c not in ("loop", "outside"))
    total = sum(row[c] for c in ("mj_step", "controller", "observe", "check", "row", "apply", "power", "rest"))
    assert total == pytest.approx(row["loop"], rel=1e-9)
    assert row["outside"] == pytest.approx(row["loop"] - row["mj_step"] - row["apply"], rel=1e-9)
    with pytest.raises(ValueError, match="seconds"):
        parts(SYSTEM, "cwc-tdt", ["B-05"], 0.0)
