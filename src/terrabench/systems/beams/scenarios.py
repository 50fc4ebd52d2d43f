"""Beam-traversal experiments as trials: planning specs, running them, the sense-estimate-plan-track
pipeline.

Scenario ids (all version 1) and their methods / instances:

* ``beams/estimation-v1`` (group ``estimation``): methods ``estimate-4``, ``estimate-3``,
  ``estimate-2`` (number of unknowns); instances ``sigma{5,10,20,50}-ts300`` (Tables 1-3) and
  ``sigma20-ts{50,100,600}`` (Table 4). One trial = one noise draw (status ``done``).
* ``beams/traversal-v1`` (group ``traversal``): methods ``interact`` (sense, estimate, plan on
  the landscape, track) and ``avoid`` (roll through the gap on a contact-free plan); instances
  ``stiff`` and ``flimsy``.
* ``beams/open-loop-v1`` (group ``open-loop``): method ``open-loop``; instances
  ``{stiff,flimsy}-f{0.1,1}`` (constant F_x after contact, Sec. III-A).
* ``beams/delay-v1`` (group ``delay``): method ``interact``; instances ``{stiff,flimsy}-d{100,300,600}``
  (sensory delay in ms, Sec. III-E).
* ``beams/experiment-v1`` (group ``experiment``): method ``estimate-ktau``; instances
  ``acrylic-sigma{0,10,20}`` (Sec. IV, eq. 12 on simulated data).
* ``beams/contact-check-v1`` (group ``contact-check``): method ``mujoco``; instances
  ``roll{R}-pitch{P}`` (MuJoCo cross-check of the contact model).
"""

from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.config import from_dict, override, to_dict

from .control import ControlConfig, TrackingController, energy_cost, hold_constant
from .estimation import (EstimatorConfig, SensingConfig, estimate, estimate_preload, relative_errors, sense,
                         sense_clean)
from .landscape import LandscapeConfig, build_landscape
from .model import (GRAVITY, Beam, BeamLayout, ModelConfig, RobotParams, SimulatedTimeout, critical_stiffness,
                    deflection_vec, first_contact_x, simulate)
from .mujoco_check import CheckConfig
from .planning import PlannerConfig, plan_path

SYSTEM_ID = "beams"

#: Beam stiffness pairs (N m/rad) per case. Stiff = the paper's estimation truth (Sec. III-B-i),
#: flimsy = k_low (Sec. III-A); the open-loop runs use k_high = 0.25 for both beams.
CASES = {"stiff": (0.25, 0.27), "flimsy": (0.01, 0.01)}
OPEN_LOOP_CASES = {"stiff": (0.25, 0.25), "flimsy": (0.01, 0.01)}

SCENARIOS = {
    "estimation": "beams/estimation-v1",
    "traversal": "beams/traversal-v1",
    "open-loop": "beams/open-loop-v1",
    "delay": "beams/delay-v1",
    "experiment": "beams/experiment-v1",
    "contact-check": "beams/contact-check-v1",
    "barriers": "beams/barriers-v1",
}
GROUPS = tuple(SCENARIOS)

METHODS = {
    "estimate-4": "Fit k1, k2, hb1, hb2 from noisy force data (Table 1)",
    "estimate-3": "Fit k1, k2 and a shared hb (Tables 2, 4)",
    "estimate-2": "Fit k1, k2 with hb = 0 known (Table 3)",
    "interact": "Sense, estimate (3 unknowns), plan on the energy landscape, track by feedback linearization",
    "avoid": "Obstacle avoidance: contact-free landscape plan (roll through the gap), same tracker",
    "open-loop": "Constant F_x after contact, no torques (Sec. III-A)",
    "estimate-ktau": "Physical-experiment variant: fit shared (k, tau0) with beam mass (eq. 12)",
    "mujoco": "Quasi-static pushes in MuJoCo vs the analytic contact model",
    "barriers": "Landscape pitch and roll barriers at k_low, k_high and the crossover stiffness vs the gap",
}
METHOD_GROUP = {
    "estimate-4": ("estimation",), "estimate-3": ("estimation",), "estimate-2": ("estimation",),
    "interact": ("traversal", "delay"), "avoid": ("traversal",), "open-loop": ("open-loop",),
    "estimate-ktau": ("experiment",), "mujoco": ("contact-check",), "barriers": ("barriers",),
}

