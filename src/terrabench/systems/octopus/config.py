"""The fully resolved configuration of one OCTOPUS trial (nested frozen dataclasses)."""

from __future__ import annotations

from dataclasses import dataclass, field

from terrabench.sim.episode import Timing
from terrabench.sim.physics import PhysicsConfig
from terrabench.systems.base import check_finite_positive
from terrabench.systems.octopus.ccm import CCMConfig
from terrabench.systems.octopus.clm import CLMConfig
from terrabench.systems.octopus.robot import RobotConfig


@dataclass(frozen=True)
class SceneConfig:
    """Terrain pieces and the start.

    Attributes:
        step_height: height of the ``step-400`` instance's step (m); ``--set scene.step_height``.
        max_step_height: the largest step any instance may have (m): the arms reach about this.
        terrace_heights: rises of the two-terrace step (m) (400 mm in total).
        terrace_tread: depth of the lower terrace (m).
        side_yaw_deg: approach angle of ``terrace2-side`` to the edges' normal (deg).
        block_height, block_length, block_width: the rough-road block (m).
        block_gap: gap between the robot's right side (flipper) and the block (m).
        start_distance: chassis centre behind the first edge at the start (m).
        jitter_offset: seeds > 0 shift the start sideways by up to this (m).
        jitter_yaw_deg: seeds > 0 turn the start by up to this (deg).
        friction: ground friction.
    """

    step_height: float = 0.4
    max_step_height: float = 0.6
    terrace_heights: tuple[float, float] = (0.2, 0.2)
    terrace_tread: float = 0.45
    side_yaw_deg: float = 25.0
    block_height: float = 0.5
    block_length: float = 0.6
    block_width: float = 0.5
    block_gap: float = 0.01
    start_distance: float = 1.0
    jitter_offset: float = 0.03
    jitter_yaw_deg: float = 3.0
    friction: float = 1.0

    def __post_init__(self) -> None:
        check_finite_positive("scene.max_step_height", self.max_step_height, "m")
        if not (isinstance(self.step_height, (int, float)) and 0 < self.step_height <= self.max_step_height):
            raise ValueError(f"scene.step_height must be in (0, {self.max_step_height}] m, got {self.step_height!r}")
        check_finite_positive("scene.start_distance", self.start_distance, "m")


@dataclass(frozen=True)
class ProtocolConfig:
    """Success, failure and the clock.

    Attributes:
        control_period: controller period (s) [P: 50 Hz].
        timeout: simulated time limit (s).
        log_period: stored series period (s).
        check_period: slow check / divergence test period (s).
        turn_over: |roll| or |pitch| beyond this is ``turned_over`` (rad).
        stuck_time: no progress of ``stuck_progress`` for this long is ``stuck`` (s).
        stuck_progress: progress that counts (m).
        success_past: the COG this far past the (last) edge on top (m).
        success_tilt: |roll| and |pitch| below this count as stable (rad).
        success_hold: held on top and stable this long (s).
        block_past: block task: the COG this far past the block's far end (m).
    """

    control_period: float = 0.02
    timeout: float = 60.0
    log_period: float = 0.1
    check_period: float = 0.5
    turn_over: float = 1.2
    stuck_time: float = 20.0
    stuck_progress: float = 0.03
    success_past: float = 0.35
    success_tilt: float = 0.2
    success_hold: float = 1.0
    block_past: float = 0.6

    def __post_init__(self) -> None:
        check_finite_positive("protocol.timeout", self.timeout, "simulated seconds")
        check_finite_positive("protocol.control_period", self.control_period, "s")
        check_finite_positive("protocol.turn_over", self.turn_over, "rad")


@dataclass(frozen=True)
class OctopusConfig:
    """Everything a trial needs besides (method, instance, seed)."""

    physics: PhysicsConfig = field(default_factory=lambda: PhysicsConfig(timestep=0.004, iterations=30))
    robot: RobotConfig = field(default_factory=RobotConfig)
    scene: SceneConfig = field(default_factory=SceneConfig)
    protocol: ProtocolConfig = field(default_factory=ProtocolConfig)
    clm: CLMConfig = field(default_factory=CLMConfig)
    ccm: CCMConfig = field(default_factory=CCMConfig)

    def __post_init__(self) -> None:
        pr = self.protocol
        Timing(pr.control_period, pr.timeout, pr.check_period, pr.log_period).substeps(self.physics.timestep)
