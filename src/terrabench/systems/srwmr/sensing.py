"""The sensing boundary of the HIT-MRII (seed 001 sec. 8.1-8.3): what a controller may read.

Joint encoders (rocker closing angles and rates, differential, bogie angles, steering angles,
wheel spin rates), wheel drive torques, six wheel-load estimates (the per-wheel 6-axis F/T
sensors: the pillar's force along the body z axis, with noise), the IMU (roll, pitch, yaw, gyro)
and the motion-capture pose and body speed (OptiTrack in the paper; here with noise). Nothing
about the soil, the sinkage or the true slip.
"""

from __future__ import annotations

import math

import mujoco
import numba
import numpy as np

from terrabench.sim.checks import roll_pitch
from terrabench.systems.srwmr.robot import SIDES, WHEELS, Names

FIELDS = ("t", "delta", "ddelta", "phi", "zeta", "mu", "spin", "tau", "load", "rpy", "gyro", "xy", "yaw", "v_body")


def rpy_from_quat(q) -> tuple[float, float, float]:
    """Roll, pitch (nose up > 0), yaw (rad) of a (w, x, y, z) quaternion."""
    w, x, y, z = q
    roll, pitch = roll_pitch(q)
    return roll, pitch, math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


class Observation:
    """Measurements after the last physics step (see module docstring; SI units).

    Attributes:
        t (s); delta (2,) closing angles L, R (rad); ddelta (2,) their rates (rad/s); phi (2,)
        differential; zeta (2,) bogie angles; mu (6,) steering; spin (6,) wheel rates (rad/s);
        tau (6,) drive torques (N m); load (6,) wheel-load estimates (N); rpy (3,) (rad); gyro
        (3,) (rad/s); xy (2,) position (m) and yaw (rad) from motion capture; v_body (2,)
        forward / lateral body speed (m/s) from motion capture, noisy.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        rng: np.random.Generator,
        load_noise: float = 5.0,
        speed_noise: float = 0.001,
        pose_noise: float = 0.00015,
    ):
        self._d = data
        def jq(n):
            return int(model.joint(n).qposadr[0])

        def jv(n):
            return int(model.joint(n).dofadr[0])

        self._rock_q = np.array([jq(Names.rocker(s)) for s in SIDES])
        self._rock_v = np.array([jv(Names.rocker(s)) for s in SIDES])
        self._diff = np.array([jq(Names.diff(s)) for s in SIDES])
        self._bog = np.array([jq(Names.bogie(s)) for s in SIDES])
        self._steer = np.array([jq(Names.steer(c)) for c in WHEELS])
        self._spin = np.array([jv(Names.drive(c)) for c in WHEELS])
        self._drive = np.array([model.actuator(Names.drive(c)).id for c in WHEELS])
        self._ft = np.array([int(model.sensor_adr[model.sensor(Names.ft(c)).id]) for c in WHEELS])
        self._quat = int(model.sensor_adr[model.sensor(Names.QUAT).id])
        self._gyro = int(model.sensor_adr[model.sensor(Names.GYRO).id])
        self._chassis = model.body(Names.CHASSIS).id
        # gravity compensation of the F/T reading: the weight of the pillar and wheel below the sensor
        g = float(np.linalg.norm(model.opt.gravity))
        self._below = np.array([model.body_subtreemass[model.body(Names.pillar(c)).id] * g for c in WHEELS])
        self._root = jv(Names.ROOT)
        self._q_idx = np.concatenate([self._rock_q, self._diff, self._bog, self._steer])
        self._v_idx = np.concatenate([self._rock_v, self._spin])
        self._ftz = self._ft + 2  # the z component of each F/T force
        # the data's arrays (views onto MuJoCo's buffers, fixed for the data's life), read once
        self._qpos, self._qvel, self._sens = data.qpos, data.qvel, data.sensordata
        self._force, self._xpos = data.actuator_force, data.xpos
        self.rng = rng
        self.load_noise, self.speed_noise, self.pose_noise = load_noise, speed_noise, pose_noise
        self.refresh()

    def refresh(self) -> Observation:
        """Read this instant's measurements: one compiled gather (:func:`_read_kernel`) and one
        draw of the noise (the same numbers, in the same order, as a draw per sensor;
        the oracle ``refresh_reference`` in tests/srwmr/srwmr_reference.py is the numpy form, tested bitwise)."""
        d = self._d
        self.t = float(d.time)
        z = self.rng.standard_normal(10 if self.load_noise else 4)
        (self.delta, self.ddelta, self.phi, self.zeta, self.mu, self.spin, self.tau, self.rpy, self.gyro,
         self.load, self.xy, self.v_body) = _read_kernel(
            self._qpos, self._qvel, self._sens, self._force, self._xpos, self._q_idx, self._v_idx, self._drive,
            self._quat, self._gyro, self._ftz, self._below, self._chassis, self._root, z,
            float(self.load_noise), float(self.pose_noise), float(self.speed_noise))
        self.yaw = self.rpy[2]
        return self

@numba.njit(cache=True)
def _read_kernel(qpos, qvel, sens, force, xpos, q_idx, v_idx, drive, quat, gyro, ftz, below, chassis, root, z,
                 load_noise, pose_noise, speed_noise):
    """The gathers and expressions of the oracle ``refresh_reference`` (tests/srwmr/srwmr_reference.py) on scalars (libm
    atan2/asin/cos/sin as Python's ``math``): (delta, ddelta, phi, zeta, mu, spin, tau, rpy, gyro,
    load, xy, v_body). ``z``: the noise draw (10 with load noise: 6 loads, then pose and speed;
    else 4)."""
    delta, ddelta, phi, zeta = np.empty(2), np.empty(2), np.empty(2), np.empty(2)
    mu, spin, tau, load = np.empty(6), np.empty(6), np.empty(6), np.empty(6)
    for k in range(2):
        delta[k] = -qpos[q_idx[k]]
        phi[k] = qpos[q_idx[2 + k]]
        zeta[k] = qpos[q_idx[4 + k]]
        ddelta[k] = -qvel[v_idx[k]]
    for k in range(6):
        mu[k] = qpos[q_idx[6 + k]]
        spin[k] = qvel[v_idx[2 + k]]
        tau[k] = force[drive[k]]
    w, x, y, zq = sens[quat], sens[quat + 1], sens[quat + 2], sens[quat + 3]
    r20 = 2.0 * (x * zq - w * y)
    r21 = 2.0 * (y * zq + w * x)
    r22 = 1.0 - 2.0 * (x * x + y * y)
    rpy = np.empty(3)
    rpy[0] = math.atan2(r21, r22)
    rpy[1] = math.asin(max(-1.0, min(1.0, r20)))
    rpy[2] = math.atan2(2 * (w * zq + x * y), 1 - 2 * (y * y + zq * zq))
    g = np.empty(3)
    for k in range(3):
        g[k] = sens[gyro + k]
    o = 0
    if load_noise:
        o = 6
        for k in range(6):
            load[k] = (-sens[ftz[k]] + below[k]) + z[k] * load_noise
    else:
        for k in range(6):
            load[k] = -sens[ftz[k]] + below[k]
    xy = np.empty(2)
    xy[0] = xpos[chassis, 0] + z[o] * pose_noise
    xy[1] = xpos[chassis, 1] + z[o + 1] * pose_noise
    yaw = rpy[2]
    vw0, vw1 = qvel[root], qvel[root + 1]
    c, sn = math.cos(yaw), math.sin(yaw)
    v_body = np.empty(2)
    v_body[0] = (c * vw0 + sn * vw1) + z[o + 2] * speed_noise
    v_body[1] = (-sn * vw0 + c * vw1) + z[o + 3] * speed_noise
    return delta, ddelta, phi, zeta, mu, spin, tau, rpy, g, load, xy, v_body