EST_INSTANCES = [f"sigma{s}-ts300" for s in (5, 10, 20, 50)] + [f"sigma20-ts{t}" for t in (50, 100, 600)]
TRAVERSAL_INSTANCES = ["stiff", "flimsy"]
OPEN_LOOP_INSTANCES = [f"{c}-f{f}" for c in ("stiff", "flimsy") for f in ("0.1", "1")]
DELAY_INSTANCES = [f"{c}-d{d}" for c in ("stiff", "flimsy") for d in (100, 300, 600)]
EXPERIMENT_INSTANCES = [f"acrylic-sigma{s}" for s in (0, 10, 20)]
CONTACT_INSTANCES = [f"roll{r}-pitch{p}" for r, p in ((0, 0), (0, 20), (20, 0), (30, 10), (-15, 30))]
BARRIER_INSTANCES = [f"gap{g / 100:.2f}" for g in range(6, 15)]

INSTANCES = {
    "estimation": EST_INSTANCES, "traversal": TRAVERSAL_INSTANCES, "open-loop": OPEN_LOOP_INSTANCES,
    "delay": DELAY_INSTANCES, "experiment": EXPERIMENT_INSTANCES, "contact-check": CONTACT_INSTANCES,
    "barriers": BARRIER_INSTANCES,
}


@dataclass(frozen=True)
class ExperimentSetup:
    """The physical robot and beams of Sec. IV (values from the paper unless noted)."""

    a: float = 0.19
    """Robot semi-axis, m."""
    b: float = 0.09
    """Robot semi-axis, m."""
    c: float = 0.035
    """Robot semi-axis, m."""
    mass: float = 0.8
    """Robot mass, kg."""
    h_c: float = 0.003
    """Centre of mass below the geometric centre, m."""
    height: float = 0.07
    """Centre height above the beams' base, m (not given; chosen = 2c as in the simulated robot)."""
    length: float = 0.305
    """Beam height L, m."""
    width: float = 0.1
    """Beam width w, m."""
    gap: float = 0.15
    """Gap d, m."""
    beam_mass: float = 0.16
    """Beam mass M_B, kg."""
    k: float = 0.78
    """Stiffness of both beams, N m/rad."""
    tau0: float = 0.19
    """Preload torque of both beams, N m."""
    speed: float = 0.064
    """Constant carriage speed, m/s."""
    sensing_time: float = 0.3
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

    k1: float = 0.25
    """True stiffness of the left beam, N m/rad."""
    k2: float = 0.27
    """True stiffness of the right beam, N m/rad."""
    hb1: float = 0.0
    """True hinge height of the left beam, m."""
    hb2: float = 0.0
    """True hinge height of the right beam, m."""

    def __post_init__(self) -> None:
        for n in ("k1", "k2"):
            v = getattr(self, n)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"case.{n} = {v!r} N m/rad is invalid; stiffness must be >= 0")
        for n in ("hb1", "hb2"):
            if not np.isfinite(getattr(self, n)):
                raise ValueError(f"case.{n} = {getattr(self, n)!r} m is not finite")


