"""The sensing boundary: what a controller of the OCTOPUS robot may read (50 Hz).

IMU roll and pitch (no yaw, no position), the encoders of the flipper and arm joints, the
flipper joint torques and the elbow torques. Nothing about the terrain, no contacts: the paper's
"the control system knows nothing about the terrain in advance".
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from terrabench.systems.octopus.robot import Names, actuated_joints, torque_joints

#: every field an observation carries (the sensing-boundary test pins this list)
FIELDS = ("t", "roll", "pitch", "q_flip", "q_arm", "tau_flip", "tau_elbow")


def roll_pitch(quat: np.ndarray) -> tuple[float, float]:
    """Roll (left side up > 0) and pitch (nose up > 0) in rad of a body quaternion (w, x, y, z)."""
    w, x, y, z = quat
    r20 = 2.0 * (x * z - w * y)        # R[2, 0]
    r21 = 2.0 * (y * z + w * x)        # R[2, 1]
    r22 = 1.0 - 2.0 * (x * x + y * y)  # R[2, 2]
    return math.atan2(r21, r22), math.asin(max(-1.0, min(1.0, r20)))


class Observation:
    """The robot's measurements after the last physics step.

    Attributes:
        t: time (s).
        roll, pitch: IMU angles (rad): roll > 0 left side up, pitch > 0 nose up.
        q_flip: flipper angles (rad), order LF, RF, LR, RR; > 0 lifts the tip.
        q_arm: (4, 3) arm joints (swing, boom, elbow) (rad), arms LF, RF, LR, RR.
        tau_flip: flipper joint torques (N m), same order.
        tau_elbow: elbow joint torques (N m), arms LF, RF, LR, RR.
    """

    __slots__ = ("_d", "_q", "_tau", "_quat", "t", "roll", "pitch", "q_flip", "q_arm", "tau_flip", "tau_elbow")

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData):
        self._d = data
        adr = lambda name: int(model.sensor_adr[model.sensor(name).id])  # noqa: E731
        self._quat = adr(Names.IMU)
        self._q = np.array([adr(Names.pos_sensor(j)) for j in actuated_joints()])
        self._tau = np.array([adr(Names.torque_sensor(j)) for j in torque_joints()])
        self.refresh()

    def refresh(self) -> "Observation":
        s = self._d.sensordata
        self.t = float(self._d.time)
        self.roll, self.pitch = roll_pitch(s[self._quat: self._quat + 4])
        q = s[self._q]
        self.q_flip = q[:4].copy()
        self.q_arm = q[4:].reshape(4, 3).copy()
        tau = s[self._tau]
        self.tau_flip = tau[:4].copy()
        self.tau_elbow = tau[4:].copy()
        return self


class FakeObservation:
    """A hand-made observation (tests, studies): the same fields, set directly."""

    def __init__(self, t=0.0, roll=0.0, pitch=0.0, q_flip=None, q_arm=None, tau_flip=None, tau_elbow=None):
        self.t, self.roll, self.pitch = t, roll, pitch
        self.q_flip = np.zeros(4) if q_flip is None else np.asarray(q_flip, float)
        self.q_arm = np.zeros((4, 3)) if q_arm is None else np.asarray(q_arm, float)
        self.tau_flip = np.zeros(4) if tau_flip is None else np.asarray(tau_flip, float)
        self.tau_elbow = np.zeros(4) if tau_elbow is None else np.asarray(tau_elbow, float)
