"""Stop rules every system shares, written once: turned over, fallen, stalled, past the goal
line, a controller's stop request (its plan complete, a health halt). A system's own physical
rule (OCTOPUS's ``tipped_back``: the COG behind its rearmost loaded contact) lives in its task.

Each rule returns ``(status, reason)`` when it fires and None otherwise, the shape a task's
``check`` returns (:class:`terrabench.systems.base.Task`); a task's ``check`` is the sequence of
its rules. Statuses are the shared ones of :data:`terrabench.benchmark.trial.STATUSES`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from terrabench.sim.stall import StallWatch


def roll_pitch(quat) -> tuple[float, float]:
    """Roll (left side up > 0) and pitch (nose up > 0) in rad of a body quaternion (w, x, y, z)
    with x forward and z up (Z-Y-X Euler angles)."""
    return roll_pitch_f(*map(float, quat))


def roll_pitch_f(w: float, x: float, y: float, z: float) -> tuple[float, float]:
    """:func:`roll_pitch` of a quaternion given as four Python floats (``ndarray.tolist()``'s
    values: no conversion)."""
    r20 = 2.0 * (x * z - w * y)        # R[2, 0]
    r21 = 2.0 * (y * z + w * x)        # R[2, 1]
    r22 = 1.0 - 2.0 * (x * x + y * y)  # R[2, 2]
    return math.atan2(r21, r22), math.asin(max(-1.0, min(1.0, r20)))


def turned_over(roll: float, pitch: float, limit: float, pitch_limit: float | None = None) -> tuple[str, str] | None:
    """``turned_over`` once |roll| exceeds ``limit`` or |pitch| exceeds ``pitch_limit`` (rad; None:
    ``limit`` too). A system whose backward fall has a physical rule of its own (OCTOPUS:
    ``tipped_back``) keeps the pitch limit only as a last-resort guard beyond it."""
    plim = limit if pitch_limit is None else pitch_limit
    if abs(roll) > limit or abs(pitch) > plim:
        lim = f"{limit} rad" if plim == limit else f"{limit} / {plim} rad"
        return "turned_over", f"|roll| {abs(roll):.2f} or |pitch| {abs(pitch):.2f} rad beyond {lim}"
    return None


def fell(z: float, z_min: float, what: str = "body") -> tuple[str, str] | None:
    """``fell`` once the height ``z`` of ``what`` is below ``z_min`` (m)."""
    if z < z_min:
        return "fell", f"{what} below z = {z_min} m"
    return None


class Stalled:
    """``stuck`` once :class:`~terrabench.sim.stall.StallWatch` fires: ``time`` s without moving
    ``distance`` m or getting that much closer to the goal. Feed it on the slow checks only (the
    stored-series replay :func:`terrabench.sim.stall.first_stall` assumes so)."""

    __slots__ = ("watch",)

    def __init__(self, time: float, distance: float):
        self.watch = StallWatch(time, distance)

    def __call__(self, t: float, x: float, y: float, d: float, where: str = "") -> tuple[str, str] | None:
        if self.watch.update(t, x, y, d):
            return "stuck", self.watch.reason() + (f" ({where})" if where else "")
        return None


#: kinds of :class:`StopRequest`: the controller gave up (a health monitor) / its plan is complete
HALT, DONE = "halt", "done"


@dataclass(frozen=True)
class StopRequest:
    """A controller's request to end the episode (carried by its command): ``kind`` :data:`HALT`
    or :data:`DONE`, and one line a reader understands."""

    kind: str
    reason: str

    def __post_init__(self) -> None:
        if self.kind not in (HALT, DONE):
            raise ValueError(f"StopRequest kind {self.kind!r}; valid: {HALT}, {DONE}")


def past_goal(x: float, goal: float | None, what: str = "chassis") -> tuple[str, str] | None:
    """``success`` once ``x`` (m, along the task's axis) reaches the goal line (None: no line)."""
    if goal is not None and x >= goal:
        return "success", f"{what} past x = {goal:.2f} m"
    return None


def requested_stop(stop: StopRequest | None, x: float, goal: float | None, tol: float) -> tuple[str, str] | None:
    """The outcome of a controller's stop request: a halt is ``stuck``; a completed plan is
    ``success`` if it ended within ``tol`` (m) of the goal line (or there is none), else ``stuck``
    short of it."""
    if stop is None:
        return None
    if stop.kind == HALT:
        return "stuck", stop.reason
    if goal is None or x >= goal - tol:
        return "success", stop.reason
    return "stuck", f"{stop.reason} short of the goal (x {x:.2f} < {goal:.2f} m)"