@dataclass(frozen=True)
class SensingSection:
    """How the force data are collected (paper Secs. II-D, III-B)."""

    sigma: float = 0.2
    """Multiplicative force-noise standard deviation (eq. 6; 0.2 = 20 %)."""
    sensing_time: float = 0.3
    """Sensing window T_s, s (estimation and experiment; traversals use protocol.delay)."""
    push_force: float = 1.0
    """Open-loop F_x after contact while sensing (and in open-loop runs), N."""
    sample_rate: float = 100.0
    """Force-sensor sampling rate, Hz."""
    lookahead: float = 0.3
    """Extra simulated time after the window, only to check that contact goes on, s."""
    max_approach_time: float = 5.0
    """Give up looking for first contact after this long, s."""
    per_axis_noise: bool = True
    """Draw the noise Z independently per force axis (True) or once per sample (False)."""

    def __post_init__(self) -> None:
        if not (np.isfinite(self.sigma) and self.sigma >= 0):
            raise ValueError(f"sensing.sigma = {self.sigma!r} is invalid; noise must be >= 0 (0.2 = 20 %)")
        for n in ("sensing_time", "sample_rate", "max_approach_time"):
            v = getattr(self, n)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"sensing.{n} = {v!r} is invalid; it must be > 0")


@dataclass(frozen=True)
class PhysicsSection:
    """The analytic integrator (paper Sec. II-B)."""

    dt: float = 2e-4
    """Integration step, s."""
    gravity: float = GRAVITY
    """Gravitational acceleration, m/s^2."""
    pitch_axis: str = "generalized"
    """Axis of the pitch equation: "generalized" (world -y) or "principal" (body e2)."""
    min_lever: float = 1e-3
    """Smallest moment arm of a contact force about a hinge, m."""
    damping: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Viscous damping on (x, alpha, beta): N s/m, N m s/rad, N m s/rad (paper: none)."""

    def __post_init__(self) -> None:
        if not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"physics.dt = {self.dt!r} s is invalid; it must be > 0")


@dataclass(frozen=True)
class ProtocolSection:
    """What a trial does: strategy, timing, start and exit."""

    strategy: str = "interact"
    """"interact" or "avoid" (traversal)."""
    delay: float = 0.3
    """Sensory delay from first contact to active control, s (traversal; = its sensing window)."""
    t_max: float = 8.0
    """Simulated time after contact for open-loop runs, s."""
    settle_time: float = 1.0
    """Extra tracking time after the planned trajectory ends, s."""
    approach: float = 0.018
    """The level robot starts this far behind its first contact with the vertical beams, m; the
    start x is rounded to the mm (0.018 m gives the paper-era x = -0.08 m under the edge
    reading, where first contact is at x = -0.0618 m; -0.122 m under the centre reading)."""
    x_exit: float = 0.11
    """A traversal succeeds once x >= x_exit with no beam contact and a near-level pose, m."""
    roll_deg: float = 0.0
    """Contact check: roll held during the push, deg."""
    pitch_deg: float = 0.0
    """Contact check: pitch held during the push, deg."""
    timeout: float = 1000.0
    """Simulated-time cap of every run of a trial, s (``--timeout``); a trial stopped by it has
    status "timeout". The default never binds (the longest run lasts about 9 s)."""

    def __post_init__(self) -> None:
        if self.strategy not in ("interact", "avoid"):
            raise ValueError(f"protocol.strategy = {self.strategy!r}; valid: interact, avoid")
        for n in ("delay", "t_max", "timeout"):
            v = getattr(self, n)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"protocol.{n} = {v!r} s is invalid; it must be > 0")
        if not (np.isfinite(self.approach) and self.approach >= 0):
            raise ValueError(f"protocol.approach = {self.approach!r} m is invalid; it must be >= 0")


KINDS = ("estimation", "traversal", "open-loop", "experiment", "contact-check", "barriers")


@dataclass(frozen=True)
class TrialConfig:
    """Every knob of a beams trial, as nested sections (stored whole with each trial, hashed
    into its key, overridden with ``--set section.field=value``)."""

    kind: str = "traversal"
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
        if self.kind not in KINDS:
            raise ValueError(f"kind = {self.kind!r}; valid: {', '.join(KINDS)}")

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


# --------------------------------------------------------------------------- pipelines

def _downsample(log, every: int, t0: float = 0.0) -> dict[str, np.ndarray]:
    sl = slice(None, None, every)
    return {
        "t": log.t[sl] + t0, "x": log.q[sl, 0], "alpha": log.q[sl, 1], "beta": log.q[sl, 2],
        "vx": log.v[sl, 0], "omega1": log.v[sl, 1], "omega2": log.v[sl, 2],
        "Fx": log.u[sl, 0], "tau1": log.u[sl, 1], "tau2": log.u[sl, 2],
        "theta1": log.theta[sl, 0], "theta2": log.theta[sl, 1],
        "fx_beam": log.force[sl, 0], "fz_beam": log.force[sl, 2],
    }


def run_estimation(cfg: TrialConfig, rng: np.random.Generator, clean=None) -> TrialResult:
    """One noise draw of Tables 1-4: sense for T_s with F_x = push_force, fit, compare."""
    model = cfg.model()
    sensing = cfg.sensing_config(cfg.sensing.sensing_time)
    t0 = time.perf_counter()
    data = sense(model, sensing, rng, clean)
    est = estimate(data, model, cfg.estimator, rng)
    wall = time.perf_counter() - t0
    err = relative_errors(est.params, model.beams)
    metrics = {
        "k1_hat": est.params["k1"], "k2_hat": est.params["k2"],
        "hb1_hat_mm": est.params["hb1"] * 1e3, "hb2_hat_mm": est.params["hb2"] * 1e3,
        **err, "cost": est.cost, "n_samples": float(est.n_samples),
        "starts_near_best": float(est.starts_near_best),
    }
    ts = {"t": data.t - data.t_contact, "fx_clean": data.force_clean[:, 0], "fy_clean": data.force_clean[:, 1],
          "fz_clean": data.force_clean[:, 2], "fx": data.force[:, 0], "fy": data.force[:, 1], "fz": data.force[:, 2]}
    return TrialResult("done", metrics, ts, wall, {"t_contact": data.t_contact, "estimate_time_s": wall})


def run_open_loop(cfg: TrialConfig) -> TrialResult:
    """Sec. III-A: zero inputs until contact, then constant F_x and no torques."""
    model = cfg.model()
    p = cfg.protocol
    t0 = time.perf_counter()
    span = p.t_max + 1.0
    log = simulate(model, (cfg.x_start(), 0.0, 0.0), (model.robot.v0, 0.0, 0.0), min(span, p.timeout),
                   hold_constant(cfg.sensing.push_force), x_exit=p.x_exit,
                   stop=lambda t, q, v, tc: (not math.isnan(tc)) and t >= tc + p.t_max)
    status = {"passed": "success", "fell": "fell"}.get(log.outcome, "stuck")
    if status == "stuck" and log.outcome == "timeout" and p.timeout < span:
        status = "timeout"
    metrics = {
        "max_pitch_deg": float(np.degrees(log.q[:, 2].max())), "min_pitch_deg": float(np.degrees(log.q[:, 2].min())),
        "max_abs_roll_deg": float(np.degrees(np.abs(log.q[:, 1]).max())),
        "max_theta_deg": float(np.degrees(log.theta.max())), "final_x": float(log.q[-1, 0]),
        "t_end": float(log.t[-1]), "t_contact": float(log.t_contact),
        "time_in_contact_s": float(log.t[-1] - log.t_contact) if not math.isnan(log.t_contact) else 0.0,
    }
    return TrialResult(status, metrics, _downsample(log, 50), time.perf_counter() - t0, {"outcome": log.outcome})


def landscape_grid(cfg: TrialConfig) -> LandscapeConfig:
    """``cfg.landscape`` with x_min moved down (in whole dx steps) to the start x when the layout
    puts first contact so far back that the start lies behind the configured grid."""
    grid = cfg.landscape
    x0 = cfg.x_start()
    if x0 < grid.x_min:
        n = math.ceil((grid.x_min - x0) / grid.dx - 1e-9)
        grid = replace(grid, x_min=grid.x_min - n * grid.dx)
    return grid


def run_traversal(cfg: TrialConfig, rng: np.random.Generator) -> TrialResult:
    """The full pipeline: approach, (sense + estimate), landscape, Dijkstra, track; eq. 11 energy."""
    model = cfg.model()
    robot, layout = model.robot, model.layout
    p = cfg.protocol
    grid = landscape_grid(cfg)
    timings: dict[str, float] = {}
    t_all = time.perf_counter()
    info: dict[str, Any] = {"strategy": p.strategy}
    metrics: dict[str, float] = {}
    if p.strategy == "interact":
        sensing = cfg.sensing_config(p.delay)
        t0 = time.perf_counter()
        clean = sense_clean(model, sensing)
        data = sense(model, sensing, rng, clean)
        timings["sense_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        est = estimate(data, model, cfg.estimator, rng)
        timings["estimate_s"] = time.perf_counter() - t0
        believed = (Beam(max(est.params["k1"], 0.0), est.params["hb1"]),
                    Beam(max(est.params["k2"], 0.0), est.params["hb2"]))
        metrics.update({"k1_hat": est.params["k1"], "k2_hat": est.params["k2"],
                        "hb1_hat_mm": est.params["hb1"] * 1e3, "hb2_hat_mm": est.params["hb2"] * 1e3})
        pre = clean.log
        q_s, v_s = (np.asarray(v, float) for v in data.state_end)
        t_start = float(pre.t[-1])
        dtc = model.dt
        pre_work = float(np.maximum(pre.u[:-1, 0] * pre.v[:-1, 0], 0).sum() * dtc)
    else:
        believed = (Beam(0.0, model.beams[0].h_b), Beam(0.0, model.beams[1].h_b))
        pre = None
        q_s = np.array([cfg.x_start(), 0.0, 0.0])
        v_s = np.array([robot.v0, 0.0, 0.0])
        t_start, pre_work = 0.0, 0.0
        timings["sense_s"] = timings["estimate_s"] = 0.0
    t0 = time.perf_counter()
    ls = build_landscape(believed, robot, layout, grid)
    timings["landscape_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    planner = cfg.planner if p.strategy == "interact" else replace(cfg.planner, forbid_contact=True)
    plan = plan_path(ls, q_s, planner)
    timings["plan_s"] = time.perf_counter() - t0
    ctrl_cfg = cfg.control
    ctrl = TrackingController(plan, 0.0, believed, robot, layout, ctrl_cfg, model.gravity, model.pitch_axis)
    t0 = time.perf_counter()
    span = plan.duration + p.settle_time
    capped = p.timeout - t_start < span
    if p.timeout - t_start <= 0:
        raise SimulatedTimeout(f"sensing used the whole simulated-time cap of {p.timeout} s")
    log = simulate(model, q_s, v_s, min(span, p.timeout - t_start), ctrl, control_period=ctrl_cfg.period)
    timings["track_s"] = time.perf_counter() - t0
    timings["total_s"] = time.perf_counter() - t_all
    n_ctrl = int(round(ctrl_cfg.period / model.dt))
    e_ctrl = energy_cost(log.u[::n_ctrl], log.v[::n_ctrl], ctrl_cfg.period)
    touching = (log.theta[-1] > 0).any()
    qf = log.q[-1]
    if log.outcome == "fell":
        status = "fell"
    elif qf[0] >= p.x_exit and not touching and abs(qf[1]) < math.radians(10) and abs(qf[2]) < math.radians(10):
        status = "success"
    else:
        status = "timeout" if capped else "stuck"
    metrics.update({
        "energy_mJ": 1e3 * (e_ctrl + pre_work), "energy_control_mJ": 1e3 * e_ctrl, "energy_sensing_mJ": 1e3 * pre_work,
        "plan_rise_mJ": 1e3 * plan.rise, "plan_barrier_mJ": 1e3 * plan.barrier, "plan_duration_s": plan.duration,
        "mode_roll": 1.0 if plan.mode == "roll" else 0.0,
        "start_pitch_deg": float(np.degrees(q_s[2])), "start_roll_deg": float(np.degrees(q_s[1])),
        "start_x": float(q_s[0]),
        "max_abs_roll_deg": float(np.degrees(np.abs(log.q[:, 1]).max())),
        "max_pitch_deg": float(np.degrees(log.q[:, 2].max())),
        "max_theta_deg": float(np.degrees(log.theta.max())),
        "final_x": float(qf[0]),
        "track_rms_mm": float(1e3 * np.sqrt(np.mean([(q[0] - plan.desired(t)[0][0]) ** 2
                                                      for t, q in zip(log.t[::50], log.q[::50])]))),
    })
    info.update({"mode": plan.mode, "outcome": log.outcome, "path_len": int(len(plan.path)),
                 "plan_coeffs": plan.coeffs.tolist(), "believed": [[b.k, b.h_b] for b in believed]})
    ts = _downsample(log, 50, t_start)
    des = np.array([plan.desired(t)[0] for t in log.t[::50]])
    ts.update({"x_d": des[:, 0], "alpha_d": des[:, 1], "beta_d": des[:, 2]})
    if pre is not None:
        pre_ts = _downsample(pre, 50)
        pre_ts.update({"x_d": np.full(pre_ts["t"].size, np.nan), "alpha_d": np.full(pre_ts["t"].size, np.nan),
                       "beta_d": np.full(pre_ts["t"].size, np.nan)})
        ts = {k: np.concatenate([pre_ts[k][:-1], ts[k]]) for k in ts}
    path_ts_len = len(ts["t"])
    info["plan_path"] = plan.path[:: max(1, len(plan.path) // 400)].tolist()
    info["n_timesteps"] = path_ts_len
    info["wall_s"] = {k: float(v) for k, v in timings.items()}  # wall-clock, not results: kept out of metrics
    return TrialResult(status, metrics, ts, timings["total_s"], info)


# --------------------------------------------------------------------------- experiment variant

def run_experiment(cfg: TrialConfig, rng: np.random.Generator) -> TrialResult:
    """Sec. IV on simulated data: carriage-driven robot, fit shared (k, tau0) with eq. 12.

    The beams follow ``layout.gap_reading``; the robot starts 0.6 a behind the beam plane, or
    5 mm before first contact where that lies further back."""
    setup = cfg.experiment
    model = replace(setup.model(cfg.layout.gap_reading), dt=cfg.physics.dt)
    x0 = min(-(setup.a * 0.6), first_contact_x(model.robot, model.layout) - 0.005)
    sensing = SensingConfig(sigma=cfg.sensing.sigma, sensing_time=setup.sensing_time, drive_speed=setup.speed,
                            x_start=x0, timeout=cfg.protocol.timeout)
    t0 = time.perf_counter()
    data = sense(model, sensing, rng)
    est = estimate_preload(data, model, 0.0, setup.beam_mass, cfg.estimator.n_starts, rng)
    wall = time.perf_counter() - t0
    k, tau0 = est.params["k"], est.params["tau0"]
    metrics = {"k_hat": k, "tau0_hat": tau0, "e_k": abs(k - setup.k) / setup.k,
               "e_tau0": abs(tau0 - setup.tau0) / setup.tau0, "cost": est.cost, "n_samples": float(est.n_samples),
               "max_pitch_deg": float(np.degrees(np.abs(data.q[:, 2]).max()))}
    ts = {"t": data.t - data.t_contact, "fx": data.force[:, 0], "fz": data.force[:, 2],
          "fx_clean": data.force_clean[:, 0], "fz_clean": data.force_clean[:, 2],
          "alpha": data.q[:, 1], "beta": data.q[:, 2]}
    return TrialResult("done", metrics, ts, wall, {"paper_estimate": {"k": 0.67, "tau0": 0.21}})


# --------------------------------------------------------------------------- specs

def _instance_config(group: str, method: str, instance: str) -> dict[str, Any]:
    """The dotted settings an instance fixes (applied on top of the defaults, before ``--set``)."""
    if group == "estimation":
        sig, ts = instance.split("-")
        return {"kind": "estimation", "sensing.sigma": int(sig[5:]) / 100, "sensing.sensing_time": int(ts[2:]) / 1000,
                "estimator.n_unknowns": int(method.split("-")[1]), "sensing.push_force": 1.0}
    if group == "traversal":
        k1, k2 = CASES[instance]
        return {"kind": "traversal", "case.k1": k1, "case.k2": k2, "protocol.strategy": method,
                "sensing.push_force": 0.1, "protocol.delay": 0.3, "sensing.sigma": 0.2}
    if group == "delay":
        case, d = instance.split("-d")
        k1, k2 = CASES[case]
        return {"kind": "traversal", "case.k1": k1, "case.k2": k2, "protocol.strategy": "interact",
                "sensing.push_force": 0.1, "protocol.delay": int(d) / 1000, "sensing.sigma": 0.2}
    if group == "open-loop":
        case, f = instance.split("-f")
        k1, k2 = OPEN_LOOP_CASES[case]
        return {"kind": "open-loop", "case.k1": k1, "case.k2": k2, "sensing.push_force": float(f)}
    if group == "experiment":
        return {"kind": "experiment", "sensing.sigma": int(instance.split("sigma")[1]) / 100}
    if group == "contact-check":
        m = re.fullmatch(r"roll(-?[\d.]+)-pitch(-?[\d.]+)", instance)
        if not m:
            raise ValueError(f"contact-check instance {instance!r} must look like 'roll20-pitch-10'")
        return {"kind": "contact-check", "protocol.roll_deg": float(m.group(1)), "protocol.pitch_deg": float(m.group(2))}
    if group == "barriers":
        return {"kind": "barriers", "layout.gap": float(instance[3:])}
    raise ValueError(f"unknown group {group!r}; valid: {', '.join(GROUPS)}")


def normalize_overrides(overrides: dict[str, Any]) -> dict[str, Any]:
    """Dotted keys; a leading ``beams.`` is dropped and the old flat names map through ALIASES."""
    out = {}
    for k, v in overrides.items():
        k = k.split(".", 1)[1] if k.startswith("beams.") else k
        out[ALIASES.get(k, k)] = v
    return out


def build_config(group: str, method: str, instance: str, overrides: dict[str, Any] | None = None) -> TrialConfig:
    """The resolved config of one trial: defaults, then the instance's settings, then overrides."""
    cfg = override(TrialConfig(), _instance_config(group, method, instance))
    if overrides:
        cfg = override(cfg, normalize_overrides(overrides))
    return cfg


