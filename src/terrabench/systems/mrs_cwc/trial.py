"""One MRS-CWC trial: build the scene, run the control loop, score the leader's path."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable

import mujoco
import numpy as np

from terrabench.metrics.navigation import navigation_metrics
from terrabench.sim.physics import diverged
from terrabench.systems.mrs_cwc import control as ctl
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import BODY_LAWS, Method
from terrabench.systems.mrs_cwc.robot import Names, add_chain
from terrabench.systems.mrs_cwc.sensing import Observation
from terrabench.terrain import dataset, sine_sum
from terrabench.terrain.mjcf import add_heightfield

#: Columns of the stored leader time series.
TIMESERIES = ("t", "x", "y", "z", "K", "tau_env", "energy")


@dataclass
class Scene:
    """A compiled scene and the handles the loop needs."""

    model: mujoco.MjModel
    data: mujoco.MjData
    start_z: float
    wheel_act: np.ndarray  # (n, 2) actuator ids [left, right]
    yaw_joints: np.ndarray  # (n-1,) joint ids of the yaw hinges (empty for D)
    yaw_servos: np.ndarray  # (n-1,) actuator ids (MJ only)
    unit_bodies: np.ndarray  # (n,) body ids of the units
    unit_geoms: list[np.ndarray]  # per unit, the geoms of the unit and everything it carries


def build_scene(terrain: dataset.Terrain, method: Method, cfg: MRSConfig) -> Scene:
    """Terrain + chain of the method's link variant, dropped at the start (spec section 2)."""
    p = terrain.params
    spec = mujoco.MjSpec()
    spec.modelname = f"mrs_cwc_{method.variant}_{terrain.id}"
    cfg.physics.apply(spec)
    x, y = sine_sum.vertex_xy(p)
    add_heightfield(spec, sine_sum.heights(p), x, y)
    sx, sy = cfg.protocol.start_xy
    probe = sine_sum.point_height(p, np.asarray(cfg.protocol.drop_probe_x) + sx, np.full(len(cfg.protocol.drop_probe_x), sy))
    start_z = float(probe.max()) + cfg.protocol.drop_height
    add_chain(spec, method.variant, (sx, sy, start_z), cfg.chain)
    model = spec.compile()
    data = mujoco.MjData(model)
    n = cfg.chain.n_units
    wheel_act = np.array([[model.actuator(Names.motor(k, s)).id for s in Names.SIDES] for k in range(n)])
    if method.variant == "none":
        yaw_joints = yaw_servos = np.zeros(0, int)
    else:
        yaw_joints = np.array([model.joint(Names.link_joint(k, "yaw")).id for k in range(1, n)])
        yaw_servos = (
            np.array([model.actuator(Names.yaw_servo(k)).id for k in range(1, n)])
            if method.variant == "motor"
            else np.zeros(0, int)
        )
    unit_bodies = np.array([model.body(Names.unit(k)).id for k in range(n)])
    owner = {int(b): k for k, b in enumerate(unit_bodies)}
    unit_geoms: list[list[int]] = [[] for _ in range(n)]
    for g in range(model.ngeom):
        b = int(model.geom_bodyid[g])
        while b and b not in owner:  # walk up to the unit that carries this body
            b = int(model.body_parentid[b])
        if b:
            unit_geoms[owner[b]].append(g)
    mujoco.mj_forward(model, data)
    return Scene(model, data, start_z, wheel_act, yaw_joints, yaw_servos, unit_bodies,
                 [np.array(g, int) for g in unit_geoms])


def drop_fallen_units(scene: Scene, fall_z: float) -> None:
    """Units below ``fall_z`` slid off the terrain: they stop colliding and are parked.

    Without this, MRS-D followers that left the world fall for hundreds of seconds; at a
    million metres from the origin MuJoCo's global-frame arithmetic loses its precision and
    the state blows up (a false divergence). A fallen unit with its own free joint (MRS-D)
    is held 10 m below ``fall_z`` at rest; a chain's units go down with their leader, whose
    fall ends the trial.
    """
    m, d = scene.model, scene.data
    z = d.xpos[scene.unit_bodies, 2]
    for k in np.flatnonzero(z < fall_z):
        m.geom_contype[scene.unit_geoms[k]] = 0
        m.geom_conaffinity[scene.unit_geoms[k]] = 0
        b = scene.unit_bodies[k]
        j = m.body_jntadr[b]
        if j >= 0 and m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
            d.qpos[m.jnt_qposadr[j] + 2] = fall_z - 10.0
            d.qvel[m.jnt_dofadr[j] : m.jnt_dofadr[j] + 6] = 0.0


def make_controller(method: Method, cfg: MRSConfig, terrain: dataset.Terrain):
    """(guidance, body law) for a method. Only the A* methods receive terrain data."""
    n = cfg.chain.n_units
    if method.guidance == "tdt":
        guidance: ctl.Guidance = ctl.TargetDirection()
    else:
        guidance = ctl.WaypointGuidance(waypoints_for(terrain, cfg), cfg.waypoints)
    body: ctl.BodyLaw = BODY_LAWS[method.body](n, cfg)
    return guidance, body


