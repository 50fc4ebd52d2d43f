"""The rover's methods: the locomotion strategies the scripted operator uses, and what ends each."""

from __future__ import annotations

from dataclasses import dataclass

from terrabench.systems.base import MethodInfo


@dataclass(frozen=True)
class RoverMethod(MethodInfo):
    """A rover method; ``goal_line``: its trial succeeds the moment the chassis passes the
    instance's goal line (a drive towards it); False: when its plan ends at the goal (a scripted
    manoeuvre whose last action must be completed, e.g. a crab that steers back, a lowered wheel)."""

    goal_line: bool = False


METHODS = {
    "wrm": RoverMethod(
        "wrm", "wheel rolling mode (straight, Ackermann path), health halt at body slip 0.96", ("wheels",),
        goal_line=True,
    ),
    "wcm": RoverMethod("wcm", "wheel crabbing mode: steer +-90 deg, roll sideways, steer back", ("wheels",)),
    "rclm": RoverMethod(
        "rclm", "robot chassis lifting mode: raise/lower the chassis, wheels coordinated (MC#2)", ("suspension",)
    ),
    "rcm": RoverMethod(
        "rcm", "robot creeping mode (inchworm), entered from WRM below 10 % climbing efficiency", ("suspension",),
        goal_line=True,
    ),
    "swlm": RoverMethod(
        "swlm", "single wheel legged mode: CoM shift, clutch, lift one wheel (MC#1), roll, lower, release",
        ("suspension", "clutch"),
    ),
    "dwlm": RoverMethod(
        "dwlm", "double wheel legged mode: as SWLM with a symmetric pair (c1+c2, c3+c4, c5+c6)",
        ("suspension", "clutch"),
    ),
}
