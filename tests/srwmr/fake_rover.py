"""The rover controller driven without a simulation: a fake observation and the default controller
(the controller-level tests of test_control_task, test_load_filter, test_qp_at_work and
test_tasks_extra)."""

from __future__ import annotations

import numpy as np

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.config import SupervisorConfig
from terrabench.systems.srwmr.control import RoverController
from terrabench.systems.srwmr.ik import IKLimits
from terrabench.systems.srwmr.robot import RobotConfig


class Obs:
    """What the controller reads each period: time, closing angles, steering, loads (default the
    equal 368 N), the body's forward speed ``v``; everything else at rest."""

    def __init__(self, t=0.0, load=None, v=0.0, delta=(0.0, 0.0), mu=None):
        self.t, self.delta, self.ddelta = t, np.array(delta, float), np.zeros(2)
        self.mu = np.zeros(6) if mu is None else np.asarray(mu, float)
        self.spin = np.zeros(6)
        self.load = np.full(6, 368.0) if load is None else np.asarray(load, float)
        self.xy, self.yaw, self.v_body, self.rpy = np.zeros(2), 0.0, np.array([v, 0.0]), np.zeros(3)


def controller(plan, **sup) -> RoverController:
    """The default rover and limits, a 10 ms period, the supervisor with ``sup`` overridden."""
    return RoverController(plan, RobotConfig(), SupervisorConfig(**sup), IKLimits(), mc.Scales(), 0.01)