def waypoints_for(terrain: dataset.Terrain, cfg: MRSConfig) -> np.ndarray:
    if cfg.waypoint_source == "released":
        return dataset.released_waypoints(terrain.id)
    from terrabench.systems.mrs_cwc.planner import plan_waypoints

    return plan_waypoints(terrain, cfg)


def run(method: Method, terrain: dataset.Terrain, cfg: MRSConfig,
        on_step: Callable[[Scene, Observation, ctl.Command, ctl.BodyLaw], None] | None = None):
    """Run one trial. Returns ``(status, metrics, timeseries, info)``.

    The loop runs the controller every control period and ``mj_step`` with ``nstep`` physics
    steps in between, so the engine does the inner loop in C. ``on_step(scene, obs, cmd,
    body)``, if given, is called once per control period after the command is applied (for
    studies that sample more than the stored series; it must not change the state).
    """
    wall0 = time.perf_counter()
    sc = build_scene(terrain, method, cfg)
    m, d = sc.model, sc.data
    pr = cfg.protocol
    guidance, body = make_controller(method, cfg, terrain)
    obs = Observation(m, d, cfg.chain.n_units, pr.target_xy)
    cmd = ctl.Command(cfg.chain.n_units)

    period = pr.control_period
    nsub = int(round(period / cfg.physics.timestep))
    n_max = int(math.ceil(pr.timeout / period)) + 1
    check_every = max(1, int(round(pr.divergence_check_period / period)))
    xyz = np.empty((n_max, 3))
    k_log = np.full(n_max, np.nan)
    tau_log = np.full(n_max, np.nan)
    e_log = np.empty(n_max)

    ctrl = d.ctrl
    wheel_act = sc.wheel_act
    wheel_speed, wheel_torque = obs.wheel_speed, obs.wheel_torque
    yaw_joints, yaw_servos = sc.yaw_joints, sc.yaw_servos
    has_servo = len(yaw_servos) > 0
    jnt_stiffness = m.jnt_stiffness
    err_max = cfg.chain.wheel_torque_limit / cfg.chain.wheel_kv
    tx, ty = pr.target_xy
    thr2 = pr.success_threshold**2
    energy = 0.0
    status, reason = "timeout", "time limit reached"
    k = 0
    engine_time = 0.0
    clock = time.perf_counter
    loop0 = clock()
    while True:
        obs.refresh()
        p = obs.pos[0]
        xyz[k] = p
        e_log[k] = energy
        if (p[0] - tx) ** 2 + (p[1] - ty) ** 2 < thr2:
            status, reason = "success", f"leader within {pr.success_threshold} m of the target"
            break
        if p[2] < pr.fall_z:
            status, reason = "fell", f"leader below z = {pr.fall_z} m"
            break
        if k % check_every == 0:
            drop_fallen_units(sc, pr.fall_z)
            why = diverged(m, d, cfg.physics.max_speed)
            if why:
                status, reason = "diverged", why
                break
        if k == n_max - 1:
            break
        body(obs, guidance.heading(obs), cmd)
        # the drive's torque limit, applied to the speed error the servo sees
        ctrl[wheel_act] = np.minimum(np.maximum(cmd.wheel_speed, wheel_speed - err_max), wheel_speed + err_max)
        if cmd.yaw_stiffness is not None:
            jnt_stiffness[yaw_joints] = cmd.yaw_stiffness
            k_log[k] = cmd.yaw_stiffness
        if has_servo:
            ctrl[yaw_servos] = cmd.yaw_target
        if on_step is not None:
            on_step(sc, obs, cmd, body)
        tau_log[k] = body.tau_env
        power = np.abs(wheel_torque * wheel_speed).sum()
        if has_servo:
            power += np.abs(obs.yaw_torque * obs.yaw_speed).sum()
        energy += period * power
        t_in = clock()
        mujoco.mj_step(m, d, nsub)
        engine_time += clock() - t_in
        k += 1
    loop_time = clock() - loop0

    n = k + 1
    metrics = navigation_metrics(xyz[:n], pr.target_xy, pr.start_xy, energy, pr.success_threshold)
    stride = max(1, int(round(pr.log_period / period)))
    idx = np.arange(0, n, stride)
    if idx[-1] != n - 1:
        idx = np.append(idx, n - 1)
    series = {
        "t": idx * period,
        "x": xyz[idx, 0],
        "y": xyz[idx, 1],
        "z": xyz[idx, 2],
        "K": k_log[idx],
        "tau_env": tau_log[idx],
        "energy": e_log[idx],
    }
    metrics["sim_time"] = k * period
    info = {
        "reason": reason,
        "success_threshold": pr.success_threshold,
        "start_z": sc.start_z,
        "control_steps": k,
        "physics_steps": k * nsub,
        "wall_time": time.perf_counter() - wall0,
        "loop_time": loop_time,
        "engine_time": engine_time,
    }
    return status, metrics, series, info
