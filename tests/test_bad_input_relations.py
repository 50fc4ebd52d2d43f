"""Issue 30's bad input: a relation between config fields that does not hold, a malformed list,
an empty id in a list, a prefix that is not an id, and env arguments that are not what they
claim are each one ``ValueError`` line (exit 2 on the command line) before any simulation and
with no store written."""

from __future__ import annotations

import shlex

import gymnasium as gym
import numpy as np
import pytest
from typer.testing import CliRunner

import terrabench.envs  # noqa: F401  (registers the envs)
from terrabench import catalog
from terrabench.cli import app
from terrabench.config import RelationError, relations_of

ENV = {"COLUMNS": "400", "NO_COLOR": "1"}


def one_error_line(res, *needles):
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:"), res.output
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


#: (command, what the one line must name): every field of the broken relation with its value
CASES = [
    ("run mrs-cwc --terrains A-01 --set stiffness.k_low=150 --set stiffness.k_high=100",
     ["stiffness.k_low=150", "stiffness.k_high=100"]),
    ("run mrs-cwc --terrains A-01 --set stiffness.latch_off=0.9 --set stiffness.latch_on=0.5",
     ["stiffness.latch_off=0.9", "stiffness.latch_on=0.5"]),
    ("run mrs-cwc --terrains A-01 --set protocol.control_period=0.001",
     ["protocol.control_period=0.001", "physics.timestep=0.005"]),
    ("run mrs-cwc --terrains A-01 --set protocol.divergence_check_period=0.005",
     ["protocol.divergence_check_period=0.005", "protocol.control_period"]),
    ("run octopus --terrains step-400 --set robot.flipper_range=[1.4,-1.2]", ["robot.flipper_range=[1.4, -1.2]"]),
    ("run octopus --terrains step-400 --set robot.l1=100", ["'robot.l1' = 100", "(0, 1.5]"]),
    ("run octopus --terrains step-400 --set protocol.check_period=0.001",
     ["protocol.check_period=0.001", "protocol.control_period"]),
    ("run octopus --terrains step-400 --set scene.step_height=0.7", ["scene.step_height=0.7",
                                                                      "scene.max_step_height=0.6"]),
    ("run srwmr --terrains t1-loose --set protocol.control_period=0.0001",
     ["protocol.control_period=0.0001", "physics.timestep"]),
    ("run srwmr --terrains t1-loose --set robot.rocker_range=[0.5,-0.5]", ["robot.rocker_range", "lower < 0 < upper"]),
    ("run srwmr --terrains t1-loose --set limits.delta_range=[-0.7,1.15]",
     ["limits.delta_range=[-0.7, 1.15]", "robot.rocker_range=[-1.2, 0.65]"]),
    # the paper's 550 mm is past what the fitted linkage reaches inside the IK's range (it started
    # at the bracket's end, the IK infeasible at once, and the skipped plan read "success")
    ("run srwmr --terrains t1-loose --set scene.clearance=0.55",
     ["scene.clearance=0.55", "limits.delta_range=[-0.6, 1.15]", "reaches 0.058-0.526 m"]),
    ("run beams --group estimation --set estimator.k_start_range=[5,0]", ["estimator.k_start_range=[5, 0]"]),
    ("run beams --group estimation --set estimator.hb_grid_mm=[-20,40,0]", ["estimator.hb_grid_mm=[-20, 40, 0]"]),
    ("run soil --terrains mars_soft/W100/s0.2 --set wheel.radius=100", ["'wheel.radius' = 100", "(0, 2]"]),
    # malformed lists and ids
    ("run mrs-cwc --terrains A-01 --set chain.drive_solimp=[1,2", ["[1,2", "does not parse"]),
    ("run mrs-cwc --methods cwc-tdt,,d-tdt --terrains A-01", ["'cwc-tdt,,d-tdt'", "empty item", "mj-tdt"]),
    ("run mrs-cwc --methods cwc-tdt --terrains A-01,", ["'A-01,'", "empty item", "A-02"]),
    ("run beams --terrains stiff-d1", ["'stiff-d1'", "stiff-d100"]),
]


