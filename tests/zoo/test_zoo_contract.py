"""The zoo system's contracts: ids, errors that name the choices, configs refused before any
simulation, unsupported families with their reasons, the stored config (no simulation here)."""

from __future__ import annotations

import math

import pytest

from terrabench.catalog import system
from terrabench.config import ConfigError
from terrabench.zoo import adapter as zad
from terrabench.zoo import families as fam
from terrabench.zoo.system import SYSTEM, ZooSystem, travel

ZOO = system("zoo")


def test_registered_system_is_the_zoo():
    assert isinstance(ZOO, ZooSystem)
    ids = set(ZOO.methods())
    assert {"mrs-cwc.cwc-tdt", "mrs-cwc.d-tdt", "octopus.clm", "octopus.ccm", "srwmr.wrm"} <= ids
    assert ZOO.instances("quick") == fam.instances("quick") and len(ZOO.instances("quick")) == 35
    assert ZOO.instances(None) == fam.instances("full")


def test_unknown_method_names_the_valid_ones():
    with pytest.raises(ValueError, match=r"nope\.x.*valid.*octopus\.clm"):
        ZOO.plan(methods=["nope.x"], instances=["step-up@0.05"])
    with pytest.raises(ValueError, match=r"unknown zoo method 'octopus\.nope'; valid: .*octopus\.ccm"):
        zad.split_method("octopus.nope")


def test_unknown_instance_names_the_form_and_the_families():
    with pytest.raises(ValueError, match=r"unknown zoo family 'nope'; valid: step-up, step-down"):
        ZOO.plan(methods=["octopus.clm"], instances=["nope@1"])
    with pytest.raises(ValueError, match=r"not FAMILY@SEVERITY.*families: step-up"):
        ZOO.plan(methods=["octopus.clm"], instances=["step-up"])
    with pytest.raises(ValueError, match=r"soft-flat.*'clay'; valid: very_loose"):
        ZOO.plan(methods=["srwmr.wrm"], instances=["soft-flat@clay"])


def test_a_bad_severity_is_refused_at_planning():
    with pytest.raises(ValueError, match=r"step-up height.*'-0.1' out of range; valid: \(0, 2\]"):
        ZOO.plan(methods=["octopus.clm"], instances=["step-up@-0.1"])
    # a user's own severity inside the range is a valid instance
    (spec,) = ZOO.plan(methods=["octopus.clm"], instances=["step-up@0.12"])
    assert spec.instance == "step-up@0.12"


@pytest.mark.parametrize("key, value", [("course.run_up", -1.0), ("protocol.time_factor", 0.5),
                                        ("protocol.turn_over", 4.0), ("course.grid", "fine")])
def test_a_bad_config_value_is_refused_before_any_simulation(monkeypatch, key, value):
    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("simulated")

    monkeypatch.setattr(ZooSystem, "make_task", boom)
    with pytest.raises(ValueError, match=key.replace(".", r"\.")):  # a ConfigError, or a parse error naming the key
        ZOO.plan(methods=["octopus.clm"], instances=["step-up@0.05"], overrides={key: value})


def test_a_stored_config_with_a_bad_value_is_refused_when_loaded():
    (spec,) = ZOO.plan(methods=["octopus.ccm"], instances=["step-up@0.05"])
    bad = {**spec.config, "course": {**spec.config["course"], "friction": -1.0}}
    with pytest.raises(ConfigError, match="friction"):
        ZOO.load_config(bad)


