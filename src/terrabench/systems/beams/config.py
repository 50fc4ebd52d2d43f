"""The beams trial config: every knob of a trial as nested frozen sections (stored whole with
each trial, hashed into its key, overridden with ``--set section.field=value``), and the beam
cases the instances name."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from terrabench.config import check_fields, from_dict, param, to_dict

from .control import ControlConfig
from .estimation import EstimatorConfig, SensingConfig
from .landscape import LandscapeConfig
from .model import GRAVITY, Beam, BeamLayout, ModelConfig, RobotParams, first_contact_x
from .mujoco_check import CheckConfig
from .planning import PlannerConfig

#: Beam stiffness pairs (N m/rad) per case. Stiff = the paper's estimation truth (Sec. III-B-i),
#: flimsy = k_low (Sec. III-A); the open-loop runs use k_high = 0.25 for both beams.
CASES = {"stiff": (0.25, 0.27), "flimsy": (0.01, 0.01)}
OPEN_LOOP_CASES = {"stiff": (0.25, 0.25), "flimsy": (0.01, 0.01)}

@dataclass(frozen=True)
class ExperimentSetup:
    """The physical robot and beams of Sec. IV (values from the paper unless noted)."""

    a: float = param(0.19, gt=0, unit="m", doc="Robot semi-axis, m")
    """Robot semi-axis, m."""
    b: float = param(0.09, gt=0, unit="m", doc="Robot semi-axis, m")
    """Robot semi-axis, m."""
    c: float = param(0.035, gt=0, unit="m", doc="Robot semi-axis, m")
    """Robot semi-axis, m."""
    mass: float = param(0.8, gt=0, unit="kg", doc="Robot mass, kg")
    """Robot mass, kg."""
    h_c: float = param(0.003, ge=0, unit="m", doc="Centre of mass below the geometric centre, m")
    """Centre of mass below the geometric centre, m."""
    height: float = param(0.07, gt=0, unit="m", doc="Centre height above the beams' base, m (not given")
    """Centre height above the beams' base, m (not given; chosen = 2c as in the simulated robot)."""
    length: float = param(0.305, gt=0, unit="m", doc="Beam height L, m")
    """Beam height L, m."""
    width: float = param(0.1, gt=0, unit="m", doc="Beam width w, m")
    """Beam width w, m."""
    gap: float = param(0.15, gt=0, unit="m", doc="Gap d, m")
    """Gap d, m."""
    beam_mass: float = param(0.16, ge=0, unit="kg", doc="Beam mass M_B, kg")
    """Beam mass M_B, kg."""
    k: float = param(0.78, ge=0, unit="N m/rad", doc="Stiffness of both beams, N m/rad")
    """Stiffness of both beams, N m/rad."""
    tau0: float = param(0.19, ge=0, unit="N m", doc="Preload torque of both beams, N m")
    """Preload torque of both beams, N m."""
    speed: float = param(0.064, gt=0, unit="m/s", doc="Constant carriage speed, m/s")
    """Constant carriage speed, m/s."""
    sensing_time: float = param(0.3, gt=0, unit="s", doc="Force window used for the fit, s (not given")
    """Force window used for the fit, s (not given; chosen: the simulated passive robot, whose
    centre of mass is only 3 mm below its pivot, pitches past 90 deg ~0.31 s after contact)."""

    def model(self, gap_reading: str = "edge") -> ModelConfig:
        m = self.mass
        # solid-ellipsoid inertias: the paper gives none for the printed robot
        inertia = (m * (self.b ** 2 + self.c ** 2) / 5, m * (self.a ** 2 + self.c ** 2) / 5,
                   m * (self.a ** 2 + self.b ** 2) / 5)
        robot = RobotParams(a=self.a, b=self.b, c=self.c, mass=m, h_c=self.h_c, inertia=inertia,
                            height=self.height, v0=self.speed)
        layout = BeamLayout(gap=self.gap, width=self.width, length=self.length, gap_reading=gap_reading)
        beam = Beam(self.k, 0.0, self.tau0, self.beam_mass)
        return ModelConfig(robot=robot, layout=layout, beams=(beam, beam))


