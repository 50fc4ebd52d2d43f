"""Running one beams trial: the sense-estimate-plan-track pipeline and the other experiment kinds
(estimation, open loop, Sec. IV experiment, landscape barriers, MuJoCo contact check)."""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any

import numpy as np

from terrabench.benchmark.trial import TrialResult, TrialSpec

from .config import CASES, TrialConfig
from .control import TrackingController, energy_cost, hold_constant
from .estimation import SensingConfig, estimate, estimate_preload, relative_errors, sense, sense_clean
from .landscape import LandscapeConfig, build_landscape
from .model import (
    Beam,
    BeamLayout,
    RobotParams,
    SimulatedTimeout,
    critical_stiffness,
    deflection_vec,
    first_contact_x,
    simulate,
)
from .planning import plan_path

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
