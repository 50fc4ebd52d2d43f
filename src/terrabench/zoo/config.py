"""The zoo's own config: the course geometry every family shares, and the protocol."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from terrabench.config import check_fields, param


@dataclass(frozen=True)
class CourseConfig:
    """Distances and sizes shared by every family (the robot's own size sets the rest)."""

    run_up: float = param(0.4, gt=0, le=10, unit="m", doc="the robot's front this far before the feature at the start")
    goal_past: float = param(0.3, ge=0, le=10, unit="m",
                             doc="success once the robot's rearmost point is this far past the feature's end")
    lane_margin: float = param(0.6, ge=0, le=10, unit="m",
                               doc="lane width = the robot's width + twice this; leaving the lane is fell")
    friction: float = param(1.0, gt=0, le=5, doc="sliding friction of every rigid ground piece (one for all robots)")
    ditch_depth: float = param(0.5, gt=0, le=5, unit="m", doc="depth of the gap family's ditch below its rims")
    fall_drop: float = param(0.25, gt=0, le=5, unit="m",
                             doc="a tracked body this far below the lowest rim of the lane has fallen")
    block_length: float = param(0.3, gt=0, le=5, unit="m", doc="length along the path of the block family's block")
    slope_length: float = param(1.5, gt=0, le=20, unit="m", doc="horizontal length of the slope families' ramp")
    rough_length: float = param(2.0, gt=0, le=20, unit="m", doc="length of the rough families' rough strip")
    rough_wavelength: float = param(1.0, gt=0, le=20, unit="m",
                                    doc="base wavelength of the sine-sum roughness (channels at 1, 1/3, 1/7.5 of it)")
    rough_ramp: float = param(0.3, gt=0, le=5, unit="m",
                              doc="roughness fades in and out over this length at the strip's ends")
    soft_length: float = param(2.0, gt=0, le=20, unit="m", doc="soft-soil family: length counted as the feature")
    grid: float = param(0.02, gt=0, le=0.5, unit="m", doc="heightfield spacing")
    run_out: float = param(1.0, gt=0, le=20, unit="m", doc="ground built beyond the goal line plus the robot's length")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class ZooProtocolConfig:
    """Success, failure and the clock (the same rules for every robot)."""

    timeout: float | None = param(None, gt=0, le=20000, unit="s", optional=True,
                                  doc="simulated time limit; null: time_factor x the course length / the robot's "
                                      "nominal speed + settle (resolved at planning into the stored config)")
    time_factor: float = param(3.0, ge=1, le=100, doc="the limit allows this many times the nominal travel time")
    settle: float = param(10.0, ge=0, le=1000, unit="s", doc="added to the scaled limit (start-up, settling)")
    stuck_time: float = param(20.0, gt=0, le=10000, unit="s",
                              doc="stuck: the rearmost point moved less than stuck_progress for this long")
    stuck_progress: float = param(0.03, gt=0, le=10, unit="m", doc="the progress that counts against stuck_time")
    turn_over: float = param(1.2, gt=0, le=math.pi, unit="rad", doc="|roll| or |pitch| of the body beyond this")
    start_jitter: float = param(0.03, ge=0, le=1, unit="m",
                                doc="seeds > 0 shift the start sideways by up to this (and draw new roughness)")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class ZooConfig:
    """A zoo trial's own settings; the robot's settings are its system's defaults (stored beside)."""

    course: CourseConfig = field(default_factory=CourseConfig)
    protocol: ZooProtocolConfig = field(default_factory=ZooProtocolConfig)

    def __post_init__(self) -> None:
        check_fields(self)
