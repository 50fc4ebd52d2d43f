"""MRS-CWC: a chain of six two-wheeled robots with switchable yaw stiffness (seed 000)."""

from __future__ import annotations

from terrabench.registry import Record, Registry

SYSTEM_ID = "mrs-cwc"


def register(registry: Registry) -> None:
    from terrabench.systems.mrs_cwc.methods import METHODS
    from terrabench.systems.mrs_cwc.scenarios import SCENARIO

    registry.register(Record("system", SYSTEM_ID, "MRS-CWC robot chain on 100 rough terrains (Xiao et al.)",
                             "terrabench.systems.mrs_cwc.scenarios:SYSTEM", SYSTEM_ID))
    registry.register(Record("scenario", SCENARIO, "reach (9,-9) from (0,0) on the released terrains A-01..A-50, B-01..B-50",
                             "terrabench.systems.mrs_cwc.scenarios:SYSTEM", SYSTEM_ID, ("benchmark",)))
    for m in METHODS.values():
        tags = (m.variant, m.guidance) + (("map",) if m.guidance == "astar" else ())
        registry.register(Record("method", m.id, f"{m.label}: {m.summary}",
                                 "terrabench.systems.mrs_cwc.methods:METHODS", SYSTEM_ID, tags))