@dataclass(frozen=True)
class CaseSection:
    """The true beams of a trial (what the robot must find out)."""

    k1: float = param(0.25, ge=0, unit="N m/rad", doc="True stiffness of the left beam, N m/rad")
    """True stiffness of the left beam, N m/rad."""
    k2: float = param(0.27, ge=0, unit="N m/rad", doc="True stiffness of the right beam, N m/rad")
    """True stiffness of the right beam, N m/rad."""
    hb1: float = param(0.0, unit="m", doc="True hinge height of the left beam, m")
    """True hinge height of the left beam, m."""
    hb2: float = param(0.0, unit="m", doc="True hinge height of the right beam, m")
    """True hinge height of the right beam, m."""

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class SensingSection:
    """How the force data are collected (paper Secs. II-D, III-B)."""

    sigma: float = param(0.2, ge=0, doc="Multiplicative force-noise standard deviation (eq")
    """Multiplicative force-noise standard deviation (eq. 6; 0.2 = 20 %)."""
    sensing_time: float = param(0.3, gt=0, unit="s", doc="Sensing window T_s, s (estimation and experiment")
    """Sensing window T_s, s (estimation and experiment; traversals use protocol.delay)."""
    push_force: float = param(1.0, ge=0, unit="N",
                              doc="Open-loop F_x after contact while sensing (and in open-loop runs), N")
    """Open-loop F_x after contact while sensing (and in open-loop runs), N."""
    sample_rate: float = param(100.0, gt=0, unit="Hz", doc="Force-sensor sampling rate, Hz")
    """Force-sensor sampling rate, Hz."""
    lookahead: float = param(0.3, ge=0, unit="s",
                             doc="Extra simulated time after the window, only to check that contact goes on, s")
    """Extra simulated time after the window, only to check that contact goes on, s."""
    max_approach_time: float = param(5.0, gt=0, unit="s", doc="Give up looking for first contact after this long, s")
    """Give up looking for first contact after this long, s."""
    per_axis_noise: bool = param(True,
                                 doc="Draw the noise Z independently per force axis (True) or once per sample (False)")
    """Draw the noise Z independently per force axis (True) or once per sample (False)."""

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class PhysicsSection:
    """The analytic integrator (paper Sec. II-B)."""

    dt: float = param(2e-4, gt=0, unit="s", doc="Integration step, s")
    """Integration step, s."""
    gravity: float = param(GRAVITY, gt=0, unit="m/s^2", doc="Gravitational acceleration, m/s^2")
    """Gravitational acceleration, m/s^2."""
    pitch_axis: str = param("generalized", choices=("generalized", "principal"),
                            doc="Axis of the pitch equation: 'generalized' (world -y) or 'principal' (body e2)")
    """Axis of the pitch equation: "generalized" (world -y) or "principal" (body e2)."""
    min_lever: float = param(1e-3, gt=0, unit="m", doc="Smallest moment arm of a contact force about a hinge, m")
    """Smallest moment arm of a contact force about a hinge, m."""
    damping: tuple[float, float, float] = param((0.0, 0.0, 0.0), length=3, ge=0,
                                                doc="viscous damping on (x, alpha, beta): N s/m, N m s/rad, N m s/rad")
    """Viscous damping on (x, alpha, beta): N s/m, N m s/rad, N m s/rad (paper: none)."""

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class ProtocolSection:
    """What a trial does: strategy, timing, start and exit."""

    strategy: str = param("interact", choices=("interact", "avoid"), doc="'interact' or 'avoid' (traversal)")
    """"interact" or "avoid" (traversal)."""
    delay: float = param(0.3, gt=0, unit="s", doc="Sensory delay from first contact to active control, s (traversal")
    """Sensory delay from first contact to active control, s (traversal; = its sensing window)."""
    t_max: float = param(8.0, gt=0, unit="s", doc="Simulated time after contact for open-loop runs, s")
    """Simulated time after contact for open-loop runs, s."""
    settle_time: float = param(1.0, ge=0, unit="s", doc="Extra tracking time after the planned trajectory ends, s")
    """Extra tracking time after the planned trajectory ends, s."""
    approach: float = param(0.018, ge=0, unit="m",
                            doc="The level robot starts this far behind its first contact with the vertical beams, m")
    """The level robot starts this far behind its first contact with the vertical beams, m; the
    start x is rounded to the mm (0.018 m gives the paper-era x = -0.08 m under the edge
    reading, where first contact is at x = -0.0618 m; -0.122 m under the centre reading)."""
    x_exit: float = param(0.11, unit="m",
                          doc="A traversal succeeds once x >= x_exit with no beam contact and a near-level pose, m")
    """A traversal succeeds once x >= x_exit with no beam contact and a near-level pose, m."""
    roll_deg: float = param(0.0, ge=-90, le=90, unit="deg", doc="Contact check: roll held during the push, deg")
    """Contact check: roll held during the push, deg."""
    pitch_deg: float = param(0.0, ge=-90, le=90, unit="deg", doc="Contact check: pitch held during the push, deg")
    """Contact check: pitch held during the push, deg."""
    timeout: float = param(1000.0, gt=0, unit="s", doc="Simulated-time cap of every run of a trial, s (``--timeout``)")
    """Simulated-time cap of every run of a trial, s (``--timeout``); a trial stopped by it has
    status "timeout". The default never binds (the longest run lasts about 9 s)."""

    def __post_init__(self) -> None:
        check_fields(self)


