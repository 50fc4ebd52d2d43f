"""Soil instance ids (the single-wheel rig and the CMU trials) and the method families: parsing
shared by planning (:mod:`.scenarios`) and the report (:mod:`.report`), kept apart so that
neither imports the other."""

from __future__ import annotations

import re

import numpy as np

from terrabench.soil.presets import SOILS
from terrabench.soil.terramechanics import SLIP_MAX, SLIP_MIN
from terrabench.systems.soil.cmu import METHODS as CMU_METHODS  # noqa: F401 - the CMU methods, re-exported
from terrabench.systems.soil.cmu import points

LOADS = (50.0, 100.0, 150.0, 370.0)
SLIPS = (-1.0, -0.5, -0.2, -0.1, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)
#: documented slip range of an instance: -1 (locked wheel) to 1 (spinning in place)
SLIP_RANGE = (SLIP_MIN, SLIP_MAX)
_ID = re.compile(r"(?P<soil>[a-z_]+)/W(?P<load>[0-9.]+)/s(?P<slip>-?[0-9.]+)")
_CMU_ID = re.compile(r"cmu/b(?P<beta>[0-9]+)/t(?P<trial>[0-9]+)")
RIG_METHODS = ("rig", "analytic")


def parse_instance(iid: str) -> tuple[str, float, float]:
    """``"mars_soft/W100/s0.20"`` -> (soil, load N, slip); ValueError naming what is wrong."""
    m = _ID.fullmatch(iid)
    if not m:
        raise ValueError(f"soil instance {iid!r} must look like SOIL/W<load N>/s<slip>, e.g. mars_soft/W100/s0.2")
    soil, load, slip = m["soil"], float(m["load"]), float(m["slip"])
    valid = sorted(SOILS) + ["custom"]
    if soil not in valid:
        raise ValueError(f"soil {soil!r} in {iid!r} is unknown; valid: {', '.join(valid)}")
    if not SLIP_RANGE[0] <= slip <= SLIP_RANGE[1]:
        raise ValueError(f"slip {slip} in {iid!r} is outside the documented range [{SLIP_RANGE[0]}, {SLIP_RANGE[1]}]")
    if not load > 0:
        raise ValueError(f"load {load} N in {iid!r} must be positive")
    return soil, load, slip


def instance_id(soil: str, load: float, slip: float) -> str:
    return f"{soil}/W{load:g}/s{slip:.2f}"


def parse_cmu(iid: str) -> int:
    """``"cmu/b30/t012"`` -> trial index 12 (checked against the data); ValueError otherwise."""
    m = _CMU_ID.fullmatch(iid)
    if not m:
        raise ValueError(f"cmu instance {iid!r} must look like cmu/b<slip angle>/t<trial>, e.g. cmu/b30/t012")
    p = points()
    trial = int(m["trial"])
    if not 0 <= trial < len(p["trial"]):
        raise ValueError(f"trial {trial} in {iid!r} is out of range; valid: 0..{len(p['trial']) - 1}")
    beta = int(p["beta_deg"][trial])
    if int(m["beta"]) != beta:
        raise ValueError(f"trial {trial} in {iid!r} was run at slip angle {beta} deg, not {m['beta']}")
    return trial


def cmu_instances() -> list[str]:
    p = points()
    order = np.lexsort((p["slip"], p["beta_deg"]))
    return [f"cmu/b{int(p['beta_deg'][i])}/t{int(p['trial'][i]):03d}" for i in order]
