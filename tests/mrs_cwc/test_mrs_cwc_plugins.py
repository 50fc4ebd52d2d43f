"""A researcher's own controller plugs in without touching the simulator."""

import textwrap

import numpy as np
import pytest

from terrabench.systems.mrs_cwc import methods
from terrabench.systems.mrs_cwc.methods import Method, register_method

PLUGIN = textwrap.dedent('''
    from terrabench.systems.mrs_cwc.methods import Method, register_method


    class Straight:
        """Every unit drives straight at 1 rad/s; a fixed yaw stiffness of 50."""

        tau_env = float("nan")

        def __init__(self, n):
            self.n = n

        def __call__(self, obs, heading_ref, cmd):
            cmd.wheel_speed[:] = 1.0
            cmd.yaw_stiffness = 50.0


    register_method(Method("straight-tdt", "Straight + TDT", "spring", "straight", "tdt", "test plugin"),
                    lambda n, cfg: Straight(n))
''')


@pytest.fixture
def plugin(tmp_path, monkeypatch):
    (tmp_path / "my_chain_plugin.py").write_text(PLUGIN)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("TERRABENCH_PLUGINS", "my_chain_plugin")
    yield
    methods.METHODS.pop("straight-tdt", None)
    methods.BODY_LAWS.pop("straight", None)


def test_a_plugin_method_runs_through_the_normal_runner(plugin, tmp_path, flat_terrain):
    from terrabench.benchmark.runner import run_trials
    from terrabench.benchmark.store import ResultsStore
    from terrabench.catalog import populate
    from terrabench.registry import Registry
    from terrabench.systems.mrs_cwc.scenarios import SYSTEM

    reg = populate.__wrapped__(Registry())  # a fresh registry sees the plugin
    assert "straight-tdt" in reg.ids("method", "mrs-cwc")
    specs = SYSTEM.plan(methods=["straight-tdt"], instances=["A-01"], overrides={"protocol.timeout": 3.0})
    with ResultsStore(tmp_path / "s.duckdb") as st:
        run_trials(specs, st, workers=1)
        (row,) = st.rows()
        ts = st.timeseries(row["key"])
    assert row["status"] == "timeout" and row["method"] == "straight-tdt"
    # (the last sample ends the trial: no command) the plugin's stiffness reached the model's yaw springs
    assert np.all(ts["K"][:-1] == 50.0)


def test_unknown_body_law_is_refused():
    with pytest.raises(ValueError, match="unknown body law 'nope'"):
        register_method(Method("x-tdt", "X", "spring", "nope", "tdt", ""))
    with pytest.raises(ValueError, match="already exists"):
        register_method(Method("cwc-tdt", "X", "spring", "cwc", "tdt", ""))