KINDS = ("estimation", "traversal", "open-loop", "experiment", "contact-check", "barriers")


@dataclass(frozen=True)
class TrialConfig:
    """Every knob of a beams trial, as nested sections (stored whole with each trial, hashed
    into its key, overridden with ``--set section.field=value``)."""

    kind: str = param("traversal", choices=KINDS,
                      doc="'estimation', 'traversal', 'open-loop', 'experiment', 'contact-check' or 'barriers'")
    """"estimation", "traversal", "open-loop", "experiment", "contact-check" or "barriers"."""
    robot: RobotParams = field(default_factory=RobotParams)
    """The ellipsoid robot (paper Sec. II-A): semi-axes m, mass kg, h_c m, inertia kg m^2, ..."""
    layout: BeamLayout = field(default_factory=BeamLayout)
    """Beam positions and sizes (m) and the reading of the gap d (``layout.gap_reading``)."""
    case: CaseSection = field(default_factory=CaseSection)
    """The true beams."""
    sensing: SensingSection = field(default_factory=SensingSection)
    """Force sensing."""
    estimator: EstimatorConfig = field(default_factory=EstimatorConfig)
    """The eq.-7 fit (unknowns, starts, tolerances)."""
    landscape: LandscapeConfig = field(default_factory=LandscapeConfig)
    """The energy-landscape grid (x_min is extended down to the start x when that lies behind it)."""
    planner: PlannerConfig = field(default_factory=PlannerConfig)
    """Dijkstra and the trajectory fit (forbid_contact: the avoidance baseline)."""
    control: ControlConfig = field(default_factory=ControlConfig)
    """Feedback-linearising tracker (period s, omega_n rad/s, limits N, N m)."""
    physics: PhysicsSection = field(default_factory=PhysicsSection)
    """The integrator."""
    protocol: ProtocolSection = field(default_factory=ProtocolSection)
    """Strategy, timing, start, exit, the simulated-time cap."""
    check: CheckConfig = field(default_factory=CheckConfig)
    """MuJoCo cross-check pushes."""
    experiment: ExperimentSetup = field(default_factory=ExperimentSetup)
    """The physical setup of Sec. IV (experiment trials only)."""

    def __post_init__(self) -> None:
        check_fields(self)

    def to_dict(self) -> dict[str, Any]:
        return to_dict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "TrialConfig":
        return from_dict(cls, d)

    def model(self) -> ModelConfig:
        """The true physics model of this trial."""
        c, p = self.case, self.physics
        return ModelConfig(robot=self.robot, layout=self.layout,
                           beams=(Beam(c.k1, c.hb1), Beam(c.k2, c.hb2)), dt=p.dt, gravity=p.gravity,
                           pitch_axis=p.pitch_axis, min_lever=p.min_lever, damping=tuple(p.damping))

    def x_start(self) -> float:
        """Start x of the robot centre, m: ``protocol.approach`` behind first contact, to the mm."""
        return round(first_contact_x(self.robot, self.layout) - self.protocol.approach, 3)

    def sensing_config(self, sensing_time: float) -> SensingConfig:
        s = self.sensing
        return SensingConfig(sigma=s.sigma, sensing_time=sensing_time, sample_rate=s.sample_rate,
                             push_force=s.push_force, x_start=self.x_start(), lookahead=s.lookahead,
                             max_approach_time=s.max_approach_time, per_axis_noise=s.per_axis_noise,
                             timeout=self.protocol.timeout)


#: Old flat override names (before the nested config) -> dotted keys.
ALIASES = {
    "kind": "kind", "k1": "case.k1", "k2": "case.k2", "hb1": "case.hb1", "hb2": "case.hb2",
    "mass": "robot.mass", "gap": "layout.gap", "gap_reading": "layout.gap_reading", "sigma": "sensing.sigma",
    "sensing_time": "sensing.sensing_time", "push_force": "sensing.push_force", "delay": "protocol.delay",
    "n_unknowns": "estimator.n_unknowns", "n_starts": "estimator.n_starts", "strategy": "protocol.strategy",
    "t_max": "protocol.t_max", "settle_time": "protocol.settle_time", "x_exit": "protocol.x_exit",
    "omega_n": "control.omega_n", "dt": "physics.dt", "roll_deg": "protocol.roll_deg",
    "pitch_deg": "protocol.pitch_deg", "timeout": "protocol.timeout",
}
