"""Gymnasium glue of the HIT-MRII rover (``terrabench/SRWMR-v1``): spaces, mapping, reward.

Observation (a ``Dict`` of float64 boxes), exactly the sensing boundary
(:mod:`terrabench.systems.srwmr.sensing`): rocker closing angles and rates, differential and
bogie angles, steering angles, wheel spins and torques, wheel-load estimates, IMU angles and
gyro, motion-capture position/yaw and body speed, time.

Action (one flat ``Box``, 14 entries): six steering targets (rad, [-1.75, 1.75]), six wheel spin
rates (rad/s, [-SPIN_LIMIT, SPIN_LIMIT]) and the two rocker closing-angle targets (rad, within
the IK's delta range). Reward = progress along +x (m, simulator quantity for the reward only) -
energy weight x J + a success bonus; terms in ``info["reward_terms"]``.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from terrabench.envs.adapter import box as _box
from terrabench.systems.srwmr.control import Command

SPIN_LIMIT = 1.0


class SRWMREnvAdapter:
    def __init__(self, progress_weight: float = 1.0, energy_weight: float = 1e-4, success_bonus: float = 10.0):
        self.progress_weight, self.energy_weight, self.success_bonus = progress_weight, energy_weight, success_bonus

    def observation_space(self, task) -> spaces.Dict:
        return spaces.Dict(
            {
                "delta": _box(2),
                "ddelta": _box(2),
                "phi": _box(2),
                "zeta": _box(2),
                "mu": _box(6),
                "spin": _box(6),
                "tau": _box(6),
                "load": _box(6),
                "rpy": _box(3),
                "gyro": _box(3),
                "xy": _box(2),
                "yaw": _box(1),
                "v_body": _box(2),
                "time": _box(1),
            }
        )

    def action_space(self, task) -> spaces.Box:
        lo_d, hi_d = task.cfg.limits.delta_range
        low = np.array([-1.75] * 6 + [-SPIN_LIMIT] * 6 + [lo_d] * 2)
        high = np.array([1.75] * 6 + [SPIN_LIMIT] * 6 + [hi_d] * 2)
        return spaces.Box(low=low, high=high, dtype=np.float64)

    def reset(self, task) -> None:
        self._task = task
        sp = self.action_space(task)
        self._low, self._high = sp.low, sp.high
        self._x = float(task.data.xpos[task.chassis, 0])

    def observation(self, obs) -> dict[str, np.ndarray]:
        return {
            "delta": np.array(obs.delta, float),
            "ddelta": np.array(obs.ddelta, float),
            "phi": np.array(obs.phi),
            "zeta": np.array(obs.zeta),
            "mu": np.array(obs.mu),
            "spin": np.array(obs.spin),
            "tau": np.array(obs.tau),
            "load": np.array(obs.load),
            "rpy": np.array(obs.rpy),
            "gyro": np.array(obs.gyro),
            "xy": np.array(obs.xy),
            "yaw": np.array([obs.yaw]),
            "v_body": np.array(obs.v_body),
            "time": np.array([obs.t]),
        }

    def command(self, action, task) -> Command:
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self._low.shape:
            raise ValueError(f"action must have shape {self._low.shape}, got {a.shape}")
        a = np.clip(a, self._low, self._high)
        return Command(steer=a[:6].copy(), spin=a[6:12].copy(), delta=a[12:14].copy(), u=np.zeros(5))

    def reward(self, prev, obs, energy: float, status: str):
        x = float(self._task.data.xpos[self._task.chassis, 0])
        terms = {
            "progress": self.progress_weight * (x - self._x),
            "energy": -self.energy_weight * float(energy),
            "success": self.success_bonus if status == "success" else 0.0,
        }
        self._x = x
        return sum(terms.values()), terms

    def reference_action(self, cmd: Command) -> np.ndarray:
        return np.concatenate([np.asarray(cmd.steer, float), np.asarray(cmd.spin, float), np.asarray(cmd.delta, float)])
