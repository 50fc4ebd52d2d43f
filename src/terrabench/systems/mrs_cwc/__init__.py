"""MRS-CWC: a chain of six two-wheeled robots with switchable yaw stiffness (seed 000)."""

from __future__ import annotations

from terrabench.registry import Registry

SYSTEM_ID = "mrs-cwc"


def register(registry: Registry) -> None:
    from terrabench.systems.mrs_cwc.scenarios import SCENARIO, SYSTEM

    SYSTEM.register(registry, "terrabench.systems.mrs_cwc.scenarios:SYSTEM",
                    {SCENARIO: "reach (9,-9) from (0,0) on the released terrains A-01..A-50, B-01..B-50"})
