"""Runner faults: workers that die or hang cost only their trials, locally and on Ray.

Faults are injected through the plug-in mechanism (``TERRABENCH_PLUGINS``, imported by every
worker): test-only MRS-CWC methods whose controller kills its own process, calls
``os._exit(3)``, raises, sleeps forever, or kills its process only the first time.
"""

import importlib
import os
import sys
import textwrap
import time

import numpy as np
import pytest

from terrabench.benchmark import runner
from terrabench.benchmark.runner import RunSummary, default_wall_budget, run_trials, sim_timeout
from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.systems.mrs_cwc import methods
from terrabench.systems.mrs_cwc.scenarios import SYSTEM

PLUGIN_NAME = "tb_fault_plugin"
PLUGIN = textwrap.dedent('''
    import ctypes
    import os
    import signal
    import time

    from terrabench.systems.mrs_cwc.methods import Method, register_method


    class Law:
        """Drives straight; ``fault`` fires on the first control call."""

        tau_env = float("nan")

        def __init__(self, n, fault):
            self.n, self.fault = n, fault

        def __call__(self, obs, heading_ref, cmd):
            fault = self.fault
            if fault == "kill":
                os.kill(os.getpid(), signal.SIGKILL)
            elif fault == "exit":
                os._exit(3)
            elif fault == "segv":
                ctypes.string_at(0)  # a segfault in C code
            elif fault == "raise":
                raise RuntimeError("boom from the controller")
            elif fault == "hang":
                while True:
                    time.sleep(1.0)
            elif fault == "once":  # dies the first time only (a marker file remembers)
                marker = os.path.join(os.environ["TB_FAULT_DIR"], "once")
                if not os.path.exists(marker):
                    open(marker, "w").close()
                    os.kill(os.getpid(), signal.SIGKILL)
            cmd.wheel_speed[:] = 1.0
            cmd.yaw_stiffness = 50.0


    for fault in ("kill", "exit", "segv", "raise", "hang", "once"):
        register_method(Method(f"fault-{fault}-tdt", f"fault {fault}", "spring", f"fault-{fault}", "tdt", "test"),
                        lambda n, cfg, fault=fault: Law(n, fault))
''')

FAULTS = ("kill", "exit", "segv", "raise", "hang", "once")
HANG_BUDGET = 6.0


def budget(spec):
    return HANG_BUDGET if spec.method == "fault-hang-tdt" else 120.0


@pytest.fixture(scope="module")
def plugin(tmp_path_factory):
    """The fault plugin importable here, in spawned workers and in Ray workers."""
    d = tmp_path_factory.mktemp("plugin")
    (d / f"{PLUGIN_NAME}.py").write_text(PLUGIN)
    saved = {k: os.environ.get(k) for k in ("TERRABENCH_PLUGINS", "PYTHONPATH", "TB_FAULT_DIR")}
    os.environ["TERRABENCH_PLUGINS"] = PLUGIN_NAME
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(d), saved["PYTHONPATH"]]))
    sys.path.insert(0, str(d))
    importlib.import_module(PLUGIN_NAME)
    yield d
    sys.path.remove(str(d))
    sys.modules.pop(PLUGIN_NAME, None)
    for f in FAULTS:
        methods.METHODS.pop(f"fault-{f}-tdt", None)
        methods.BODY_LAWS.pop(f"fault-{f}", None)
    for k, v in saved.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


def plan(method, terrains=("A-01",)):
    return SYSTEM.plan(methods=[method], instances=list(terrains), overrides={"protocol.timeout": 1.0})


def fault_specs():
    return {f: plan(f"fault-{f}-tdt")[0] for f in FAULTS}


def assert_same_trial(st_a, st_b, key):
    (ra,), (rb,) = st_a.rows(keys=[key]), st_b.rows(keys=[key])
    assert ra["status"] == rb["status"]
    np.testing.assert_equal(ra["metrics"], rb["metrics"])  # bitwise (NaN == NaN here)
    ta, tb = st_a.timeseries(key), st_b.timeseries(key)
    assert list(ta) == list(tb) and ta
    for col in ta:
        np.testing.assert_array_equal(ta[col], tb[col])


