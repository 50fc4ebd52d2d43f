"""One MRS-CWC episode as a hallway :class:`~terrabench.systems.base.Task`.

The chain is dropped above the terrain at the start; it succeeds when the leader comes within
the threshold of the target, fails when the leader falls off the world; the time limit
truncates it. Metrics are the benchmark's NCR, NEF, NEC from the leader's path (spec section 5).
"""

from __future__ import annotations

import mujoco
import numpy as np

from terrabench.metrics.navigation import navigation_metrics
from terrabench.sim.checks import Stalled, fell
from terrabench.sim.episode import Timing
from terrabench.sim.scene import index_view, writer
from terrabench.systems.base import TaskBase
from terrabench.systems.mrs_cwc import control as ctl
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import BODY_LAWS, Method
from terrabench.systems.mrs_cwc.robot import Names, add_chain, drive_ref_dof
from terrabench.systems.mrs_cwc.sensing import Observation
from terrabench.terrain import dataset, sine_sum
from terrabench.terrain.mjcf import add_heightfield

#: Columns of the log (the loop adds ``energy``; the stored series has ``t`` first).
COLUMNS = ("x", "y", "z", "K", "tau_env")
#: Columns of the stored leader time series.
TIMESERIES = ("t",) + COLUMNS + ("energy",)


class MRSTask(TaskBase):
    """The chain of ``method``'s link variant on ``terrain`` under ``cfg``."""

    columns = COLUMNS

    def __init__(self, method: Method, terrain: dataset.Terrain, cfg: MRSConfig):
        self.method, self.terrain, self.cfg = method, terrain, cfg
        pr = cfg.protocol
        self.physics = cfg.physics
        self.timing = Timing(pr.control_period, pr.timeout, pr.divergence_check_period, pr.log_period)
        self.start_z = float("nan")

    # ------------------------------------------------------------------ scene
    def build(self, spec: mujoco.MjSpec) -> None:
        """Terrain + chain of the method's link variant, dropped at the start (spec section 2)."""
        p, cfg = self.terrain.params, self.cfg
        spec.modelname = f"mrs_cwc_{self.method.variant}_{self.terrain.id}"
        x, y = sine_sum.vertex_xy(p)
        add_heightfield(spec, sine_sum.heights(p), x, y)
        sx, sy = cfg.protocol.start_xy
        probe_x = np.asarray(cfg.protocol.drop_probe_x)
        probe = sine_sum.point_height(p, probe_x + sx, np.full(len(probe_x), sy))
        self.start_z = float(probe.max()) + cfg.protocol.drop_height
        add_chain(spec, self.method.variant, (sx, sy, self.start_z), cfg.chain)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> Observation:
        self.model, self.data = model, data
        n = self.cfg.chain.n_units
        self.wheel_act = np.array([[model.actuator(Names.motor(k, s)).id for s in Names.SIDES] for k in range(n)])
        if self.method.variant == "none":
            self.yaw_joints = self.yaw_servos = np.zeros(0, int)
        else:
            self.yaw_joints = np.array([model.joint(Names.link_joint(k, "yaw")).id for k in range(1, n)])
            self.yaw_servos = (np.array([model.actuator(Names.yaw_servo(k)).id for k in range(1, n)])
                               if self.method.variant == "motor" else np.zeros(0, int))
        self.unit_bodies = np.array([model.body(Names.unit(k)).id for k in range(n)])
        owner = {int(b): k for k, b in enumerate(self.unit_bodies)}
        unit_geoms: list[list[int]] = [[] for _ in range(n)]
        for g in range(model.ngeom):
            b = int(model.geom_bodyid[g])
            while b and b not in owner:  # walk up to the unit that carries this body
                b = int(model.body_parentid[b])
            if b:
                unit_geoms[owner[b]].append(g)
        self.unit_geoms = [np.array(g, int) for g in unit_geoms]
        pr = self.cfg.protocol
        self.obs = Observation(model, data, n, pr.target_xy)
        self._has_servo = len(self.yaw_servos) > 0
        ch = self.cfg.chain
        self._constraint_drive = ch.wheel_drive == "constraint"
        if self._constraint_drive:
            a = drive_ref_dof(model)
            self._ref_vel = data.qvel[a : a + 2 * n].reshape(n, 2)
        else:
            self._err_max = ch.wheel_torque_limit / ch.wheel_kv
        self._thr2 = pr.success_threshold ** 2
        wheels = index_view(data.ctrl, self.wheel_act)
        if not np.shares_memory(wheels, data.ctrl):  # add_chain adds the motors in this order
            raise ValueError(f"the wheel motors must be consecutive actuators, got ids {self.wheel_act.ravel()}")
        self._wheel_ctrl = wheels.reshape(n, 2)  # the clamp writes straight into data.ctrl
        self._set_stiffness = writer(model.jnt_stiffness, self.yaw_joints)
        self._set_yaw_targets = writer(data.ctrl, self.yaw_servos)
        self._power_buf = np.zeros((n, 2))
        # the opt-in stall stop (protocol.stall_time)
        self._stall = Stalled(pr.stall_time, pr.stall_distance) if pr.stall_time > 0 else None
        return self.obs

    # ------------------------------------------------------------------ loop
    def observe(self) -> Observation:
        return self.obs.refresh()

    def check(self, obs: Observation, slow: bool) -> tuple[str, str] | None:
        if obs.target_d2 < self._thr2:
            pr = self.cfg.protocol
            return "success", f"leader within {pr.success_threshold} m of the target"
        if obs.leader_z < self.cfg.protocol.fall_z:
            return fell(obs.leader_z, self.cfg.protocol.fall_z, "leader")
        if slow:
            self.drop_fallen_units(self.cfg.protocol.fall_z)
            if self._stall is not None:
                return self._stalled(obs)
        return None

    def _stalled(self, obs: Observation) -> tuple[str, str] | None:
        """``stuck`` per :class:`~terrabench.sim.checks.Stalled` on the leader's position and
        target distance. Checked on the slow period only. NCR, NEF's numerator and success
        depend on d_min alone, so a trial stopped here keeps its NCR; its journey, energy and
        NEC are those at the stop.
        """
        p = obs.pos[0]
        return self._stall(obs.t, float(p[0]), float(p[1]), obs.target_distance)

    def apply(self, cmd: ctl.Command) -> None:
        if self._constraint_drive:
            # the velocity constraint's reference; its frictionloss is the torque limit
            np.negative(cmd.wheel_speed, out=self._ref_vel)
        else:
            # the drive's torque limit, applied to the speed error the servo sees
            ws, err, out = self.obs.wheel_speed, self._err_max, self._wheel_ctrl
            np.minimum(np.maximum(cmd.wheel_speed, ws - err, out=out), ws + err, out=out)
        if cmd.yaw_stiffness is not None:
            self._set_stiffness(cmd.yaw_stiffness)
        if self._has_servo:
            self._set_yaw_targets(cmd.yaw_target)

    def row(self, obs: Observation, cmd: ctl.Command | None) -> tuple[float, ...]:
        p = obs.pos[0]
        if cmd is None:
            return p[0], p[1], p[2], np.nan, np.nan
        k = np.nan if cmd.yaw_stiffness is None else cmd.yaw_stiffness
        return p[0], p[1], p[2], k, cmd.tau_env

    def power(self, obs: Observation) -> float:
        buf = self._power_buf
        np.multiply(obs.wheel_torque, obs.wheel_speed, out=buf)
        power = np.abs(buf, out=buf).sum()
        if self._has_servo:
            power += np.abs(obs.yaw_torque * obs.yaw_speed).sum()
        return power

    def metrics(self, log) -> dict[str, float]:
        pr = self.cfg.protocol
        return navigation_metrics(log.block(("x", "y", "z")), pr.target_xy, pr.start_xy, log.energy,
                                  pr.success_threshold)

    def info(self) -> dict:
        return {"success_threshold": self.cfg.protocol.success_threshold, "start_z": self.start_z}

    # ------------------------------------------------------------------ housekeeping
    def drop_fallen_units(self, fall_z: float) -> None:
        """Units below ``fall_z`` slid off the terrain: they stop colliding and are parked.

        Without this, MRS-D followers that left the world fall for hundreds of seconds; at a
        million metres from the origin MuJoCo's global-frame arithmetic loses its precision and
        the state blows up (a false divergence). A fallen unit with its own free joint (MRS-D)
        is held 10 m below ``fall_z`` at rest; a chain's units go down with their leader, whose
        fall ends the trial.
        """
        m, d = self.model, self.data
        z = d.xpos[self.unit_bodies, 2]
        for k in np.flatnonzero(z < fall_z):
            m.geom_contype[self.unit_geoms[k]] = 0
            m.geom_conaffinity[self.unit_geoms[k]] = 0
            b = self.unit_bodies[k]
            j = m.body_jntadr[b]
            if j >= 0 and m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
                d.qpos[m.jnt_qposadr[j] + 2] = fall_z - 10.0
                d.qvel[m.jnt_dofadr[j]: m.jnt_dofadr[j] + 6] = 0.0


