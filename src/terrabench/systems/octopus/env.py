"""Gymnasium glue of the OCTOPUS crawler (``terrabench/Octopus-v1``): spaces, mapping, reward.

Observation (a ``Dict`` of float64 boxes), exactly the sensing boundary: ``imu`` = [roll, pitch,
yaw rate] (rad, rad, rad/s from the gyro: the heading hold's input; no yaw angle, no position),
``q_flip`` (4,) flipper angles, ``q_arm`` (12,) arm joints (swing, boom, elbow per arm LF, RF,
LR, RR), ``tau_flip`` (4,) and ``tau_elbow`` (4,) joint torques
(N m), ``time`` (s).

Action (one flat float64 ``Box``, 18 entries): left/right track speed in
``[-TRACK_LIMIT, TRACK_LIMIT]`` m/s, then the four flipper angle targets and the twelve arm
joint targets (rad) within the robot's joint ranges (``robot.flipper_range``, ``swing_range``,
``boom_range``, ``elbow_range``). The servos' torque limits apply as in the benchmark.

Reward = ``progress`` (metres the chassis moved along the task's axis this period: a
simulator quantity used for the reward only, never observed) + ``energy`` (- weight x joules)
+ ``success`` (a bonus on arrival); terms in ``info["reward_terms"]``.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from terrabench.envs.adapter import box as _box
from terrabench.systems.octopus.rules import Command

#: bound of the track-speed actions (m/s); the controllers drive at 0.06-0.1 m/s
TRACK_LIMIT = 0.3


class OctopusEnvAdapter:
    """Spaces, observation/command mapping and reward terms of the OCTOPUS crawler."""

    def __init__(self, progress_weight: float = 1.0, energy_weight: float = 1e-4, success_bonus: float = 10.0):
        self.progress_weight, self.energy_weight, self.success_bonus = progress_weight, energy_weight, success_bonus

    def observation_space(self, task) -> spaces.Dict:
        return spaces.Dict({"imu": _box(3), "q_flip": _box(4), "q_arm": _box(12), "tau_flip": _box(4),
                            "tau_elbow": _box(4), "time": _box(1)})

    def action_space(self, task) -> spaces.Box:
        r = task.cfg.robot
        low = [-TRACK_LIMIT] * 2 + [r.flipper_range[0]] * 4
        high = [TRACK_LIMIT] * 2 + [r.flipper_range[1]] * 4
        for _ in range(4):
            for rng in (r.swing_range, r.boom_range, r.elbow_range):
                low.append(rng[0])
                high.append(rng[1])
        return spaces.Box(low=np.array(low), high=np.array(high), dtype=np.float64)

    def reset(self, task) -> None:
        self._task = task
        space = self.action_space(task)
        self._low, self._high = space.low, space.high
        self._s = task.progress()[0]

    def observation(self, obs) -> dict[str, np.ndarray]:
        return {"imu": np.array([obs.roll, obs.pitch, obs.yaw_rate]), "q_flip": np.array(obs.q_flip, float),
                "q_arm": np.array(obs.q_arm, float).ravel(), "tau_flip": np.array(obs.tau_flip, float),
                "tau_elbow": np.array(obs.tau_elbow, float), "time": np.array([obs.t])}

    def command(self, action, task) -> Command:
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self._low.shape:
            raise ValueError(f"action must have shape {self._low.shape}, got {a.shape}")
        a = np.clip(a, self._low, self._high)
        return Command(track=a[:2].copy(), flip=a[2:6].copy(), arm=a[6:].reshape(4, 3).copy())

    def reward(self, prev, obs, energy: float, status: str) -> tuple[float, dict[str, float]]:
        s = self._task.progress()[0]
        terms = {"progress": self.progress_weight * (s - self._s), "energy": -self.energy_weight * float(energy),
                 "success": self.success_bonus if status == "success" else 0.0}
        self._s = s
        return sum(terms.values()), terms

    def reference_action(self, cmd: Command) -> np.ndarray:
        return np.concatenate([np.asarray(cmd.track, float), np.asarray(cmd.flip, float),
                               np.asarray(cmd.arm, float).ravel()])