@pytest.fixture(scope="module")
def reference(plugin, tmp_path_factory):
    """Clean in-process results for the healthy trials (and for 'once' after its one death)."""
    d = tmp_path_factory.mktemp("ref")
    os.environ["TB_FAULT_DIR"] = str(d)
    (d / "once").touch()  # in-process, the 'once' law just drives
    st = ResultsStore(d / "ref.duckdb")
    specs = plan("cwc-tdt", ("A-01", "B-02")) + [fault_specs()["once"]]
    run_trials(specs, st, workers=1)
    (d / "once").unlink()
    yield st
    st.close()


# ------------------------------------------------------------------ helpers and the store
def test_sim_timeout_and_default_budget():
    spec = plan("cwc-tdt")[0]
    assert sim_timeout(spec) == 1.0
    assert default_wall_budget(spec) == pytest.approx(
        runner.BUDGET_OVERHEAD_S + runner.BUDGET_SAFETY / SYSTEM.realtime_factor)
    released = SYSTEM.plan(methods=["cwc-tdt"], instances=["A-01"])[0]
    assert sim_timeout(released) == 1000.0 and 300 < default_wall_budget(released) < 600
    # a slower system gets a longer budget for the same simulated timeout
    from terrabench.catalog import system

    slow = system("srwmr")
    assert slow.realtime_factor < SYSTEM.realtime_factor
    rover = slow.plan(methods=["wrm"], instances=["t1-loose"], overrides={"protocol.timeout": 700.0})[0]
    t = sim_timeout(rover)
    assert default_wall_budget(rover) == pytest.approx(
        runner.BUDGET_OVERHEAD_S + runner.BUDGET_SAFETY * t / slow.realtime_factor)
    unknown = TrialSpec("nosuch", "x", "m", "i", 0, {})
    assert sim_timeout(unknown) is None and default_wall_budget(unknown) == runner.FALLBACK_WALL_BUDGET_S
    with pytest.raises(ValueError, match="wall_budget must be positive"):
        run_trials([spec], None, wall_budget=0)


def test_error_rows_are_not_done_but_physics_outcomes_are(tmp_path):
    a, b, c = (TrialSpec("s", "sc", "m", i, 0, {}) for i in ("a", "b", "c"))
    with ResultsStore(tmp_path / "r.duckdb") as st:
        st.write(a, TrialResult("error", info={"error": "worker died: signal 9 (SIGKILL)"}))
        st.write(b, TrialResult("timeout"))
        st.write(c, TrialResult("fell"))
        assert st.done_keys() == {a.key, b.key, c.key}  # every row is still a taken key
        assert st.done_keys(retry_errors=True) == {b.key, c.key}
        assert st.error_keys() == {a.key} and st.error_keys([b.key]) == set()


def test_describe_and_faults():
    s = RunSummary(requested=6, skipped=0, finished=6, statuses={"timeout": 5, "error": 1}, wall_time=12.34,
                   retried=1, worker_deaths=2, rerun_errors=2, errors={"worker died: signal 9 (SIGKILL)": 1})
    assert s.faults == 1
    assert s.describe() == ("6 trials requested, 0 already stored, 6 run in 12.3 s; "
                            "statuses {'timeout': 5, 'error': 1}; "
                            "1 retried after a worker died; 1 error (worker died: signal 9 (SIGKILL)); "
                            "2 error rows from earlier runs retried")
    assert RunSummary(2, 2).faults == 0 and "already stored" in RunSummary(2, 2).describe()


