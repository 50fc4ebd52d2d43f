"""The fully resolved configuration of one MRS-CWC trial."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from terrabench.config import Relation, check_fields, clock_relations, le, param
from terrabench.sim.physics import PhysicsConfig
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
    """Start, target, success and failure (spec section 2)."""

    start_xy: tuple[float, float] = param((0.0, 0.0), length=2, unit="m", doc="leader start; the chain trails along -x")
    target_xy: tuple[float, float] = param((9.0, -9.0), length=2, unit="m",
                                           doc="target; the released scenes use (9, -9)")
    drop_height: float = param(0.5, ge=0, unit="m",
                               doc="the leader is dropped this far above the highest sampled terrain point")
    drop_probe_x: tuple[float, ...] = param((0.34, 0.12, 0.0, -0.3, -0.6, -0.9, -1.2, -1.5), length=8, unit="m",
                                            doc="x positions sampled at the start y for the drop height")
    success_threshold: float = param(0.5, gt=0, unit="m", doc="XY leader-target distance that counts as arrival")
    timeout: float = param(1000.0, gt=0, unit="s", doc="simulated time limit")
    fall_z: float = param(-50.0, unit="m", doc="leader below this height has fallen off the world (any height)")
    control_period: float = param(0.025, gt=0, unit="s", doc="controller period")
    log_period: float = param(0.1, gt=0, unit="s",
                              doc="period of the stored leader time series (metrics use every control period)")
    divergence_check_period: float = param(0.5, gt=0, unit="s", doc="how often the state is checked for blow-up")
    start_jitter: float = param(0.05, ge=0, unit="m",
                                doc="seeds > 0 shift the start uniformly by up to this much in x and y; seed 0 is "
                                    "the released protocol exactly")
    stall_time: float = param(0.0, ge=0, unit="s",
                              doc="opt-in early stop (0 = off, the default): status stuck once the leader has moved "
                                  "less than stall_distance from where it last moved and d_min (the closest it has "
                                  "come to the target, which alone fixes NCR and success) has not improved by "
                                  "stall_distance for this long; checked every divergence_check_period; a stopped "
                                  "trial keeps its NCR, but a chain that stood still this long may in principle "
                                  "still break free later, so this changes outcomes (docs/mrs-cwc-findings.md)")
    stall_distance: float = param(0.05, gt=0, unit="m", doc="the movement / d_min improvement that counts as progress")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class MRSConfig:
    """Everything a trial needs besides (method, terrain, seed): MuJoCo options (``physics``),
    the robot (``chain``), the protocol, the control laws (``drive``, ``stiffness``,
    ``head_following``, ``follow``, ``waypoints``) and the waypoint source with our A* planner.

    Relations (checked by ``validate`` once every ``--set`` is applied): the soft stiffness is not
    above the stiff one and the latch releases below where it latches (the CWC law's hysteresis,
    paper eqs 10-12); the control period is a whole number of physics steps, and the divergence
    check and the stored series are not faster than the controller (both run at control instants).
    """

    relations: ClassVar[tuple[Relation, ...]] = (
        le("stiffness.k_low", "stiffness.k_high", "k_low is the soft stiffness; a stiffer one needs k_high raised too"),
        le("stiffness.latch_off", "stiffness.latch_on", "the latch releases below where it latches on"),
        *clock_relations(check="protocol.divergence_check_period"),
    )

    physics: PhysicsConfig = field(default_factory=PhysicsConfig)
    chain: ChainConfig = field(default_factory=ChainConfig)
    protocol: ProtocolConfig = field(default_factory=ProtocolConfig)
    drive: DriveConfig = field(default_factory=DriveConfig)
    stiffness: StiffnessLawConfig = field(default_factory=StiffnessLawConfig)
    head_following: HeadFollowingConfig = field(default_factory=HeadFollowingConfig)
    follow: FollowConfig = field(default_factory=FollowConfig)
    waypoints: WaypointConfig = field(default_factory=WaypointConfig)
    waypoint_source: str = param("released", choices=WAYPOINT_SOURCES,
                                 doc="waypoints: released (the benchmark's CSV) or planner (our A*)")
    planner: PlannerConfig = field(default_factory=PlannerConfig)

    def __post_init__(self) -> None:
        check_fields(self)
