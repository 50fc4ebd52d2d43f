"""The sensing boundary: what a controller of the OCTOPUS robot may read (50 Hz).

IMU roll and pitch and the yaw rate from its gyro (no yaw angle, no position), the encoders
of the flipper and arm joints, the flipper joint torques and the elbow torques. Nothing about
the terrain, no contacts: the paper's "the control system knows nothing about the terrain in
advance".
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from terrabench.sim.checks import roll_pitch, roll_pitch_f  # noqa: F401 - re-exported: the IMU's angles
from terrabench.systems.octopus.robot import Names, actuated_joints, torque_joints

#: every field an observation carries (the sensing-boundary test pins this list)
FIELDS = ("t", "roll", "pitch", "yaw_rate", "q_flip", "q_arm", "tau_flip", "tau_elbow")


class Observation:
    """The robot's measurements after the last physics step.

    Attributes:
        t: time (s).
        roll, pitch: IMU angles (rad): roll > 0 left side up, pitch > 0 nose up.
        yaw_rate: rate of the heading (rad/s, > 0 turning left) from the IMU's gyro and its roll
            and pitch; a controller may integrate it into a heading (it drifts on a real robot).
        q_flip: flipper angles (rad), order LF, RF, LR, RR; > 0 lifts the tip.
        q_arm: (4, 3) arm joints (swing, boom, elbow) (rad), arms LF, RF, LR, RR.
        tau_flip: flipper joint torques (N m), same order.
        tau_elbow: elbow joint torques (N m), arms LF, RF, LR, RR.
    """

    # _flat: the one buffer the array fields view (encoders, then torques), or None (the task's
    # stored row reads it in one go)
    __slots__ = ("_d", "_s", "_q", "_tau", "_both", "_quat", "_gyro", "_head", "_flat", "t", "roll", "pitch",
                 "yaw_rate", "q_flip", "q_arm", "tau_flip", "tau_elbow")

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData):
        self._d = data
        self._s = data.sensordata  # a view of MjData's fixed array: valid for the data's life
        adr = lambda name: int(model.sensor_adr[model.sensor(name).id])  # noqa: E731
        self._quat = adr(Names.IMU)
        self._gyro = adr(Names.GYRO)
        q = np.array([adr(Names.pos_sensor(j)) for j in actuated_joints()])
        tau = np.array([adr(Names.torque_sensor(j)) for j in torque_joints()])
        # contiguous addresses (the builder adds the sensors in this order) read as slices
        self._q = slice(int(q[0]), int(q[-1]) + 1) if (np.diff(q) == 1).all() else q
        self._tau = slice(int(tau[0]), int(tau[-1]) + 1) if (np.diff(tau) == 1).all() else tau
        # encoders and torques adjacent (the builder's order): one copy a tick for both
        adjacent = isinstance(self._q, slice) and isinstance(self._tau, slice) and self._q.stop == self._tau.start
        self._both = slice(self._q.start, self._tau.stop) if adjacent else None
        # the IMU's quaternion and gyro within the first few values (the builder's order): one read
        head = max(self._quat + 4, self._gyro + 3)
        self._head = head if head <= 8 else 0
        self.refresh()

    def refresh(self) -> "Observation":
        s = self._s
        self.t = float(self._d.time)
        a, g = self._quat, self._gyro
        if self._head:
            h = s[:self._head].tolist()
            roll, pitch = roll_pitch_f(h[a], h[a + 1], h[a + 2], h[a + 3])
            wy, wz = h[g + 1], h[g + 2]
        else:
            roll, pitch = roll_pitch_f(*s[a: a + 4].tolist())
            _, wy, wz = s[g: g + 3].tolist()
        self.roll, self.pitch = roll, pitch
        # Z-Y-X Euler rate of the heading from body rates: (wy sin(roll) + wz cos(roll)) / cos(pitch)
        self.yaw_rate = (wy * math.sin(roll) + wz * math.cos(roll)) / max(math.cos(pitch), 1e-3)
        # one fresh copy a tick, the fields are views of it
        if self._both is not None:
            b = s[self._both].copy()
            self.q_flip, self.q_arm, self.tau_flip, self.tau_elbow = b[:4], b[4:16].reshape(4, 3), b[16:20], b[20:]
            self._flat = b
            return self
        self._flat = None
        q = s[self._q].copy()
        self.q_flip, self.q_arm = q[:4], q[4:].reshape(4, 3)
        tau = s[self._tau].copy()
        self.tau_flip, self.tau_elbow = tau[:4], tau[4:]
        return self


class FakeObservation:
    """A hand-made observation (tests, studies): the same fields, set directly."""

    def __init__(self, t=0.0, roll=0.0, pitch=0.0, q_flip=None, q_arm=None, tau_flip=None, tau_elbow=None,
                 yaw_rate=0.0):
        self.t, self.roll, self.pitch, self.yaw_rate = t, roll, pitch, yaw_rate
        self.q_flip = np.zeros(4) if q_flip is None else np.asarray(q_flip, float)
        self.q_arm = np.zeros((4, 3)) if q_arm is None else np.asarray(q_arm, float)
        self.tau_flip = np.zeros(4) if tau_flip is None else np.asarray(tau_flip, float)
        self.tau_elbow = np.zeros(4) if tau_elbow is None else np.asarray(tau_elbow, float)