# ------------------------------------------------------------------ the local pool
def test_local_pool_survives_every_fault_and_the_next_run_retries_only_errors(plugin, reference, tmp_path):
    os.environ["TB_FAULT_DIR"] = str(tmp_path)
    clean = plan("cwc-tdt", ("A-01", "B-02"))
    bad = fault_specs()
    specs = clean[:1] + [bad[f] for f in FAULTS] + clean[1:]
    with ResultsStore(tmp_path / "r.duckdb") as st:
        t0 = time.perf_counter()
        s = run_trials(specs, st, workers=2, wall_budget=budget)
        assert time.perf_counter() - t0 < HANG_BUDGET + 120  # (a loaded 2-core machine)
        assert s.finished == 8 and not s.interrupted
        rows = {r["method"]: r for r in st.rows() if r["method"].startswith("fault")}
        assert rows["fault-kill-tdt"]["status"] == "error"
        assert rows["fault-kill-tdt"]["info"]["error"] == "worker died: signal 9 (SIGKILL)"
        assert rows["fault-kill-tdt"]["info"]["attempts"] == 2
        assert rows["fault-exit-tdt"]["info"]["error"] == "worker died: exit code 3"
        assert rows["fault-segv-tdt"]["info"]["error"] == "worker died: signal 11 (SIGSEGV)"
        assert rows["fault-raise-tdt"]["status"] == "error"
        assert "RuntimeError: boom from the controller" in rows["fault-raise-tdt"]["info"]["error"]
        assert rows["fault-hang-tdt"]["info"]["error"].startswith("hung: no result within the wall budget of 6.0 s")
        assert rows["fault-once-tdt"]["status"] == "timeout"  # died once, then ran in a fresh worker
        for spec in clean + [bad["once"]]:
            assert_same_trial(st, reference, spec.key)
        assert (s.retried, s.worker_deaths, s.hung, s.faults, s.rerun_errors) == (4, 7, 1, 5, 0)
        assert s.statuses == {"timeout": 3, "error": 5}
        text = s.describe()
        assert "4 retried after a worker died" in text and "1 hung past the wall budget" in text
        assert "5 error (" in text and "worker died: exit code 3" in text

        kept = {r["key"]: r["finished_at"] for r in st.rows() if r["status"] != "error"}
        again = run_trials(specs, st, workers=2, wall_budget=budget)
        assert again.skipped == 3 and again.finished == 5 and again.rerun_errors == 5
        assert again.statuses == {"error": 5} and again.faults == 5
        assert "5 error rows from earlier runs retried" in again.describe()
        rows = st.rows()
        assert len(rows) == 8  # nothing duplicated
        assert {r["key"]: r["finished_at"] for r in rows if r["status"] != "error"} == kept  # nothing touched


def test_one_worker_process_when_asked(plugin, reference, tmp_path):
    specs = [fault_specs()["exit"]] + plan("cwc-tdt", ("A-01",))
    with ResultsStore(tmp_path / "r.duckdb") as st:
        s = run_trials(specs, st, workers=1, in_process=False)
        assert s.statuses == {"error": 1, "timeout": 1} and s.retried == 1 and s.worker_deaths == 2
        assert_same_trial(st, reference, specs[1].key)
    with pytest.raises(ValueError, match="in_process=True cannot enforce"):
        run_trials(specs, None, in_process=True, wall_budget=5.0)


# ------------------------------------------------------------------ Ray
def test_unreachable_ray_address_fails_fast_with_one_line(tmp_path):
    pytest.importorskip("ray")
    import ray

    if ray.is_initialized():
        pytest.skip("a Ray session is already up")
    with ResultsStore(tmp_path / "r.duckdb") as st:
        t0 = time.perf_counter()
        with pytest.raises(ValueError, match="cannot reach a Ray cluster at '127.0.0.1:9'") as err:
            run_trials(plan("cwc-tdt"), st, backend="ray", address="127.0.0.1:9")
        assert time.perf_counter() - t0 < 30
        assert "\n" not in str(err.value)
        assert st.rows() == []


@pytest.fixture(scope="module")
def ray_session(plugin):
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield ray
    ray.shutdown()


def test_ray_survives_every_fault_and_the_next_run_retries_only_errors(ray_session, reference, tmp_path):
    clean = plan("cwc-tdt", ("A-01", "B-02"))
    bad = fault_specs()
    specs = clean[:1] + [bad[f] for f in ("kill", "exit", "raise", "hang")] + clean[1:]
    with ResultsStore(tmp_path / "r.duckdb") as st:
        s = run_trials(specs, st, backend="ray", workers=2, wall_budget=budget)
        assert s.finished == 6 and not s.interrupted
        rows = {r["method"]: r for r in st.rows() if r["method"].startswith("fault")}
        for f in ("kill", "exit"):
            r = rows[f"fault-{f}-tdt"]
            assert r["status"] == "error" and r["info"]["error"].startswith("worker died: ray ")
            assert r["info"]["attempts"] == 2
        assert "RuntimeError: boom from the controller" in rows["fault-raise-tdt"]["info"]["error"]
        assert rows["fault-hang-tdt"]["info"]["error"].startswith("hung: no result within the wall budget")
        for spec in clean:
            assert_same_trial(st, reference, spec.key)
        assert (s.retried, s.worker_deaths, s.hung, s.faults) == (2, 4, 1, 4)

        again = run_trials(clean + [bad["kill"], bad["raise"]], st, backend="ray", workers=2, wall_budget=budget)
        assert again.skipped == 2 and again.finished == 2 and again.rerun_errors == 2
        assert again.statuses == {"error": 2}
        assert len(st.rows()) == 6


