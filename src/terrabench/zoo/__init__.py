"""The mobility map (issue 29): every robot x every terrain family, one protocol (``terrabench run zoo``).

Pieces: :mod:`~terrabench.zoo.families` (terrain families, severities, groups),
:mod:`~terrabench.zoo.config` (course and protocol), :mod:`~terrabench.zoo.adapter` (what a robot
system gives: footprint, methods, unsupported families; :func:`register_adapter` for plugins),
:mod:`~terrabench.zoo.task` (the shared stop order and metrics), :mod:`~terrabench.zoo.system`
(the registered system).
"""

from __future__ import annotations

from terrabench.registry import Registry

SYSTEM_ID = "zoo"


def register(registry: Registry) -> None:
    from terrabench.zoo.system import SCENARIO, SYSTEM

    SYSTEM.register(registry, "terrabench.zoo.system:SYSTEM",
                    {SCENARIO: "the mobility map: every robot's go-to-goal methods x the terrain families"})
