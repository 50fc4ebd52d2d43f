"""MRS-CWC's Gymnasium glue (:class:`MRSEnvAdapter`) and its render overlay.

Observation (a ``Dict`` of float64 ``Box`` es, copies of the sensing boundary
:class:`~terrabench.systems.mrs_cwc.sensing.Observation`; n = 6 units):

=================  ===========  ==============================================
key                shape        meaning (SI units)
=================  ===========  ==============================================
pos                (n, 3)       unit positions (m)
xaxis              (n, 3)       unit longitudinal axes, world frame
angvel             (n, 3)       unit angular velocities, world frame (rad/s)
yaw                (n,)         unit headings (rad)
wheel_speed        (n, 2)       [left, right] wheel speeds (rad/s)
wheel_torque       (n, 2)       [left, right] wheel torques (N m)
joint_yaw          (n-1,)       link relative yaws (rad); linked variants only
yaw_torque         (n-1,)       yaw-servo torques (N m); MRS-MJ only
yaw_speed          (n-1,)       yaw-joint speeds (rad/s); MRS-MJ only
target             (2,)         [bearing (rad), horizontal distance (m)] to the target
time               (1,)         simulated time (s)
=================  ===========  ==============================================

Action (a flat float64 ``Box``): the body law's command. The first 2n entries are the wheel
speeds, unit-major ``[u0 left, u0 right, u1 left, ...]``, in ``[-WHEEL_LIMIT, WHEEL_LIMIT]``
rad/s; the spring variant (CWC, CS methods) adds one common yaw stiffness in
``[0, stiffness.k_high]`` N m/rad (100 by default); the motor variant (MJ) adds the n-1
yaw-servo targets in ``[-pi, pi]`` rad; the D variant has wheel speeds only. Actions are
clipped to the box. The drive's torque limit is then applied by the task as in the benchmark.

Reward = ``progress`` (metres the leader got closer to the target this period, x
``progress_weight``) + ``energy`` (- ``energy_weight`` x joules drawn this period) +
``success`` (``success_bonus`` on arrival), terms in ``info["reward_terms"]``.

The logged ``tau_env`` column is a diagnostic of the CWC body law (its environment-torque
estimate, paper eq. 11), not a measurement: an action carries none, so env-driven episodes log
NaN there. Everything physical (positions, stiffness, energy, metrics) is the benchmark's,
bitwise, when the env is driven by the benchmark's controller.
"""

from __future__ import annotations

import math

import numpy as np
from gymnasium import spaces

from terrabench.envs.adapter import box as _box
from terrabench.systems.mrs_cwc import control as ctl
from terrabench.systems.mrs_cwc.sensing import Observation

#: bound of every wheel-speed action (rad/s); the benchmark's laws stay within 6 rad/s
WHEEL_LIMIT = 8.0


class MRSEnvAdapter:
    """Spaces, observation/command mapping and reward terms of the MRS-CWC chain."""

    def __init__(self, progress_weight: float = 1.0, energy_weight: float = 1e-3, success_bonus: float = 10.0):
        self.progress_weight, self.energy_weight, self.success_bonus = progress_weight, energy_weight, success_bonus

    # ------------------------------------------------------------------ spaces
    def observation_space(self, task) -> spaces.Dict:
        n, variant = task.cfg.chain.n_units, task.method.variant
        d = {"pos": _box(n, 3), "xaxis": _box(n, 3), "angvel": _box(n, 3), "yaw": _box(n, low=-math.pi, high=math.pi),
             "wheel_speed": _box(n, 2), "wheel_torque": _box(n, 2)}
        if variant != "none":
            d["joint_yaw"] = _box(n - 1)
        if variant == "motor":
            d["yaw_torque"] = _box(n - 1)
            d["yaw_speed"] = _box(n - 1)
        d["target"] = spaces.Box(low=np.array([-math.pi, 0.0]), high=np.array([math.pi, np.inf]), dtype=np.float64)
        d["time"] = _box(1, low=0.0)
        return spaces.Dict(d)

    def action_space(self, task) -> spaces.Box:
        n, variant = task.cfg.chain.n_units, task.method.variant
        low, high = [-WHEEL_LIMIT] * (2 * n), [WHEEL_LIMIT] * (2 * n)
        if variant == "spring":
            low.append(0.0)
            high.append(task.cfg.stiffness.k_high)
        elif variant == "motor":
            low += [-math.pi] * (n - 1)
            high += [math.pi] * (n - 1)
        return spaces.Box(low=np.array(low), high=np.array(high), dtype=np.float64)

    # ------------------------------------------------------------------ episode
    def reset(self, task) -> None:
        """Start of an episode."""
        self._task = task
        self._variant = task.method.variant
        self._n = task.cfg.chain.n_units
        space = self.action_space(task)
        self._low, self._high = space.low, space.high

    def observation(self, obs: Observation) -> dict[str, np.ndarray]:
        out = {"pos": obs.pos.copy(), "xaxis": obs.xaxis.copy(), "angvel": obs.angvel.copy(),
               "yaw": np.clip(obs.yaw, -math.pi, math.pi), "wheel_speed": obs.wheel_speed.copy(),
               "wheel_torque": obs.wheel_torque.copy()}
        if self._variant != "none":
            out["joint_yaw"] = np.array(obs.joint_yaw)
        if self._variant == "motor":
            out["yaw_torque"] = np.array(obs.yaw_torque)
            out["yaw_speed"] = np.array(obs.yaw_speed)
        out["target"] = np.array([obs.target_bearing, obs.target_distance])
        out["time"] = np.array([obs.t])
        return out

    def command(self, action, task) -> ctl.Command:
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self._low.shape:
            raise ValueError(f"action must have shape {self._low.shape}, got {a.shape}")
        a = np.clip(a, self._low, self._high)
        n = self._n
        cmd = ctl.Command(n)
        cmd.wheel_speed[:] = a[: 2 * n].reshape(n, 2)
        if self._variant == "spring":
            cmd.yaw_stiffness = float(a[2 * n])
        elif self._variant == "motor":
            cmd.yaw_target = a[2 * n :].copy()
        return cmd

    def reward(self, prev: dict[str, np.ndarray], obs: dict[str, np.ndarray], energy: float,
               status: str) -> tuple[float, dict[str, float]]:
        terms = {"progress": self.progress_weight * float(prev["target"][1] - obs["target"][1]),
                 "energy": -self.energy_weight * float(energy),
                 "success": self.success_bonus if status == "success" else 0.0}
        return sum(terms.values()), terms

    def reference_action(self, cmd: ctl.Command) -> np.ndarray:
        parts = [np.asarray(cmd.wheel_speed, np.float64).ravel()]
        if self._variant == "spring":
            parts.append(np.array([cmd.yaw_stiffness], np.float64))
        elif self._variant == "motor":
            parts.append(np.asarray(cmd.yaw_target, np.float64))
        return np.concatenate(parts)


def overlay(task, obs: Observation) -> str:
    """The render overlay's MRS-CWC line: the method, the applied yaw stiffness K and the distance left."""
    parts = [task.method.label]
    if task.method.variant == "spring" and len(task.yaw_joints):
        parts.append(f"K = {float(task.model.jnt_stiffness[task.yaw_joints[0]]):.1f} N m/rad")
    parts.append(f"d = {obs.target_distance:.2f} m")
    return "  ".join(parts)
