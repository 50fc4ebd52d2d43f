"""The fully resolved configuration of one HIT-MRII trial (nested frozen dataclasses)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from terrabench.config import Relation, check_fields, clock_relations, ordered, param, relation
from terrabench.sim.physics import PhysicsConfig
from terrabench.systems.srwmr.constraints import ALLOWED_LIFTS, Scales
from terrabench.systems.srwmr.ik import IKLimits
from terrabench.systems.srwmr.kinematics import clearance_reach
from terrabench.systems.srwmr.robot import RobotConfig
from terrabench.systems.srwmr.soils import SOIL_NAMES


@dataclass(frozen=True)
class SupervisorConfig:
    """Supervisor and scripted-operator settings (sec. 7)."""

    reply_s: float | None = param(2.0, ge=0.0, le=600.0, unit="s", optional=True,
                                  doc="the scripted operator answers a reminder after this (null: never answers)")
    wait_s: float = param(10.0, gt=0.0, le=600.0, unit="s", doc="an unanswered reminder reverses the mode after this")
    eff_window: float = param(20.0, gt=0.0, le=600.0, unit="s", doc="climbing-efficiency window")
    eff_min: float = param(0.10, ge=0.0, le=1.0, doc="WRM -> RCM below this climbing efficiency [S 10 %]")
    health_slip: float = param(0.96, gt=0.0, le=1.0, doc="body-slip health limit [S 0.96]")
    health_s: float = param(5.0, gt=0.0, le=600.0, unit="s", doc="the health limit must hold this long")
    slip_tau: float = param(5.0, gt=0.0, le=600.0, unit="s", doc="time constant of the body-slip estimate")
    steer_tol: float = param(0.05, gt=0.0, le=1.0, unit="rad", doc="wheels roll once steering errors are below this")
    load_tau: float = param(0.2, ge=0.0, le=10.0, unit="s",
                            doc="time constant of a first-order filter on the F/T wheel-load estimates that "
                                "MC#10 / MC#11 read [R]: the monitors judge the load distribution 'under the "
                                "quasi-static balance' [S sec. 7.1], while the estimates swing by up to +-330 N for a "
                                "few 10 ms periods when a wheel set starts or stops and the soil's loads hold (T4 "
                                "RCM: W_fmr 760 N read against 323 N); 0.2 s passes a lift's load change (seconds) "
                                "and not those; 0 = each period's raw estimates (every result before 2026-12-07; "
                                "docs/srwmr.md, 'The load monitors read transients')")
    rcm_rim_ratio: float = param(7.0 / 3.6, ge=0.0, le=20.0,
                                 doc="RCM rolling-set rim speed per unit chassis vertical speed, a floor over "
                                     "the kinematic speed [S Task 4: '7.0 mm/s ... when the command velocity "
                                     "of the robot chassis is 3.6 mm/s'; the fitted linkage's own shrink per "
                                     "lift gives 1.26 of it (docs/srwmr.md), so the paper's command is kept; "
                                     "0: the kinematic speed only]")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class SoilConfig:
    """The soil under the wheels (terramechanics forces every physics step).

    ``preset`` empty: the instance's own soil (T1 very loose / loose, the others loose).
    """

    preset: str = param("", choices=("",) + SOIL_NAMES, doc="soil for every instance ('' = the instance's)")
    jitter: float = param(0.05, ge=0.0, le=0.3, doc="seeds > 0 scale k_phi and K by 1 +- this (uniform)")
    k_phi_scale: float = param(1.0, gt=0.2, le=5.0, doc="multiplies the soil's k_phi (study knob)")
    v_eps: float = param(0.004, gt=0.0, le=0.05, unit="m/s", doc="slip regularising speed of the soil hook")
    every: int = param(1, ge=1, le=4, doc="soil forces every k-th physics step")
    refresh: bool = param(True, choices=(True, False), doc="soil forces from the current (not one-step-old) velocities")
    footing: bool = param(True, choices=(True, False), doc="static footing of still wheels (docs/soil.md)")
    rut_behind: bool = param(False, choices=(True, False),
                             doc="a driven wheel whose hub does not advance feels no steady-state soil resistance "
                                 "pushing it back (its rut lies behind it); off: the forward-travel steady state at "
                                 "the clipped slip, which backs a wheel with no thrust to spare away at about its "
                                 "rim speed (docs/soil.md, 'Limitations'; off until the stored results are re-made)")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class SceneConfig:
    """Start pose and terrain pieces."""

    start_jitter: float = param(0.02, ge=0.0, le=0.2, unit="m", doc="seeds > 0 shift the start by up to this")
    yaw_jitter_deg: float = param(1.0, ge=0.0, le=10.0, unit="deg", doc="seeds > 0 turn the start by up to this")
    approach: float = param(0.6, ge=0.0, le=5.0, unit="m", doc="front wheels to the slope foot at the start")
    clearance: float = param(0.25, ge=0.15, le=0.55, unit="m", doc="start ground clearance [S 250 mm, 150-550 tested]")
    burial: float | None = param(None, ge=0.0, le=0.15, unit="m", optional=True,
                                 doc="start with every wheel sunk this deep below the undisturbed soil surface, "
                                     "settled in its own rut (the rut = this less the static sinkage; at or below "
                                     "the static sinkage: no rut); at most the wheel radius, the deepest sinkage "
                                     "the soil model represents; null = the instance's own (T4 0.15 [S Task 4 "
                                     "'all wheels are totally sunk'], every other 0: on the surface), written "
                                     "into the stored config at planning")
    lift: str = param("", choices=("",) + tuple("+".join(a) for a in ALLOWED_LIFTS),
                      doc="T12/T13 wheels lifted, MC#1 sets (SWLM one wheel, DWLM c1+c2 / c3+c4 / c5+c6); "
                          "'' = the instance's")

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class ProtocolConfig:
    """Clock and stop rules."""

    control_period: float = param(0.01, gt=0.0, le=0.1, unit="s", doc="controller period [S Ts = 0.01 s]")
    timeout: float | None = param(None, gt=0.0, le=20000.0, unit="s", optional=True,
                                  doc="simulated time limit; null = the instance's own, written into the "
                                      "stored config at planning (every trial carries a number)")
    log_period: float = param(0.5, gt=0.0, le=10.0, unit="s", doc="stored series period")
    check_period: float = param(1.0, gt=0.0, le=10.0, unit="s", doc="slow check period")
    turn_over: float = param(0.7, gt=0.1, le=1.5, unit="rad", doc="|roll| or |pitch| beyond this is turned_over")

    def __post_init__(self) -> None:
        check_fields(self)


def _within(x: float, bounds: tuple[float, float]) -> bool:
    return bounds[0] <= x <= bounds[1]


@dataclass(frozen=True)
class SRWMRConfig:
    """Everything a trial needs besides (method, instance, seed).

    Relations (checked by ``validate`` once every ``--set`` is applied): the rocker and the
    IK's delta ranges are (lower, upper) with lower < upper, the IK's inside the joint's stops, and
    the start clearance one the linkage reaches inside the IK's range; the
    control period is a whole number of physics steps, and the slow check and the stored series are
    not faster than the controller (both run at control instants).
    """

    relations: ClassVar[tuple[Relation, ...]] = (
        ordered("robot.rocker_range", strict=True, why="a joint range is (lower, upper)"),
        ordered("limits.delta_range", strict=True, why="a range is (lower, upper)"),
        relation(("limits.delta_range", "robot.rocker_range"), lambda d, q: -q[1] <= d[0] and d[1] <= -q[0],
                 "{0} must lie within the rocker joint's stops {1} read as closing angles (delta = -q)",
                 why="the IK may not command a closing angle the joint cannot reach"),
        relation(("scene.clearance", "limits.delta_range", "robot"), lambda c, d, r: _within(c, clearance_reach(r, d)),
                 "{0} must be a clearance the linkage reaches with closing angles inside {1}",
                 why="the start posture is solved for it; outside, the solver stops at its bracket's end",
                 detail=lambda c, d, r: "this linkage reaches %.3f-%.3f m" % clearance_reach(r, d)),
        *clock_relations(),
    )

    #: 0.25 ms: the soil force's stiffness below v_eps grows with the wheel's load, and the fitted linkage's
    #: middle wheels (577 N at rest, ~1,000 N in a legged lift) need it (docs/assumptions-srwmr.md, "Physics step")
    physics: PhysicsConfig = field(default_factory=lambda: PhysicsConfig(timestep=0.00025, iterations=30))
    robot: RobotConfig = field(default_factory=RobotConfig)
    soil: SoilConfig = field(default_factory=SoilConfig)
    scene: SceneConfig = field(default_factory=SceneConfig)
    protocol: ProtocolConfig = field(default_factory=ProtocolConfig)
    supervisor: SupervisorConfig = field(default_factory=SupervisorConfig)
    limits: IKLimits = field(default_factory=IKLimits)
    scales: Scales = field(default_factory=Scales)
