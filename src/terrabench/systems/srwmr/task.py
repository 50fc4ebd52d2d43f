"""One HIT-MRII episode as a hallway :class:`~terrabench.systems.base.Task`.

The wheels stand on soil: their rigid contact with the ground is off and
:class:`terrabench.soil.SoilWheels` writes the terramechanics forces every physics step
(``before_substep``); they still collide with rigid obstacles. Ground truth is used here only
for stop checks, logging and metrics (never by the controller).
"""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numba
import numpy as np

from terrabench.sim.checks import past_goal, requested_stop, turned_over
from terrabench.sim.episode import Timing
from terrabench.soil import SoilWheels, flat_ground, hfield_ground
from terrabench.soil.presets import HIT_MRII_WHEEL
from terrabench.soil.table import cached_table
from terrabench.systems.base import TaskBase
from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.config import SRWMRConfig
from terrabench.systems.srwmr.kinematics import delta_for_clearance
from terrabench.systems.srwmr.layouts import Layout, layout, start_burial, time_limit
from terrabench.systems.srwmr.legged import apply_clutch
from terrabench.systems.srwmr.methods import METHODS
from terrabench.systems.srwmr.motors import HIT_MRII
from terrabench.systems.srwmr.robot import (
    LINK_BIT,
    SIDES,
    WHEEL_BIT,
    WHEELS,
    Names,
    add_robot,
    wheel_bodies,
)
from terrabench.systems.srwmr.sensing import Observation
from terrabench.systems.srwmr.soils import srwmr_soil
from terrabench.terrain.mjcf import add_heightfield, ground_material

COLUMNS = (
    ("x", "y", "z", "yaw", "pitch", "roll", "v", "v_cmd", "delta_L", "delta_R", "mode", "step", "slip", "sinkage")
    + tuple(f"W_{c}" for c in WHEELS)
    + ("DP", "P_drive")
    + tuple(f"DP_{c}" for c in WHEELS)  # per-wheel drawbar pull (N): the PC = DP / W of Tasks 12, 13
    + tuple(f"Wft_{c}" for c in WHEELS)  # F/T wheel-load estimates (N): also a wheel on a rigid step
    + tuple(f"eta_{n}" for n in mc.NAMES)
    + ("v_lat", "vy_cmd", "wz", "wz_cmd")
)
_NC = len(COLUMNS)
_ETA = slice(COLUMNS.index("eta_MC2"), COLUMNS.index("eta_MC2") + len(mc.NAMES))
_ETA_START, _ETA_END = _ETA.start, _ETA.stop  # v_lat, vy_cmd, wz, wz_cmd follow the ratios
assert COLUMNS[12:14] == ("slip", "sinkage") and COLUMNS[20:22] == ("DP", "P_drive") and COLUMNS[22] == "DP_c1"
assert COLUMNS[_ETA_END:] == ("v_lat", "vy_cmd", "wz", "wz_cmd")


#: a completed plan counts as reaching the goal line within this (m)
GOAL_TOL = 0.05
_NO_U = np.zeros(5)
_NO_RATIOS = np.zeros(len(mc.NAMES))


@numba.njit(cache=True)
def _row_kernel(p, qvel, rpy, delta, slip, sink, fn, dp, force, vel, drive, load, ratios, u, mode, step, has_cmd):
    """One log row (:data:`COLUMNS`): the expressions of the oracle ``row_reference``
    (tests/srwmr/srwmr_reference.py) on scalars, sums over the six wheels one after the other from
    0 (numpy's order for six values)."""
    out = np.empty(_NC)
    out[0], out[1], out[2] = p[0], p[1], p[2]
    yaw = rpy[2]
    c, s = math.cos(yaw), math.sin(yaw)
    out[3], out[4], out[5] = yaw, rpy[1], rpy[0]
    out[6] = c * qvel[0] + s * qvel[1]
    out[8], out[9] = delta[0], delta[1]
    s_slip = s_sink = s_dp = s_pow = 0.0
    n_in = 0
    for i in range(6):
        if sink[i] > 0.0:  # slip and sinkage are the soil's: a wheel out of the soil (lifted) has neither
            s_slip += slip[i]
            s_sink += sink[i]
            n_in += 1
        s_dp += dp[i]
        s_pow += abs(force[drive[i]] * vel[drive[i]])
        out[14 + i] = fn[i]
        out[22 + i] = dp[i]
        out[28 + i] = load[i]
    out[12] = s_slip / n_in if n_in else np.nan
    out[13] = s_sink / n_in if n_in else np.nan
    out[20] = s_dp
    out[21] = s_pow
    for i in range(_ETA_END - _ETA_START):
        out[_ETA_START + i] = ratios[i] if has_cmd else np.nan
    out[_ETA_END] = -s * qvel[0] + c * qvel[1]
    out[_ETA_END + 2] = qvel[5]
    if has_cmd:
        out[7], out[10], out[11] = u[0], mode, step
        out[_ETA_END + 1], out[_ETA_END + 3] = u[1], u[2]
    else:
        out[7] = out[10] = out[11] = out[_ETA_END + 1] = out[_ETA_END + 3] = np.nan
    return out


