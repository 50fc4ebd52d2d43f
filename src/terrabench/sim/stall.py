"""An opt-in early stop for trials that stand still: no progress and no new best distance.

A navigation trial whose robot has stopped moving and is no closer to its goal than it has
ever been can only spend the rest of its time limit repeating that. :class:`StallWatch` is
the rule, written once so that the episode (online, on the task's slow checks) and a study
replaying a stored time series (``benchmarks/stall_study.py``) apply exactly the same test.

The rule, fed one sample ``(t, x, y, d)`` at a time (time, position, distance to the goal):
the *reference* is the position and the best distance ``d_min`` of the last sample at which
the robot made progress; progress is moving more than ``distance`` from the reference
position, or getting closer than ``d_min - distance``. The trial is stalled once ``time``
seconds pass without progress. Times are compared with a 1 us tolerance, so a rule fed the
simulator's accumulated clock and one fed ``k x period`` agree.
"""

from __future__ import annotations

import math

#: tolerance of the elapsed-time comparison (s): the simulator's clock accumulates rounding
TIME_TOLERANCE = 1e-6


class StallWatch:
    """Stalled after ``time`` s without moving ``distance`` m or improving d_min by it."""

    __slots__ = ("time", "distance", "since", "ref")

    def __init__(self, time: float, distance: float):
        if not (time > 0 and distance > 0):
            raise ValueError(f"a stall watch needs time > 0 and distance > 0, got {time!r}, {distance!r}")
        self.time, self.distance = float(time), float(distance)
        self.since = 0.0
        self.ref: tuple[float, float, float] | None = None  # x, y, best distance so far

    def update(self, t: float, x: float, y: float, d: float) -> bool:
        """Feed one sample; True once the trial has stalled."""
        ref, eps = self.ref, self.distance
        if ref is None or math.hypot(x - ref[0], y - ref[1]) > eps or d < ref[2] - eps:
            self.ref = (x, y, d if ref is None else min(d, ref[2]))
            self.since = t
            return False
        return t - self.since >= self.time - TIME_TOLERANCE

    def reason(self) -> str:
        return f"moved < {self.distance:g} m and d_min did not improve for {self.time:g} s"


def first_stall(t, x, y, target_xy: tuple[float, float], *, period: float, check_period: float,
                stall_time: float, distance: float, check_last: bool = True) -> float | None:
    """When the stall stop would have fired on a stored leader series (s), or None.

    ``t, x, y``: the stored series (a whole number of control periods apart, the last row the
    stop). The samples at the episode's slow checks (multiples of ``check_period``) are fed to
    a :class:`StallWatch`, as the episode feeds them; ``check_last=False`` leaves out the last
    row, for a trial that stopped there on a check that runs before the stall rule (success,
    a fall). Exact when every slow-check instant is a stored row (the MRS-CWC series: 0.1 s
    rows, 0.5 s checks); a ValueError otherwise.
    """
    every = max(1, int(round(check_period / period)))
    watch = StallWatch(stall_time, distance)
    tx, ty = target_xy
    ks = [int(round(v / period)) for v in t]
    if ks and not set(range(0, ks[-1] + 1, every)) <= set(ks):
        raise ValueError("the series skips slow-check instants; it cannot be replayed exactly")
    last = len(ks) - 1
    for i, k in enumerate(ks):
        if k % every or (i == last and not check_last):
            continue
        if watch.update(k * period, x[i], y[i], math.hypot(tx - x[i], ty - y[i])):
            return k * period
    return None
