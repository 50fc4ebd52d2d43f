"""HIT-MRII in the zoo: the rover driving straight down the lane on soil (WRM, and WRM with the
supervisor's switch to RCM when the climbing efficiency drops).

The task is :class:`~terrabench.systems.srwmr.task.SRWMRTask` (soil forces every physics step,
the IK-driven plan, the rover's power, electrical energy and metrics) on the zoo's course with
the zoo's stop rules; the rover's own health halt (body slip) is its own stop rule
(:meth:`~terrabench.zoo.task.ZooRules.own_stop`). Its wheels touch the ground only through the
terramechanics model (their rigid contact with the ground is off), so the rigid families are
unsupported: srwmr's task has no rigid-ground mode to switch to.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from terrabench.sim.checks import Stalled, requested_stop
from terrabench.sim.episode import Timing
from terrabench.soil.presets import HIT_MRII_WHEEL
from terrabench.soil.table import cached_table
from terrabench.systems.srwmr.config import SRWMRConfig
from terrabench.systems.srwmr.control import RoverController
from terrabench.systems.srwmr.kinematics import delta_for_clearance
from terrabench.systems.srwmr.layouts import Layout
from terrabench.systems.srwmr.methods import METHODS
from terrabench.systems.srwmr.modes import Step
from terrabench.systems.srwmr.robot import LINK_BIT, RobotConfig, add_robot
from terrabench.systems.srwmr.task import GOAL_TOL, SRWMRTask, trial_soil
from terrabench.terrain.mjcf import add_heightfield
from terrabench.zoo.adapter import Footprint, ZooAdapter, register_adapter
from terrabench.zoo.families import FAMILIES
from terrabench.zoo.task import ZooRules, start_height

RIGID = ("the rover's wheels touch the ground only through the terramechanics model (srwmr.task turns their "
         "rigid ground contact off) and srwmr has no rigid-ground mode; rigid families need one")
#: the plan's WRM speed (m/s): the paper's 25 mm/s (srwmr.layouts' slope tasks)
SPEED = 0.025
#: the plan drives on this far past the point where the rear crosses the goal line (m)
PLAN_PAST = 0.5


class ZooSRWMRTask(ZooRules, SRWMRTask):
    """The rover on a zoo soil course, chassis nose at ``course.start_front``, heading +x."""

    def __init__(self, method: str, course: Any, cfg: SRWMRConfig, zoo: Any, footprint: Footprint, timeout: float,
                 seed: int = 0):
        self.method, self.cfg, self.seed = method, cfg, seed
        self.instance = f"{course.family}@{course.severity:g}"
        self.course, self.zoo, self.footprint = course, zoo, footprint
        r = cfg.robot
        y0 = self.start_y(seed)
        x0 = course.start_front - r.nose
        self.start = (x0, y0, 0.0)
        self.goal_chassis = course.goal_x + r.tail  # the chassis x when the rear wheels' edge crosses
        until = self.goal_chassis + PLAN_PAST - x0  # in the plan's start frame
        plan = (Step("WRM", v=SPEED, dist=until + 1.0, until_x=until, auto_rcm=method == "rcm"),)
        flat_z = course.floor_z if course.hfield is None else None
        profile = ((-50.0, flat_z), (50.0, flat_z)) if flat_z is not None else ((-50.0, 0.0), (50.0, 0.0))
        self.layout = Layout(profile, (), course.soil, plan, self.goal_chassis, note=course.note)
        pr = cfg.protocol
        self.physics = cfg.physics
        self.goal_line = METHODS[method].goal_line
        self.timing = Timing(pr.control_period, timeout, pr.check_period, pr.log_period)
        self.soil = trial_soil(course.soil, cfg, seed)
        self.rng = np.random.default_rng(1_000_000 + seed)
        self.delta0 = delta_for_clearance(r, cfg.scene.clearance)
        self.last_cmd = None
        self.zoo_init()

    def build(self, spec: mujoco.MjSpec) -> None:
        c, r, fp = self.course, self.cfg.robot, self.footprint
        spec.modelname = f"zoo_srwmr_{c.family}"
        self.flat = c.hfield is None
        if self.flat:
            spec.worldbody.add_geom(name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[40, 40, 0.1],
                                    pos=[0, 0, c.floor_z], contype=0, conaffinity=LINK_BIT,
                                    rgba=[0.72, 0.55, 0.38, 1])
        else:
            hf = c.hfield
            g = add_heightfield(spec, hf.h, hf.x, hf.y, name="ground", friction=self.zoo.course.friction)
            g.contype, g.conaffinity = 0, LINK_BIT
        spec.worldbody.add_light(pos=[0, 0, 5], dir=[0, 0, -1])
        self.table = cached_table(self.soil, HIT_MRII_WHEEL)
        self.z_sink = self.table.static_sinkage(r.total_mass * 9.81 / 6)
        x0, y0, yaw = self.start
        z0 = start_height(c, x0 - r.tail, x0 + r.nose, fp.width)
        hz = r.hinge_height - self.z_sink + (self.cfg.scene.clearance - r.clearance)
        add_robot(spec, (x0, y0, z0 + hz + 0.002), yaw, r)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData):
        obs = super().bind(model, data)
        self._zoo_mode = None
        return obs

    def rear_length(self) -> float:
        return self.cfg.robot.tail

    def check(self, obs: Any, slow: bool) -> tuple[str, str] | None:
        # a new mode (the supervisor's WRM -> RCM switch) gets its own stuck window: the creep
        # starts from rest, and the window that ran out in the slipping WRM is not its failure
        cmd = self.last_cmd
        mode = None if cmd is None else getattr(cmd, "mode", None)
        if mode != self._zoo_mode:
            self._zoo_mode = mode
            pr = self.zoo.protocol
            self._zoo_stall = Stalled(pr.stuck_time, pr.stuck_progress)
        return super().check(obs, slow)

    def own_stop(self, obs: Any, rear_x: float) -> tuple[str, str] | None:
        cmd = self.last_cmd
        if cmd is None or cmd.stop is None:
            return None
        return requested_stop(cmd.stop, float(self.data.xpos[self.chassis, 0]), self.goal_chassis, GOAL_TOL)

    def info(self) -> dict:
        own = SRWMRTask.info(self)
        own["goal_chassis"] = own.pop("goal_x")  # the chassis x at success; the zoo's goal_x is the rear's
        return {**own, **self.zoo_info()}


class SRWMRAdapter(ZooAdapter):
    robot = "srwmr"
    label = "HIT-MRII"
    config_cls = SRWMRConfig
    task_cls = ZooSRWMRTask
    methods = {"wrm": "wheel rolling straight down the lane at 25 mm/s, health halt at body slip",
               "rcm": "as wrm, the supervisor switching to creeping (RCM) below 10 % climbing efficiency"}
    unsupported = {f.id: RIGID for f in FAMILIES.values() if f.rigid}

    def method_reason(self, method: str, family: str) -> str | None:
        why = super().method_reason(method, family)
        if why is None and method == "rcm" and family == "soft-flat":
            # measured: on level soil the two trials are the same bits (no switch), 50-70 s each
            return ("on level soil the climbing efficiency never drops below the switch threshold: srwmr.rcm "
                    "is srwmr.wrm there (run that)")
        return why

    def footprint(self) -> Footprint:
        r = RobotConfig()
        # nose to tail over the wheels' outer edges, track + a wheel's width; height: the hinge
        # height (the body's top is at about it); mass: RobotConfig.total_mass
        return Footprint(length=r.nose + r.tail, front=r.nose, width=r.track + r.wheel_width, height=r.hinge_height,
                         wheel_radius=r.wheel_radius, mass=r.total_mass, speed=SPEED)

    def make_controller(self, method: str, task: ZooSRWMRTask):
        cfg = task.cfg
        return RoverController(list(task.layout.plan), cfg.robot, cfg.supervisor, cfg.limits, cfg.scales,
                               cfg.protocol.control_period)


ADAPTER = register_adapter(SRWMRAdapter())
