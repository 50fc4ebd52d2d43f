"""OCTOPUS: four arms walk while four flippers crawl; climbing a 400 mm step by touch (seed 003)."""

from __future__ import annotations

from terrabench.registry import Registry

SYSTEM_ID = "octopus"


def register(registry: Registry) -> None:
    from terrabench.systems.octopus.scenarios import ROUGH_SCENARIO, SCENARIO, SWEEP_SCENARIO, SYSTEM

    SYSTEM.register(registry, "terrabench.systems.octopus.scenarios:SYSTEM",
                    {SCENARIO: "the paper's step tasks (400 mm step, two-terrace front/side) and the 500 mm block",
                     SWEEP_SCENARIO: "step-height sweep 100-550 mm",
                     ROUGH_SCENARIO: "beyond the paper: CLM vs CCM over sine-sum rough ground, three levels"})