@numba.njit(cache=True)
def _abs_power_kernel(force, vel):
    """sum |force * velocity| over the actuators (W) in numpy's order for up to 128 values (one
    after the other below 8, else 8 partial sums, then the rest), so bitwise
    ``np.abs(force * vel).sum()`` (tested); :meth:`SRWMRTask.power` takes numpy beyond 128."""
    n = force.shape[0]
    p = np.empty(n)
    for i in range(n):
        p[i] = abs(force[i] * vel[i])
    if n < 8:
        res = 0.0
        for i in range(n):
            res += p[i]
        return res
    r = p[:8].copy()
    i = 8
    while i < n - (n % 8):
        for j in range(8):
            r[j] += p[i + j]
        i += 8
    res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
    while i < n:
        res += p[i]
        i += 1
    return res


def trial_soil(name: str, cfg: SRWMRConfig, seed: int):
    """The soil of a trial: the named one, k_phi scaled, seeds > 0 jittered within the bound."""
    s = srwmr_soil(name)
    f_k, f_K = cfg.soil.k_phi_scale, 1.0
    if seed and cfg.soil.jitter:
        rng = np.random.default_rng(10_000 + seed)
        j = cfg.soil.jitter
        f_k *= 1.0 + rng.uniform(-j, j)
        f_K *= 1.0 + rng.uniform(-j, j)
    if f_k == 1.0 and f_K == 1.0:
        return s
    return dataclasses.replace(s, name=f"{s.name}~{seed}", k_phi=s.k_phi * f_k, K=s.K * f_K)


