"""The sensing boundary: what the real chain measures, read from MuJoCo sensors.

An :class:`Observation` holds zero-copy views into ``MjData.sensordata`` (refreshed by every
``mj_step``) plus the few derived quantities a controller needs (headings, target bearing).
It never exposes the terrain or the simulator; the A* guidance gets its map separately.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from terrabench.systems.mrs_cwc.robot import Names, drive_ref_dof

_TWO_PI = 2 * np.pi


def wrap(a: float | np.ndarray) -> float | np.ndarray:
    """Wrap angles to (-pi, pi] (rad)."""
    return np.pi - np.mod(np.pi - a, _TWO_PI)


def wrap_scalar(a: float) -> float:
    """:func:`wrap` for one Python float, bitwise equal to it (``%`` is numpy's ``mod``)."""
    return math.pi - (math.pi - a) % _TWO_PI


class Observation:
    """Measurements of one control instant.

    Attributes (all SI units):
        t: time (s).
        pos: unit positions, (n, 3) (m) - odometry/GNSS-like localisation.
        xaxis: each unit's longitudinal axis in the world frame, (n, 3).
        angvel: unit angular velocities in the world frame, (n, 3) (rad/s).
        yaw: unit headings, (n,) (rad).  yaw_rate: (n,) (rad/s).
        wheel_speed: (n, 2) [left, right] (rad/s).  wheel_torque: (n, 2) (N m).
        joint_yaw: relative yaw of each link, predecessor minus follower, (n-1,) (rad); empty for D.
        yaw_torque: measured yaw-joint torques of the MJ variant, (n-1,) (N m); empty otherwise.
        yaw_speed: yaw-joint speeds of the MJ variant, (n-1,) (rad/s); empty otherwise.
        target_bearing: world bearing from the leader to the target (rad).
        target_distance: horizontal leader-target distance (m).
        target_d2: its square, dx^2 + dy^2 (m^2).  leader_z: leader height (m).
    """

    __slots__ = (
        "t", "pos", "xaxis", "angvel", "yaw", "yaw_rate", "wheel_speed", "wheel_torque",
        "joint_yaw", "yaw_torque", "yaw_speed", "target_bearing", "target_distance",
        "target_d2", "leader_z", "_data", "_target",
    )

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, n_units: int, target_xy: tuple[float, float]):
        sd = data.sensordata
        adr = lambda name: int(model.sensor_adr[model.sensor(name).id])  # noqa: E731
        a = adr(f"{Names.unit(0)}_pos")
        per_unit = sd[a : a + 9 * n_units].reshape(n_units, 9)
        self.pos, self.xaxis, self.angvel = per_unit[:, 0:3], per_unit[:, 3:6], per_unit[:, 6:9]
        a = adr(f"{Names.wheel(0, 'left')}_vel")
        self.wheel_speed = sd[a : a + 2 * n_units].reshape(n_units, 2)
        a = drive_ref_dof(model)
        if a is not None:
            # constraint drive (ChainConfig.wheel_drive): the wheel torque is the friction
            # tendon's force, i.e. the constraint force on the (otherwise free) reference dof
            self.wheel_torque = data.qfrc_constraint[a : a + 2 * n_units].reshape(n_units, 2)
        else:
            a = adr(f"{Names.motor(0, 'left')}_torque")
            self.wheel_torque = sd[a : a + 2 * n_units].reshape(n_units, 2)
        self.joint_yaw = self._block(model, sd, f"{Names.link_joint(1, 'yaw')}_angle", n_units - 1)
        if model.nsensor and self._has(model, f"{Names.yaw_servo(1)}_torque"):
            tq = self._block(model, sd, f"{Names.yaw_servo(1)}_torque", 2 * (n_units - 1))
            self.yaw_torque, self.yaw_speed = tq[0::2], tq[1::2]
        else:
            self.yaw_torque = self.yaw_speed = np.zeros(0)
        self.yaw_rate = self.angvel[:, 2]
        self._data = data
        self._target = target_xy
        self.refresh()

    @staticmethod
    def _has(model: mujoco.MjModel, name: str) -> bool:
        try:
            model.sensor(name)
            return True
        except KeyError:
            return False

    def _block(self, model, sd, first: str, n: int) -> np.ndarray:
        if not self._has(model, first):
            return np.zeros(0)
        a = int(model.sensor_adr[model.sensor(first).id])
        return sd[a : a + n]

    def refresh(self) -> "Observation":
        """Recompute the derived quantities after a physics step."""
        ax = self.xaxis
        self.yaw = np.arctan2(ax[:, 1], ax[:, 0])  # equals the Z-Y-X yaw of the unit
        self.t = self._data.time
        px, py, self.leader_z = self.pos[0].tolist()
        dx = self._target[0] - px
        dy = self._target[1] - py
        self.target_bearing = math.atan2(dy, dx)
        self.target_distance = math.hypot(dx, dy)
        self.target_d2 = dx * dx + dy * dy
        return self
