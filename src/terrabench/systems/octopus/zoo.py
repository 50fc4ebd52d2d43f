"""OCTOPUS in the zoo: the robot and its CLM / CCM controllers on any rigid course.

The task is :class:`~terrabench.systems.octopus.task.OctopusTask` (its contact pass, command
limits, power and metrics) with the zoo's course instead of the paper's pieces and the zoo's
stop rules (:class:`~terrabench.zoo.task.ZooRules`). The crawler has no soil model, so the soil
families are unsupported.
"""

from __future__ import annotations

from typing import Any

import mujoco

from terrabench.sim.episode import Timing
from terrabench.systems.octopus.ccm import CCMController
from terrabench.systems.octopus.clm import CLMController
from terrabench.systems.octopus.config import OctopusConfig
from terrabench.systems.octopus.robot import ARMS, Names, add_robot
from terrabench.systems.octopus.task import Layout, OctopusTask
from terrabench.terrain.course import add_course
from terrabench.terrain.mjcf import GROUND_BIT
from terrabench.zoo.adapter import Footprint, ZooAdapter, register_adapter
from terrabench.zoo.families import FAMILIES
from terrabench.zoo.task import ZooRules, start_height

NO_SOIL = "the crawler's tracks have no terramechanics model (rigid contact only); soil families need one"


class ZooOctopusTask(ZooRules, OctopusTask):
    """OCTOPUS on a zoo course: chassis front ``course.start_front``, heading +x."""

    def __init__(self, method: str, course: Any, cfg: OctopusConfig, zoo: Any, footprint: Footprint,
                 timeout: float, seed: int = 0):
        self.method, self.cfg, self.seed = method, cfg, seed
        self.instance = f"{course.family}@{course.severity:g}"
        self.course, self.zoo, self.footprint = course, zoo, footprint
        pr = cfg.protocol
        self.physics = cfg.physics
        self.timing = Timing(pr.control_period, timeout, pr.check_period, pr.log_period)
        y0 = self.start_y(seed)
        x0 = course.start_front - footprint.front
        self.layout = Layout("zoo", (), course.goal_x, 0.0, 0.0, (x0, y0), 0.0)
        self.camera = {"azimuth": 90.0, "elevation": -12.0}
        self.zoo_init()

    def build(self, spec: mujoco.MjSpec) -> None:
        c, r, fp = self.course, self.cfg.robot, self.footprint
        spec.modelname = f"zoo_octopus_{c.family}"
        add_course(spec, c, contype=GROUND_BIT, conaffinity=0, friction=self.zoo.course.friction)
        spec.worldbody.add_light(pos=[0, 0, 4], dir=[0, 0, -1])
        x0, y0 = self.layout.start
        z0 = start_height(c, x0 - self.rear_length(), x0 + fp.front, fp.width)
        add_robot(spec, (x0, y0, z0 + r.pulley_r + 0.01), 0.0, r)
        # the paper's start pose of the arms (as OctopusTask.build): out to the sides, tips up
        self._q0 = {Names.arm_joint(k, "swing"): (0.9 if k[1] == "F" else -0.6) for k in ARMS}
        self._q0.update({Names.arm_joint(k, "boom"): -0.3 for k in ARMS})
        self._q0.update({Names.arm_joint(k, "elbow"): 1.0 for k in ARMS})

    def info(self) -> dict:
        return self.zoo_info()


class OctopusAdapter(ZooAdapter):
    robot = "octopus"
    label = "OCTOPUS"
    config_cls = OctopusConfig
    task_cls = ZooOctopusTask
    methods = {"clm": "compound locomotion: arms walk and lift, flippers crawl",
               "ccm": "crawler-only: automated flipper step climbing"}
    unsupported = {f.id: NO_SOIL for f in FAMILIES.values() if not f.rigid}

    def footprint(self) -> Footprint:
        # flipper tip to flipper tip (pulley_x 0.2 + flipper 0.25 + tip 0.05 each way), the arms'
        # resting tips out to the sides; mass: the compiled model's subtree mass (94.2 kg); speed:
        # CLM's walking speed (OctopusConfig protocol.timeout doc: 0.054 m/s)
        return Footprint(length=1.0, front=0.5, width=0.8, height=0.33, wheel_radius=0.09, mass=94.2, speed=0.054)

    def make_controller(self, method: str, task: ZooOctopusTask):
        cfg = task.cfg
        if method == "clm":
            return CLMController(cfg.clm, cfg.robot, cfg.protocol.control_period)
        return CCMController(cfg.ccm, cfg.protocol.control_period, cfg.robot)


ADAPTER = register_adapter(OctopusAdapter())
