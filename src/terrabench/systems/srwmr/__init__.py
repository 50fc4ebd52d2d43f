"""HIT-MRII: a reconfigurable rocker-bogie rover on loose soil, its constraint-saturated inverse
kinematics and locomotion modes: wheel rolling, crabbing, chassis lifting, creeping and the
wheel-legged SWLM / DWLM (seed 001, Qi et al., IJRR). See docs/srwmr.md."""

from __future__ import annotations

from terrabench.registry import Registry

SYSTEM_ID = "srwmr"


def register(registry: Registry) -> None:
    from terrabench.systems.srwmr.scenarios import SCENARIO, SLOPE_SCENARIO, SYSTEM

    SYSTEM.register(
        registry,
        "terrabench.systems.srwmr.scenarios:SYSTEM",
        {
            SCENARIO: "the paper's tasks T1-T15 (group tasks): wheeled, chassis and wheel-legged modes on loose soil",
            SLOPE_SCENARIO: "slope sweep 0-25 deg, very loose and loose soil, WRM vs RCM",
        },
    )