class SRWMRTask(TaskBase):
    """The rover driven by the scripted operator's plan on one instance."""

    columns = COLUMNS

    def __init__(self, method: str, instance: str, cfg: SRWMRConfig, seed: int = 0):
        self.method, self.instance, self.cfg, self.seed = method, instance, cfg, seed
        self.layout: Layout = layout(instance, method, cfg.robot, cfg.scene.approach, cfg.scene.lift)
        pr = cfg.protocol
        self.physics = cfg.physics
        self.goal_line = METHODS[method].goal_line
        self.timing = Timing(pr.control_period, time_limit(cfg, instance, method), pr.check_period, pr.log_period)
        self.soil = trial_soil(cfg.soil.preset or self.layout.soil, cfg, seed)
        rng = np.random.default_rng(seed)
        sc = cfg.scene
        if seed:
            self.start = (
                rng.uniform(-sc.start_jitter, sc.start_jitter),
                rng.uniform(-sc.start_jitter, sc.start_jitter),
                math.radians(rng.uniform(-sc.yaw_jitter_deg, sc.yaw_jitter_deg)),
            )
        else:
            self.start = (0.0, 0.0, 0.0)
        self.rng = np.random.default_rng(1_000_000 + seed)
        self.delta0 = delta_for_clearance(cfg.robot, sc.clearance)
        self.last_cmd = None
        # clips look along the axles from the robot's right, nearly level: lifts, sinkage and the
        # rocker's closing read in profile (report.render.camera_of)
        self.camera = {"azimuth": 90.0 + math.degrees(self.start[2]), "elevation": -6.0}

    # ------------------------------------------------------------------ scene
    def build(self, spec: mujoco.MjSpec) -> None:
        lay, r = self.layout, self.cfg.robot
        spec.modelname = f"srwmr_{self.instance}"
        prof = lay.profile
        self.flat = all(abs(z - prof[0][1]) < 1e-12 for _, z in prof) and lay.cross_deg == 0.0
        if self.flat:
            spec.worldbody.add_geom(
                name="ground",
                type=mujoco.mjtGeom.mjGEOM_PLANE,
                size=[40, 40, 0.1],
                pos=[0, 0, prof[0][1]],
                contype=0,
                conaffinity=LINK_BIT,
                material=ground_material(spec),
            )
        else:
            # a ramp, a pit or a cross slope: one heightfield (20 mm along x, 0.5 m along y: both
            # linear between the vertices) for the soil and the rigid links
            x = np.arange(-4.0, 9.0 + 1e-9, 0.02)
            y = np.linspace(-2.5, 2.5, 11)
            z = np.interp(x, [p[0] for p in prof], [p[1] for p in prof])
            h = np.repeat(z[:, None], len(y), axis=1)
            if lay.cross_deg:
                h = h + math.tan(math.radians(lay.cross_deg)) * y[None, :]
            g = add_heightfield(spec, h, x, y, name="ground", friction=0.8)
            g.contype, g.conaffinity = 0, LINK_BIT
            g.material = ground_material(spec)
        for i, (cx, cy, hx, hy, hz) in enumerate(lay.boxes):
            zb = float(np.interp(cx, [p[0] for p in prof], [p[1] for p in prof]))
            spec.worldbody.add_geom(
                name=f"obstacle_{i}",
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[hx, hy, hz],
                pos=[cx, cy, zb + hz],
                contype=0,
                conaffinity=LINK_BIT | WHEEL_BIT,
                friction=[0.8, 0.005, 0.0001],
                rgba=[0.55, 0.3, 0.25, 1],
            )
        spec.worldbody.add_light(pos=[0, 0, 5], dir=[0, 0, -1])
        self.table = cached_table(self.soil, HIT_MRII_WHEEL)
        self.z_sink = self.table.static_sinkage(r.total_mass * 9.81 / 6)
        # a buried start (scene.burial, T4): each wheel settled in a rut that deep less the static
        # sinkage, carved under its hub by the soil hook (bind); the robot stands that much lower
        burial = start_burial(self.cfg, self.instance, self.method)
        self.rut = max(burial - self.z_sink, 0.0)
        x0, y0, yaw = self.start
        hz = r.hinge_height - self.z_sink + (self.cfg.scene.clearance - r.clearance)
        z = lay.z0 + hz + 0.002
        if self.rut > 0.0:
            z -= self.rut
        cross = math.radians(lay.cross_deg)
        if cross:
            # on a cross slope the rover stands on the slope's plane: rolled by its angle, the
            # chassis centre the same distance from the plane as from flat ground
            z = lay.z0 + math.tan(cross) * y0 + (z - lay.z0) / math.cos(cross)
        add_robot(spec, (x0, y0, z), yaw, r, roll=cross)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> Observation:
        self.model, self.data = model, data
        r = self.cfg.robot
        d0 = self.delta0
        for s in SIDES:
            data.qpos[model.joint(Names.rocker(s)).qposadr[0]] = -d0
            data.qpos[model.joint(Names.front(s)).qposadr[0]] = r.z_ratio * d0
            data.qpos[model.joint(Names.bogie(s)).qposadr[0]] = d0
        mujoco.mj_forward(model, data)
        ground = flat_ground(self.layout.profile[0][1]) if self.flat else hfield_ground(model, "ground")
        rut = getattr(self, "rut", 0.0)  # set by build (a subclass with its own scene has none)
        self.soil_wheels = SoilWheels(
            model,
            data,
            wheel_bodies(),
            HIT_MRII_WHEEL,
            self.table,
            ground,
            v_eps=self.cfg.soil.v_eps,
            every=self.cfg.soil.every,
            refresh=self.cfg.soil.refresh,
            footing=self.cfg.soil.footing,
            ruts=rut if rut > 0.0 else None,
            rut_behind=self.cfg.soil.rut_behind,
        )
        model.geom_contype[[model.geom(Names.wheel(c)).id for c in WHEELS]] = WHEEL_BIT
        self.before_substep = self.soil_wheels.before_substep
        self.a_steer = np.array([model.actuator(Names.steer(c)).id for c in WHEELS])
        self.a_drive = np.array([model.actuator(Names.drive(c)).id for c in WHEELS])
        self.a_rock = np.array([model.actuator(Names.rocker(s)).id for s in SIDES])
        data.ctrl[self.a_rock] = -d0
        self.chassis = model.body(Names.CHASSIS).id
        self._act_force, self._act_vel = data.actuator_force, data.actuator_velocity  # views, fixed buffers
        self._groups = {"drive": self.a_drive, "steer": self.a_steer, "rocker": self.a_rock}
        self.energy_elec = 0.0  # J of electrical input (motors.HIT_MRII), summed by power()
        self.energy_elec_steps: dict[int, float] = {}  # the same per plan step (T2, T8, T10 periods)
        self.obs = Observation(model, data, self.rng)
        self.clutch = (False, False)
        self.x_start = float(data.xpos[self.chassis, 0])
        self.z_start = float(data.xpos[self.chassis, 2])
        return self.obs

    # ------------------------------------------------------------------ loop
    def observe(self) -> Observation:
        return self.obs.refresh()

    def check(self, obs: Observation, slow: bool):
        over = turned_over(obs.rpy[0], obs.rpy[1], self.cfg.protocol.turn_over)
        if over is not None:
            return over
        x = float(self.data.xpos[self.chassis, 0])
        goal = self.layout.goal_x
        cmd = self.last_cmd
        stop = requested_stop(None if cmd is None else cmd.stop, x, goal, GOAL_TOL)
        if stop is not None:
            return stop
        return past_goal(x, goal) if self.goal_line else None

    def apply(self, cmd) -> None:
        d = self.data
        d.ctrl[self.a_steer] = cmd.steer
        d.ctrl[self.a_drive] = cmd.spin
        d.ctrl[self.a_rock] = -cmd.delta
        cl = getattr(cmd, "clutch", None)
        if cl is not None and tuple(cl) != self.clutch:
            self.clutch = apply_clutch(self.model, d, cl, self.clutch)  # SWLM / DWLM (legged.py)
        self.last_cmd = cmd

    def row(self, obs: Observation, cmd) -> np.ndarray:
        """The stored columns (:data:`COLUMNS`) of this instant, filled by one compiled kernel
        (:func:`_row_kernel`; bitwise the oracle ``row_reference``, tested)."""
        d, t = self.data, self.soil_wheels.truth
        if cmd is None:
            u, ratios, mode, step, has = _NO_U, _NO_RATIOS, 0.0, 0.0, False
        else:
            u, ratios, mode, step, has = cmd.u, cmd.ratios, float(cmd.mode), float(getattr(cmd, "step", np.nan)), True
        return _row_kernel(d.xpos[self.chassis], d.qvel, obs.rpy, obs.delta, t["slip"], t["sinkage"], t["Fn"],
                           t["DP"], d.actuator_force, d.actuator_velocity, self.a_drive, obs.load,
                           np.asarray(ratios, float), np.asarray(u, float), mode, step, has)

    def power(self, obs) -> float:
        """Electrical power proxy: sum |force x velocity| over the actuators (W), compiled
        (:func:`_abs_power_kernel`, bitwise ``np.abs(force * velocity).sum()``)."""
        f, v = self._act_force, self._act_vel
        # the loop calls power() once per control period: the electrical input of the named motors
        # (motors.HIT_MRII: winding loss, no-load current, gear efficiency; no regeneration) is
        # summed here beside the mechanical figure the loop integrates
        e = self.timing.control_period * float(HIT_MRII.power_of(f, v, self._groups))
        self.energy_elec += e
        k = getattr(self.last_cmd, "step", None)
        if k is not None and k == k:  # a plan step (not NaN)
            self.energy_elec_steps[int(k)] = self.energy_elec_steps.get(int(k), 0.0) + e
        if f.shape[0] > 128:  # numpy's sum splits in halves there (the kernel does not)
            return float(np.abs(f * v).sum())
        return float(_abs_power_kernel(f, v))

    def metrics(self, log) -> dict[str, float]:
        from terrabench.systems.srwmr.metrics import episode_metrics

        out = episode_metrics(log, self.x_start, self.z_start, self.cfg.scales.w_fmr_centre)
        out["energy_elec_kJ"] = self.energy_elec / 1000.0
        for k, e in sorted(self.energy_elec_steps.items())[:8]:  # the steps episode_metrics reports
            out[f"step{k}_energy_elec_kJ"] = e / 1000.0
        return out

    def info(self) -> dict:
        return {
            "soil": self.soil.name,
            "k_phi": self.soil.k_phi,
            "K": self.soil.K,
            "goal_x": self.layout.goal_x,
            "slope_deg": self.layout.slope_deg,
            "cross_deg": self.layout.cross_deg,
            "note": self.layout.note,
            "timestep": self.physics.timestep,
        }
