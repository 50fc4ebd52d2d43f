"""The paper's published group results (seed 000_9cedac2e0bc47d42, Tables II and III).

Values are copied from the paper's tables: NSR (%), mean NCR (%), mean NEF, mean NEC (J/m),
50 terrains per group. They are reference data for the reports, never used by a controller.
"""

from __future__ import annotations

#: group -> method id -> (NSR %, NCR %, NEF, NEC J/m)
PAPER_TABLES: dict[str, dict[str, tuple[float, float, float, float]]] = {
    # Table II: Performance Metrics for Methods in Group A
    "A": {
        "cwc-tdt": (96.0, 98.2, 0.775, 269.0),
        "cwc-astar": (94.0, 97.5, 0.755, 277.1),
        "mj-tdt": (94.0, 97.7, 0.701, 267.6),
        "mj-astar": (92.0, 97.4, 0.707, 258.9),
        "cs-tdt": (88.0, 93.4, 0.723, 261.8),
        "cs-astar": (94.0, 96.4, 0.753, 273.6),
        "d-tdt": (62.0, 79.1, 0.531, 286.0),
        "d-astar": (64.0, 80.1, 0.539, 409.0),
    },
    # Table III: Performance Metrics for Methods in Group B
    "B": {
        "cwc-tdt": (74.0, 90.3, 0.336, 754.5),
        "cwc-astar": (78.0, 88.6, 0.371, 639.7),
        "mj-tdt": (38.0, 67.8, 0.200, 3332.5),
        "mj-astar": (52.0, 73.2, 0.248, 2711.3),
        "cs-tdt": (40.0, 73.8, 0.253, 1797.3),
        "cs-astar": (48.0, 69.5, 0.273, 2340.5),
        "d-tdt": (0.0, 20.4, 0.054, 6530.0),
        "d-astar": (0.0, 20.6, 0.046, 8909.7),
    },
}
METRIC_NAMES = ("NSR", "NCR", "NEF", "NEC")
TRIALS_PER_GROUP = 50


def paper_row(group: str, method: str) -> dict[str, float] | None:
    row = PAPER_TABLES.get(group, {}).get(method)
    return None if row is None else dict(zip(METRIC_NAMES, row))
