"""Every system's report separates config variants: two ``--set`` values in one store give two
labelled lines (or sections), never one line mixing both."""

from __future__ import annotations

import pytest

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.catalog import populate, system
from terrabench.config import fields_info

#: what a system declares (a class attribute of its System subclass) when it has no
#: ``timeout_key`` to vary, or when varying its timeout would change what the smoke request
#: measures: a ``--set`` key and two values whose smoke runs must come out as two variants
ATTR = "report_variant"


def variant_pair(sysobj):
    """``(key, a, b)``: the system's own ``report_variant``, else its ``timeout_key`` at 0.9 and 0.95
    times the smoke request's timeout (or the default one): both differ from the planned config, and
    neither runs longer than the smoke request. Fails naming what to declare when neither exists."""
    declared = getattr(sysobj, ATTR, None)
    if declared is not None:
        assert isinstance(declared, tuple) and len(declared) == 3 and declared[1] != declared[2], (
            f"{sysobj.id}: {ATTR} must be (KEY, VALUE_A, VALUE_B) with two different values, not {declared!r}")
        return declared
    key = sysobj.timeout_key
    timeout = dict(sysobj.smoke).get("overrides", {}).get(key) if key else None
    if key and timeout is None:
        timeout = next((i.default for i in fields_info(sysobj.base_config()) if i.key == key), None)
    assert key and isinstance(timeout, (int, float)) and timeout > 0, (
        f"{sysobj.id}: the report-variant test has no config key to vary: declare on the system class "
        f"{type(sysobj).__name__} a class attribute {ATTR} = (KEY, VALUE_A, VALUE_B): a --set key and two values "
        "that change little of what the smoke request measures (e.g. a jitter that seed 0 does not use), whose "
        "report must show two labelled variants")
    return key, round(0.9 * timeout, 6), round(0.95 * timeout, 6)


@pytest.mark.parametrize("sid", populate().ids("system"))
def test_two_set_variants_give_two_labelled_lines(sid, tmp_path):
    sysobj = system(sid)
    key, a, b = variant_pair(sysobj)
    assert key in {i.key for i in fields_info(sysobj.base_config())}, (
        f"{sid}: {ATTR} names {key!r}, which is not a --set key of its config (terrabench config {sid})")
    smoke = dict(sysobj.smoke)
    specs = []
    for v in (a, b):
        specs += sysobj.plan(**{**smoke, "overrides": {**smoke.get("overrides", {}), key: v}})
    with ResultsStore(tmp_path / "s.duckdb") as st:
        run_trials(specs, st, workers=1)
        index = sysobj.report(st, tmp_path / "out")
    text = index.read_text()
    assert f"{key}={a}" in text and f"{key}={b}" in text, f"{sid}: the report does not name both variants"


def test_a_system_with_nothing_to_vary_fails_naming_what_to_declare():
    from terrabench.systems.base import System

    class NoClock(System):
        id = "no-clock"

    with pytest.raises(AssertionError, match=rf"declare on the system class NoClock a class attribute {ATTR} = "):
        variant_pair(NoClock())
    NoClock.report_variant = ("rig.average_s", 0.1, 0.1)
    with pytest.raises(AssertionError, match="two different values"):
        variant_pair(NoClock())