@pytest.mark.parametrize("command, needles", CASES, ids=[c for c, _ in CASES])
def test_bad_input_is_one_line_before_any_work(tmp_path, command, needles):
    store = tmp_path / "r.duckdb"
    res = CliRunner().invoke(app, shlex.split(command) + ["--store", str(store)], env=ENV)
    one_error_line(res, *needles)
    assert not store.exists()


def test_relations_hold_on_every_default_config():
    """The declared relations hold on every system's defaults (or the defaults would be refused),
    and the systems that declare timing relations declare them on the root config."""
    for sid in catalog.populate().ids("system"):
        cfg = catalog.system(sid).base_config()
        for prefix, rel in relations_of(cfg):
            rel.check(_at(cfg, prefix))


def _at(cfg, prefix):
    for part in filter(None, prefix.split(".")):
        cfg = getattr(cfg, part)
    return cfg


def test_a_relation_is_checked_after_every_override_whatever_their_order():
    """Raising k_high and k_low together is valid in either order of the --set items."""
    sysobj = catalog.system("mrs-cwc")
    for order in (("stiffness.k_high", "stiffness.k_low"), ("stiffness.k_low", "stiffness.k_high")):
        values = {"stiffness.k_low": 300.0, "stiffness.k_high": 400.0}
        specs = sysobj.plan(instances=["A-01"], methods=["cwc-tdt"], overrides={k: values[k] for k in order})
        assert len(specs) == 1
    with pytest.raises(RelationError, match="stiffness.k_low=300 must be <= stiffness.k_high"):
        sysobj.plan(instances=["A-01"], methods=["cwc-tdt"], overrides={"stiffness.k_low": 300.0})


def test_beams_instances_match_exactly():
    """``stiff`` is an instance of its own: it does not also plan stiff-d100/300/600."""
    sysobj = catalog.system("beams")
    ids = {s.instance for s in sysobj.plan(instances=["stiff"], methods=["interact"])}
    assert ids == {"stiff"}


ENVS = ["terrabench/MRSCWC-v1", "terrabench/Octopus-v1", "terrabench/SRWMR-v1"]


@pytest.mark.parametrize("env_id", ENVS)
def test_env_instance_must_be_an_id(env_id):
    with pytest.raises(ValueError, match="123 is not an id"):
        gym.make(env_id, instance=123)


@pytest.mark.parametrize("env_id", ENVS)
def test_env_actions_must_be_numbers(env_id):
    env = gym.make(env_id)
    env.reset(seed=0)
    n = env.action_space.shape[0]
    for action in ([10**400] * n, np.array(["0.1"] * n), ["0.1"] * n, np.ones(n, dtype=bool),
                   np.ones(n, dtype=complex)):
        with pytest.raises(ValueError, match="action must be an array of numbers"):
            env.step(action)
    env.step([0] * n)  # Python ints are numbers
    env.close()


def test_a_relation_names_a_bound_computed_from_other_fields_in_its_one_line():
    """``Relation.detail``: the error adds what is valid for the values given (here the rover's start
    clearance against what its linkage reaches inside the IK's closing-angle range), and the bound
    follows the fields it is computed from (a narrower IK range reaches less)."""
    sysobj = catalog.system("srwmr")
    with pytest.raises(RelationError, match=r"scene.clearance=0.53 .* this linkage reaches 0.058-0.526 m"):
        sysobj.plan(instances=["t1-loose"], methods=["wrm"], overrides={"scene.clearance": 0.53})
    with pytest.raises(RelationError, match=r"this linkage reaches 0.058-0.4\d\d m"):
        sysobj.plan(instances=["t1-loose"], methods=["wrm"],
                    overrides={"scene.clearance": 0.5, "limits.delta_range": [-0.6, 0.8]})
    assert len(sysobj.plan(instances=["t1-loose"], methods=["wrm"], overrides={"scene.clearance": 0.52})) == 1