def test_unsupported_families_are_skipped_and_asked_for_give_the_reason():
    specs = ZOO.plan(group="quick")
    soil = {f.id for f in fam.FAMILIES.values() if not f.rigid}
    for s in specs:
        f = s.instance.partition("@")[0]
        robot = s.method.partition(".")[0]
        assert (f in soil) == (robot == "srwmr"), (s.method, s.instance)
    with pytest.raises(ValueError, match=r"octopus\.clm on soft-flat: .*terramechanics"):
        ZOO.plan(methods=["octopus.clm"], instances=["soft-flat@loose"])
    with pytest.raises(ValueError, match=r"srwmr\.wrm on step-up: .*rigid"):
        ZOO.plan(methods=["srwmr.wrm"], instances=["step-up@0.05"])
    with pytest.raises(ValueError, match="cannot enter the zoo family 'gap'.*analytic"):
        zad.adapters()["beams"].refuse("any", "gap")
    with pytest.raises(ValueError, match="terramechanics"):
        ZOO.check_trial("mrs-cwc.d-tdt", "slope-loose@10", ZOO.base_config())
    assert ZOO.reason("octopus.ccm", "step-up@0.3") is None
    assert "is srwmr.wrm there" in ZOO.reason("srwmr.rcm", "soft-flat@loose")
    assert ZOO.reason("srwmr.rcm", "slope-loose@10") is None


def test_every_registered_adapter_declares_a_reason_per_unsupported_family():
    for robot, ad in zad.adapters().items():
        for f, why in ad.unsupported.items():
            assert f in fam.FAMILIES, (robot, f)
            assert isinstance(why, str) and len(why) > 20, (robot, f)
        if ad.methods:
            fp = ad.footprint()
            assert fp.length > fp.front > 0 and fp.mass > 0 and fp.speed > 0


def test_stored_config_is_whole_and_the_time_limit_resolved():
    (spec,) = ZOO.plan(methods=["mrs-cwc.cwc-tdt"], instances=["gap@0.3"])
    c = spec.config
    assert set(c) == {"course", "protocol", "robot"}
    assert {"chain", "drive", "stiffness", "protocol", "physics"} <= set(c["robot"])
    ad = zad.adapters()["mrs-cwc"]
    fp, pr = ad.footprint(), ZOO.base_config().protocol
    course = fam.family("gap").course("0.3", fp, ZOO.base_config().course)
    assert c["protocol"]["timeout"] == math.ceil(pr.time_factor * travel(course, fp) / fp.speed + pr.settle)
    assert travel(course, fp) == pytest.approx(0.4 + 0.3 + 0.3 + fp.length)
    # the stored config rebuilds itself, and a set timeout wins
    assert ZOO.trial_config(spec.method, spec.instance, ZOO.load_config(c)) == dict(c)
    (s2,) = ZOO.plan(methods=["mrs-cwc.cwc-tdt"], instances=["gap@0.3"], overrides={"protocol.timeout": 7.0})
    assert s2.config["protocol"]["timeout"] == 7.0 and s2.key != spec.key


def test_a_slower_robot_gets_a_longer_limit():
    fast = ZOO.plan(methods=["mrs-cwc.cwc-tdt"], instances=["soft-flat@loose", "step-up@0.05"])
    slow = ZOO.plan(methods=["srwmr.wrm"], instances=["soft-flat@loose"])
    assert slow[0].config["protocol"]["timeout"] > 3 * fast[0].config["protocol"]["timeout"]


def test_a_plugin_adapter_adds_its_methods(monkeypatch):
    monkeypatch.setattr(zad, "ADAPTERS", dict(zad.adapters()))

    class Toy(zad.ZooAdapter):
        robot, label = "toy", "a toy"
        methods = {"go": "drive straight"}
        unsupported = {"gap": "cannot jump"}

        def footprint(self):
            return zad.Footprint(0.5, 0.25, 0.4, 0.2, 0.1, 10.0, 0.2)

        def robot_config(self, method):
            return {"k": 1}

    zad.register_adapter(Toy())
    assert "toy.go" in SYSTEM.methods()
    (spec,) = SYSTEM.plan(methods=["toy.go"], instances=["step-up@0.05"])
    assert spec.config["robot"] == {"k": 1}
    assert not SYSTEM.applies("toy.go", "gap@0.3")

    class Other(Toy):
        pass

    with pytest.raises(ValueError, match="registered already"):
        zad.register_adapter(Other())