def plan_specs(*, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
               group: str | None = None, seeds: int = 1, overrides: dict[str, Any] | None = None) -> list[TrialSpec]:
    """Expand a request into trial specs (see the module docstring for ids)."""
    overrides = normalize_overrides(dict(overrides or {}))
    if overrides:
        override(TrialConfig(), overrides)  # validate keys and values early
    groups = GROUPS if group in (None, "all") else (group,)
    for g in groups:
        if g not in SCENARIOS:
            raise ValueError(f"unknown beams group {g!r}; valid: {', '.join(GROUPS)}, all")
    if methods:
        bad = [m for m in methods if m not in METHODS]
        if bad:
            raise ValueError(f"unknown beams method(s) {bad}; valid: {', '.join(METHODS)}")
    if instances:
        known = {i for g in GROUPS for i in INSTANCES[g]} | {"stiff", "flimsy"}
        bad = [i for i in instances if i not in known]
        if bad:
            raise ValueError(f"unknown beams instance(s) {bad}; valid: {', '.join(sorted(known))}")
    if seeds < 1:
        raise ValueError(f"seeds = {seeds}; it must be >= 1")
    specs = []
    for g in groups:
        for m in METHODS:
            if g not in METHOD_GROUP[m] or (methods and m not in methods):
                continue
            for inst in INSTANCES[g]:
                if instances and inst not in instances and not any(inst.startswith(i + "-") for i in instances):
                    continue
                cfg = build_config(g, m, inst, overrides)
                # noise-free or deterministic trials need one seed only
                deterministic = g in ("open-loop", "contact-check", "barriers") or m == "avoid" or \
                    (g == "experiment" and cfg.sensing.sigma == 0)
                for s in range(1 if deterministic else seeds):
                    specs.append(TrialSpec(SYSTEM_ID, SCENARIOS[g], m, inst, s, cfg.to_dict()))
    return specs


