"""The beam-traversing robot in the zoo: registered, but it enters no family.

Its model (:mod:`terrabench.systems.beams.model`) is the paper's analytic dynamics of an
ellipsoid rolling over one beam pair, not a body in a MuJoCo scene, so it cannot be placed on a
course; every family is declared unsupported with that reason and it has no zoo method to plan.
"""

from __future__ import annotations

from typing import Any

from terrabench.zoo.adapter import Footprint, ZooAdapter, register_adapter
from terrabench.zoo.families import FAMILIES

ANALYTIC = ("the beam robot's model is the paper's analytic dynamics over a beam pair (systems/beams/model.py), "
            "not a MuJoCo body; it cannot be put on a course")


class BeamsAdapter(ZooAdapter):
    robot = "beams"
    label = "beam-traversing ellipsoid"
    methods: dict[str, str] = {}
    unsupported = {f: ANALYTIC for f in FAMILIES}

    def footprint(self) -> Footprint:
        raise NotImplementedError(ANALYTIC)

    def robot_config(self, method: str) -> dict[str, Any]:
        raise NotImplementedError(ANALYTIC)


ADAPTER = register_adapter(BeamsAdapter())
