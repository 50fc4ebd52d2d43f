"""The fully resolved configuration of one OCTOPUS trial (nested frozen dataclasses)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

from terrabench.config import Relation, check_fields, clock_relations, le, ordered, param
from terrabench.sim.physics import PhysicsConfig
from terrabench.systems.octopus.controller_config import CCMConfig, CLMConfig
from terrabench.systems.octopus.robot import RobotConfig


@dataclass(frozen=True)
class SceneConfig:
    """Terrain pieces and the start.

    Relation: ``step_height <= max_step_height`` (the largest step the arms reach).
    """

    relations: ClassVar[tuple[Relation, ...]] = (
        le("step_height", "max_step_height", "the largest step the arms reach"),
    )

    step_height: float = param(0.4, gt=0, unit="m", doc="height of the step-400 instance's step (<= max_step_height)")
    max_step_height: float = param(0.6, gt=0, unit="m",
                                   doc="the largest step any instance may have: the arms reach about this")
    terrace_heights: tuple[float, float] = param((0.2, 0.2), length=2, gt=0, unit="m",
                                                 doc="rises of the two-terrace step (lower, upper); 400 mm in total "
                                                     "by default")
    terrace_tread: float = param(0.45, gt=0, unit="m", doc="depth of the lower terrace")
    side_yaw_deg: float = param(25.0, ge=-90, le=90, unit="deg",
                                doc="approach angle of terrace2-side to the edges' normal")
    block_height: float = param(0.5, gt=0, unit="m", doc="rough-road block height")
    block_length: float = param(0.6, gt=0, unit="m", doc="rough-road block length")
    block_width: float = param(0.5, gt=0, unit="m", doc="rough-road block width")
    block_gap: float = param(0.01, ge=0, unit="m",
                             doc="gap between the robot's right side and the block, from the outermost contact "
                                 "surface: the right flipper pulley capsule's end, pulley_r beyond the flipper's side "
                                 "face (the paper: '10 mm beside the robot'; measured from the side face the pulley "
                                 "overlapped the block by 8 cm and caught its corner)")
    start_distance: float = param(1.0, gt=0, unit="m", doc="chassis centre behind the first edge at the start")
    jitter_offset: float = param(0.03, ge=0, unit="m", doc="seeds > 0 shift the start sideways by up to this")
    jitter_yaw_deg: float = param(3.0, ge=0, le=180, unit="deg", doc="seeds > 0 turn the start by up to this")
    friction: float = param(1.0, ge=0, doc="ground friction")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class ProtocolConfig:
    """Success, failure and the clock."""

    control_period: float = param(0.02, gt=0, unit="s", doc="controller period [P: 50 Hz]")
    timeout: float = param(150.0, gt=0, unit="s",
                           doc="simulated time limit; the paper gives none (and calls CLM slow). It scales with the "
                               "crawler speed: 90 s was set for a 0.1 m/s walk (the block task's 2.2 m of travel, a "
                               "two-terrace task's two climbs and walks; at 60 s those were cut off while still "
                               "progressing); at clm.track_speed 0.06 m/s the same distances take 0.1 / 0.06 as "
                               "long, 150 s (at 90 s the block trials were cut off at 2.07-2.18 of 2.26 m)")
    log_period: float = param(0.1, gt=0, unit="s", doc="stored series period")
    check_period: float = param(0.5, gt=0, unit="s", doc="slow check / divergence test period")
    turn_over: float = param(1.2, gt=0, le=math.pi, unit="rad",
                             doc="|roll| beyond this is turned_over; the pitch has the tip-back rule (tipped_back: "
                                 "the COG behind the rearmost loaded contact) and, as a last-resort guard, "
                                 "turned_over beyond 1.6 rad (task.TURN_OVER_PITCH)")
    stuck_time: float = param(20.0, gt=0, unit="s", doc="no progress of stuck_progress for this long is stuck")
    stuck_progress: float = param(0.03, gt=0, unit="m", doc="progress that counts (see stuck_time)")
    success_past: float = param(0.35, ge=0, unit="m", doc="the COG this far past the (last) edge on top")
    success_tilt: float = param(0.2, gt=0, le=math.pi, unit="rad", doc="|roll| and |pitch| below this count as stable")
    success_hold: float = param(1.0, ge=0, unit="s", doc="held on top and stable this long")
    block_past: float = param(0.6, ge=0, unit="m", doc="block task: the COG this far past the block's far end")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class OctopusConfig:
    """Everything a trial needs besides (method, instance, seed).

    Relations (checked by ``validate`` once every ``--set`` is applied): every joint range is
    (lower, upper) with lower < upper (MuJoCo needs it; a reversed range is no range); the control
    period is a whole number of physics steps, and the slow check and the stored series are not
    faster than the controller (both run at control instants).
    """

    relations: ClassVar[tuple[Relation, ...]] = (
        *(ordered(f"robot.{j}_range", strict=True, why="a joint range is (lower, upper)")
          for j in ("flipper", "swing", "boom", "elbow")),
        *clock_relations(),
    )

    physics: PhysicsConfig = field(default_factory=lambda: PhysicsConfig(timestep=0.004, iterations=30))
    robot: RobotConfig = field(default_factory=RobotConfig)
    scene: SceneConfig = field(default_factory=SceneConfig)
    protocol: ProtocolConfig = field(default_factory=ProtocolConfig)
    clm: CLMConfig = field(default_factory=CLMConfig)
    ccm: CCMConfig = field(default_factory=CCMConfig)