_CLEAN_CACHE: dict[str, Any] = {}


def run_barriers(cfg: TrialConfig) -> TrialResult:
    """Sec. II-G on the landscape at this layout: pitch and roll barriers at k_low and k_high and
    the landscape's own critical stiffness (where the two barriers are equal)."""
    from .landscape import critical_stiffness_landscape, pitch_roll_barriers
    t0 = time.perf_counter()
    grid, robot, layout = cfg.landscape, cfg.robot, cfg.layout
    metrics: dict[str, float] = {"gap": layout.gap, "inner_gap": layout.inner_gap}
    for name, k in (("low", CASES["flimsy"][0]), ("high", CASES["stiff"][0])):
        b = pitch_roll_barriers(k, robot, layout, grid)
        metrics[f"pitch_{name}_mJ"] = 1e3 * b["pitch"]
        metrics["roll_mJ"] = 1e3 * b["roll"]
    metrics["k_cross"] = critical_stiffness_landscape(robot, layout, grid)
    metrics["k0_formula"] = critical_stiffness(robot, layout)
    metrics["roll_clear_deg"] = roll_to_clear(robot, layout)
    return TrialResult("done", metrics, {}, time.perf_counter() - t0, {})


def roll_to_clear(robot: RobotParams, layout: BeamLayout) -> float:
    """Smallest |roll| (deg, 0.1 deg steps) at which the robot passes the vertical beams without contact
    at every x (pitch 0); NaN when no roll up to 90 deg does."""
    xs = np.linspace(-robot.a - 0.01, robot.a + 0.01, 121)
    for deg in np.arange(0.0, 90.01, 0.1):
        al = math.radians(deg)
        th = deflection_vec(xs, al, 0.0, 0.0, 0, robot, layout)
        th2 = deflection_vec(xs, al, 0.0, 0.0, 1, robot, layout)
        if not ((th > 0).any() or (th2 > 0).any()):
            return float(deg)
    return math.nan