# ------------------------------------------------------------------ the command line
def test_cli_run_with_a_killed_worker_finishes_and_stores_every_trial(plugin, tmp_path):
    from typer.testing import CliRunner

    from terrabench.cli import app

    store = tmp_path / "cli.duckdb"
    r = CliRunner().invoke(app, ["run", "mrs-cwc", "--methods", "fault-kill-tdt,cwc-tdt", "--terrains", "A-01",
                                 "--timeout", "1", "--workers", "2", "--store", str(store), "--quiet"])
    text = " ".join(r.output.split())
    assert r.exit_code in (0, 1), r.output  # 1 once the command line exits non-zero on faults
    assert "2 run" in text and "Traceback" not in r.output and "BrokenProcessPool" not in r.output
    with ResultsStore(store, read_only=True) as st:
        got = {row["method"]: (row["status"], row["info"].get("error")) for row in st.rows()}
    assert got == {"fault-kill-tdt": ("error", "worker died: signal 9 (SIGKILL)"), "cwc-tdt": ("timeout", None)}


def test_sigterm_keeps_finished_trials_kills_the_workers_and_exits_130(tmp_path):
    import signal
    import subprocess

    store = tmp_path / "term.duckdb"
    cmd = [sys.executable, "-c", "from terrabench.cli import app; app()", "run", "mrs-cwc", "--methods", "cwc-tdt",
           "--terrains", "A-01,A-02,A-03,A-04,A-05,A-06", "--timeout", "100", "--workers", "2",
           "--store", str(store), "--quiet"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = []
    for line in p.stdout:  # one plain line per stored trial (not a terminal)
        lines.append(line)
        if line.startswith("[1/6]"):
            break
    children = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
    t0 = time.perf_counter()
    p.send_signal(signal.SIGTERM)
    out = "".join(lines) + p.stdout.read()
    assert p.wait(timeout=60) == 130, out
    assert time.perf_counter() - t0 < 20
    assert "interrupted" in out and "Traceback" not in out
    time.sleep(0.5)
    assert children and not any(os.path.exists(f"/proc/{c}") and "zombie" not in open(f"/proc/{c}/status").read()
                                for c in children)  # the workers are gone
    with ResultsStore(store, read_only=True) as st:
        rows = st.rows()
    assert 1 <= len(rows) < 6 and "error" not in {r["status"] for r in rows}


def test_an_interrupt_during_a_store_write_waits_for_the_commit(tmp_path):
    # DuckDB turns a KeyboardInterrupt raised inside its execute into an InterruptException (an
    # Exception), which the pool once swallowed as "a dead worker", losing the trial and the stop
    import signal

    spec = TrialSpec("mrs-cwc", "A", "cwc-tdt", "A-01", 0, {})
    with ResultsStore(tmp_path / "s.duckdb") as st:
        old = signal.signal(signal.SIGTERM, lambda *_: (_ for _ in ()).throw(KeyboardInterrupt))
        try:
            with pytest.raises(KeyboardInterrupt):
                with runner._interrupts_deferred():
                    os.kill(os.getpid(), signal.SIGTERM)  # pending, not delivered
                    st.write(spec, TrialResult("success", wall_time=1.0, metrics={"x": 1.0}))
        finally:
            signal.signal(signal.SIGTERM, old)
        assert [r["status"] for r in st.rows()] == ["success"]  # committed before the stop


def test_a_store_error_in_the_pool_is_raised_not_taken_for_a_dead_worker(plugin):
    from terrabench.benchmark.pool import run_pool

    spec = TrialSpec("mrs-cwc", "A", "cwc-tdt", "A-01", 0, {"sim": {"timeout": 0.2}})

    def land(spec, result):
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        run_pool([spec], land, 1, lambda s: 120.0, RunSummary(1, 0))
