"""The single-wheel soil testbed (issue 12): the hallway's terramechanics as a runnable system."""

from __future__ import annotations


def register(registry) -> None:
    from terrabench.systems.soil.scenarios import SCENARIO, SYSTEM

    SYSTEM.register(registry, "terrabench.systems.soil.scenarios:SYSTEM",
                    {SCENARIO: "single rigid wheel: drawbar pull, torque and sinkage vs slip per soil and load; "
                               "the CMU smooth-wheel trials beside the model"})
