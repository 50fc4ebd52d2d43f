"""The unit of work every system shares: a trial spec in, a trial result out.

A trial is fully determined by ``(system, scenario, method, instance, seed, config)``;
:attr:`TrialSpec.key` hashes exactly those six things, so the results store can skip
finished trials and two runs of the same spec can be compared row by row.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

#: Every status a trial can end with. ``success`` is the only one counted as a success.
#: ``timeout`` is a truncation (the time limit, not a failure of the robot's physics: Gymnasium
#: envs report it as ``truncated``); ``fell``, ``stuck``, ``turned_over``, ``tipped_back`` are the
#: robot's failures (``tipped_back``: the COG passed behind the rearmost loaded contact, nose up, a
#: physical tip-over backwards rather than an attitude limit); ``diverged`` is the physics blowing
#: up; ``error`` is a fault (a bug, a dead worker), retried by the next run; ``done`` ends trials
#: that have no success criterion (estimation).
STATUSES = ("success", "timeout", "fell", "stuck", "turned_over", "tipped_back", "diverged", "error",
            "done")
#: Statuses that truncate an episode rather than terminate it.
TRUNCATIONS = ("timeout",)


def canonical_json(obj: Any) -> str:
    """JSON with sorted keys and no whitespace: the form that is hashed and stored."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=_json_default)


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, tuple):
        return list(obj)
    raise TypeError(f"not JSON-serialisable: {type(obj).__name__}")


@dataclass(frozen=True)
class TrialSpec:
    """What to run.

    Attributes:
        system: system id, e.g. ``"mrs-cwc"`` or ``"beams"``.
        scenario: versioned scenario id, e.g. ``"mrs-cwc/benchmark-v1"``.
        method: method id within the system, e.g. ``"cwc-tdt"``.
        instance: the terrain or case, e.g. ``"B-07"``.
        seed: integer seed for every random draw the trial makes.
        config: the fully resolved configuration as a JSON-serialisable mapping.
    """

    system: str
    scenario: str
    method: str
    instance: str
    seed: int
    config: Mapping[str, Any] = field(default_factory=dict)

    @property
    def config_hash(self) -> str:
        return hashlib.sha256(canonical_json(self.config).encode()).hexdigest()[:16]

    @property
    def key(self) -> str:
        ident = [self.system, self.scenario, self.method, self.instance, int(self.seed), self.config_hash]
        return hashlib.sha256(canonical_json(ident).encode()).hexdigest()[:24]


@dataclass
class TrialResult:
    """What a trial produced.

    Attributes:
        status: one of :data:`STATUSES`.
        metrics: named scalar figures (floats; NaN where undefined).
        timeseries: equal-length 1-D arrays keyed by name, ``"t"`` (s) first; may be empty.
        wall_time: seconds of wall-clock time the trial took.
        info: JSON-serialisable extras (messages, counts, the threshold used...).
    """

    status: str
    metrics: dict[str, float] = field(default_factory=dict)
    timeseries: dict[str, np.ndarray] = field(default_factory=dict)
    wall_time: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"unknown trial status {self.status!r}; valid: {', '.join(STATUSES)}")
        lengths = {len(v) for v in self.timeseries.values()}
        if len(lengths) > 1:
            raise ValueError(f"timeseries columns differ in length: {sorted(lengths)}")
