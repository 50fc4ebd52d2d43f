"""Every system's report separates config variants: two ``--set`` values in one store give two
labelled lines (or sections), never one line mixing both."""

from __future__ import annotations

import pytest

from terrabench.benchmark.runner import run_trials
from terrabench.benchmark.store import ResultsStore
from terrabench.catalog import populate, system

#: per system: a config key whose two values do not change what the smoke request measures much,
#: and the two values
VARIED = {
    "mrs-cwc": ("protocol.timeout", 1.0, 1.5),
    "octopus": ("protocol.timeout", 2.0, 2.5),
    "soil": ("rig.average_s", 0.1, 0.15),
    "beams": ("protocol.timeout", 900.0, 950.0),
    "srwmr": ("scene.start_jitter", 0.03, 0.04),  # seed 0 starts unjittered: same physics, two configs
}


@pytest.mark.parametrize("sid", populate().ids("system"))
def test_two_set_variants_give_two_labelled_lines(sid, tmp_path):
    if sid not in VARIED:
        pytest.skip(f"no variant pair declared for {sid!r} in VARIED")
    sysobj = system(sid)
    key, a, b = VARIED[sid]
    smoke = dict(sysobj.smoke)
    specs = []
    for v in (a, b):
        specs += sysobj.plan(**{**smoke, "overrides": {**smoke.get("overrides", {}), key: v}})
    with ResultsStore(tmp_path / "s.duckdb") as st:
        run_trials(specs, st, workers=1)
        index = sysobj.report(st, tmp_path / "out")
    text = index.read_text()
    assert f"{key}={a}" in text and f"{key}={b}" in text, f"{sid}: the report does not name both variants"