class MRSController:
    """Guidance (target direction or waypoints) + the method's body law: ``obs -> Command``."""

    def __init__(self, guidance: ctl.Guidance, body: ctl.BodyLaw, n_units: int):
        self.guidance, self.body = guidance, body
        self.cmd = ctl.Command(n_units)

    def __call__(self, obs: Observation) -> ctl.Command:
        cmd = self.cmd
        self.body(obs, self.guidance.heading(obs), cmd)
        cmd.tau_env = self.body.tau_env
        return cmd


def make_controller(method: Method, cfg: MRSConfig, terrain: dataset.Terrain) -> MRSController:
    """The controller of a method. Only the A* methods receive terrain data (their map)."""
    n = cfg.chain.n_units
    if method.guidance == "tdt":
        guidance: ctl.Guidance = ctl.TargetDirection()
    else:
        guidance = ctl.WaypointGuidance(waypoints_for(terrain, cfg), cfg.waypoints)
    return MRSController(guidance, BODY_LAWS[method.body](n, cfg), n)


def waypoints_for(terrain: dataset.Terrain, cfg: MRSConfig) -> np.ndarray:
    if cfg.waypoint_source == "released":
        return dataset.released_waypoints(terrain.id)
    from terrabench.systems.mrs_cwc.planner import plan_waypoints

    return plan_waypoints(terrain, cfg)


def run(method: Method, terrain: dataset.Terrain, cfg: MRSConfig, *, on_step=None):
    """One trial of ``method`` on any terrain (also one not in the dataset) -> TrialResult."""
    from terrabench.systems.base import run_task

    return run_task(MRSTask(method, terrain, cfg), make_controller(method, cfg, terrain), on_step=on_step)


def bound(method: Method, terrain: dataset.Terrain, cfg: MRSConfig) -> MRSTask:
    """A compiled, bound task at its start state (for tests and studies that poke the scene)."""
    from terrabench.sim.scene import compile_scene

    task = MRSTask(method, terrain, cfg)
    task.bind(*compile_scene(task))
    return task
