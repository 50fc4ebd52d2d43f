"""The MRS-CWC chain in the zoo: six units, the CWC (elastic links) and D (independent units)
body laws with target-direction tracking towards a point far down the lane.

The task is :class:`~terrabench.systems.mrs_cwc.task.MRSTask` (drive limits, stiffness switching,
power, navigation metrics) on the zoo's course with the zoo's stop rules. The wheels have rigid
contact only, so the soil families are unsupported. The A* methods need a height map of a released
terrain and are not offered.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import mujoco

from terrabench.config import to_dict
from terrabench.sim.checks import roll_pitch
from terrabench.sim.episode import Timing
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import config_for, get_method
from terrabench.systems.mrs_cwc.robot import add_chain
from terrabench.systems.mrs_cwc.task import MRSTask, make_controller
from terrabench.terrain.course import add_course
from terrabench.terrain.mjcf import GROUND_BIT
from terrabench.zoo.adapter import Footprint, ZooAdapter, register_adapter
from terrabench.zoo.families import FAMILIES
from terrabench.zoo.task import ZooRules, start_height

NO_SOIL = "the chain's wheels have rigid contact only (no terramechanics model); soil families need one"
#: the TDT target: this far beyond the goal line on the lane's centre line (m)
TARGET_AHEAD = 20.0
#: the chain is placed this far above the highest ground under it (m), wheels down
DROP = 0.02


class ZooMRSTask(ZooRules, MRSTask):
    """The chain on a zoo course: leader's front at ``course.start_front``, followers along -x."""

    def __init__(self, method: str, course: Any, cfg: MRSConfig, zoo: Any, footprint: Footprint, timeout: float,
                 seed: int = 0):
        self.course, self.zoo, self.footprint = course, zoo, footprint
        y0 = self.start_y(seed)
        lead = cfg.chain.bumper_ahead + cfg.chain.bumper_radius  # leader centre to its front
        pr = replace(cfg.protocol, start_xy=(course.start_front - lead, y0),
                     target_xy=(course.goal_x + TARGET_AHEAD, 0.0), timeout=timeout)
        self.method, self.terrain, self.cfg = get_method(method), None, replace(cfg, protocol=pr)
        self.physics = cfg.physics
        self.timing = Timing(pr.control_period, timeout, pr.divergence_check_period, pr.log_period)
        self.start_z = float("nan")
        self._half_body = 0.5 * cfg.chain.body_length
        self.instance = f"{course.family}@{course.severity:g}"
        self.zoo_init()

    def build(self, spec: mujoco.MjSpec) -> None:
        c, ch, fp = self.course, self.cfg.chain, self.footprint
        spec.modelname = f"zoo_mrs_cwc_{self.method.variant}_{c.family}"
        add_course(spec, c, contype=GROUND_BIT, conaffinity=0, friction=self.zoo.course.friction)
        sx, sy = self.cfg.protocol.start_xy
        z = start_height(c, c.start_front - fp.length, c.start_front, fp.width)
        self.start_z = z + ch.wheel_radius + ch.axle_drop + DROP
        add_chain(spec, self.method.variant, (sx, sy, self.start_z), ch)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData):
        # the energy per m kg uses this build's mass (MRS-D has no link masses: 41.9 kg, not 45.9)
        self.footprint = replace(self.footprint, mass=float(model.body_mass[1:].sum()))
        return super().bind(model, data)

    def pose(self) -> tuple[float, float, float, float, float]:
        d, units = self.data, self.unit_bodies
        x = d.xpos[units]
        roll, pitch = roll_pitch(d.xquat[units[0]])
        return (float(x[:, 0].min() - self._half_body), float(x[0, 1]), float(x[:, 2].min()), roll, pitch)

    def info(self) -> dict:
        return {**self.zoo_info(), "start_z": self.start_z}


class MRSAdapter(ZooAdapter):
    robot = "mrs-cwc"
    label = "MRS-CWC chain"
    config_cls = MRSConfig
    task_cls = ZooMRSTask
    methods = {"cwc-tdt": "elastic links, yaw stiffness switched by sensed torques; heads down the lane",
               "d-tdt": "six independent units following by position; heads down the lane"}
    unsupported = {f.id: NO_SOIL for f in FAMILIES.values() if not f.rigid}

    def footprint(self) -> Footprint:
        # six units 0.30 m apart: leader bumper front (0.12 + 0.09 m ahead of its centre) to the
        # last body's rear end (5 x 0.30 + 0.10 m behind); width: the bumper disc (0.18 m);
        # height: bumper top (0.215 m); mass: the spring chain's compiled mass (45.9 kg);
        # speed: 1.5 rad/s x 0.05 m (DriveConfig.wheel_speed)
        return Footprint(length=1.81, front=0.21, width=0.18, height=0.215, wheel_radius=0.05, mass=45.9,
                         speed=0.075)

    def robot_config(self, method: str) -> dict[str, Any]:
        return config_for(get_method(method), to_dict(MRSConfig()))

    def make_controller(self, method: str, task: ZooMRSTask):
        return make_controller(task.method, task.cfg, None)


ADAPTER = register_adapter(MRSAdapter())
