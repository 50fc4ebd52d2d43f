"""The fully resolved configuration of one MRS-CWC trial."""

from __future__ import annotations

from dataclasses import dataclass, field

from terrabench.sim.episode import Timing
from terrabench.sim.physics import PhysicsConfig
from terrabench.systems.base import check_finite_positive
from terrabench.systems.mrs_cwc.control import (
    DriveConfig,
    FollowConfig,
    HeadFollowingConfig,
    StiffnessLawConfig,
    WaypointConfig,
)
from terrabench.systems.mrs_cwc.planner import PlannerConfig
from terrabench.systems.mrs_cwc.robot import ChainConfig

WAYPOINT_SOURCES = ("released", "planner")


@dataclass(frozen=True)
class ProtocolConfig:
    """Start, target, success and failure (spec section 2).

    Attributes:
        start_xy: leader start (m); the chain trails along -x.
        target_xy: target (m); the released scenes use (9, -9).
        drop_height: leader dropped this far above the highest sampled terrain point (m).
        drop_probe_x: x positions sampled at y = start y for the drop height (m).
        success_threshold: XY leader-target distance that counts as arrival (m).
        timeout: simulated time limit (s).
        fall_z: leader below this height has fallen off the world (m).
        control_period: controller period (s).
        log_period: period of the stored leader time series (s); metrics use every period.
        divergence_check_period: how often the state is checked for blow-up (s).
        start_jitter: seeds > 0 shift the start uniformly by up to this much in x and y (m);
            seed 0 is the released protocol exactly.
        stall_time: opt-in early stop (0 = off, the default): status ``stuck`` once the leader
            has moved less than ``stall_distance`` from where it last moved and d_min (the
            closest it has come to the target, which alone fixes NCR and success) has not
            improved by ``stall_distance`` for this long (s). Checked every
            ``divergence_check_period``. A stopped trial keeps the NCR it had; a chain that
            stood still this long may in principle still break free later, so this changes
            outcomes and is off by default (documented in docs/mrs-cwc-findings.md).
        stall_distance: the movement / d_min improvement that counts as progress (m).
    """

    start_xy: tuple[float, float] = (0.0, 0.0)
    target_xy: tuple[float, float] = (9.0, -9.0)
    drop_height: float = 0.5
    drop_probe_x: tuple[float, ...] = (0.34, 0.12, 0.0, -0.3, -0.6, -0.9, -1.2, -1.5)
    success_threshold: float = 0.5
    timeout: float = 1000.0
    fall_z: float = -50.0
    control_period: float = 0.025
    log_period: float = 0.1
    divergence_check_period: float = 0.5
    start_jitter: float = 0.05
    stall_time: float = 0.0
    stall_distance: float = 0.05

    def __post_init__(self) -> None:
        check_finite_positive("timeout", self.timeout, "simulated seconds")
        check_finite_positive("success threshold", self.success_threshold, "m")
        check_finite_positive("control period", self.control_period, "s")
        if not (self.stall_time >= 0 and self.stall_distance > 0):
            raise ValueError(f"stall_time must be >= 0 (0 = off) and stall_distance > 0, got "
                             f"{self.stall_time!r}, {self.stall_distance!r}")


@dataclass(frozen=True)
class MRSConfig:
    """Everything a trial needs besides (method, terrain, seed).

    Attributes:
        physics: MuJoCo options.
        chain: robot dimensions and masses.
        protocol: start/target/success/timeout.
        drive: wheel-speed law.
        stiffness: CWC stiffness law (CS forces mode "constant").
        head_following: MJ control.
        follow: D control.
        waypoints: A* waypoint following.
        waypoint_source: ``"released"`` (the benchmark's CSV) or ``"planner"`` (our A*).
        planner: cost terms of our A* planner.
    """

    physics: PhysicsConfig = field(default_factory=PhysicsConfig)
    chain: ChainConfig = field(default_factory=ChainConfig)
    protocol: ProtocolConfig = field(default_factory=ProtocolConfig)
    drive: DriveConfig = field(default_factory=DriveConfig)
    stiffness: StiffnessLawConfig = field(default_factory=StiffnessLawConfig)
    head_following: HeadFollowingConfig = field(default_factory=HeadFollowingConfig)
    follow: FollowConfig = field(default_factory=FollowConfig)
    waypoints: WaypointConfig = field(default_factory=WaypointConfig)
    waypoint_source: str = "released"
    planner: PlannerConfig = field(default_factory=PlannerConfig)

    def __post_init__(self) -> None:
        if self.waypoint_source not in WAYPOINT_SOURCES:
            raise ValueError(f"unknown waypoint source {self.waypoint_source!r}; valid: {', '.join(WAYPOINT_SOURCES)}")
        pr = self.protocol
        Timing(pr.control_period, pr.timeout, pr.divergence_check_period, pr.log_period).substeps(self.physics.timestep)