_CLEAN_CACHE: dict[str, Any] = {}


def run_trial(spec: TrialSpec) -> TrialResult:
    """Run one beams trial; bad parameters and impossible requests come back as status "error",
    a run stopped by ``protocol.timeout`` as status "timeout"."""
    t0 = time.perf_counter()
    try:
        cfg = TrialConfig.from_dict(dict(spec.config))
        rng = np.random.default_rng([int(spec.seed), 4])
        if cfg.kind == "estimation":
            model = cfg.model()
            sensing = cfg.sensing_config(cfg.sensing.sensing_time)
            key = repr((model, replace(sensing, sigma=0.0)))
            if key not in _CLEAN_CACHE:
                if len(_CLEAN_CACHE) > 16:
                    _CLEAN_CACHE.clear()
                _CLEAN_CACHE[key] = sense_clean(model, sensing)
            res = run_estimation(cfg, rng, _CLEAN_CACHE[key])
        elif cfg.kind == "traversal":
            res = run_traversal(cfg, rng)
        elif cfg.kind == "open-loop":
            res = run_open_loop(cfg)
        elif cfg.kind == "experiment":
            res = run_experiment(cfg, rng)
        elif cfg.kind == "barriers":
            res = run_barriers(cfg)
        else:
            from .mujoco_check import run_contact_check
            res = run_contact_check(cfg)
    except SimulatedTimeout as exc:
        return TrialResult("timeout", {}, {}, time.perf_counter() - t0, {"reason": str(exc)})
    except (ValueError, TypeError) as exc:
        return TrialResult("error", {}, {}, time.perf_counter() - t0, {"error": str(exc)})
    res.wall_time = time.perf_counter() - t0
    res.info.setdefault("k0_formula", critical_stiffness())
    return res
