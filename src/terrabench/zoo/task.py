"""The zoo's rules on top of a robot's own task: one stop order, extra log columns, the metrics.

A system's zoo task subclasses its own task and :class:`ZooRules` (first in the bases), builds
the course instead of its own terrain and implements :meth:`ZooRules.pose`. The stop order is the
same for every robot: turned over, fell (a tracked body below the course's ``fall_z`` or the
reference out of the lane), success (the rearmost point past the goal line), the robot's own
stop request (:meth:`ZooRules.own_stop`, e.g. the rover's health halt), stuck (slow checks only);
the time limit is the episode's truncation (``timeout``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from terrabench.sim.checks import Stalled, roll_pitch, turned_over
from terrabench.zoo.metrics import zoo_metrics

#: the columns the zoo adds to a robot's own log
ZOO_COLUMNS = ("zoo_rear_x", "zoo_y", "zoo_low_z", "zoo_roll", "zoo_pitch")


class ZooRules:
    """Mixin: ``self.course``, ``self.zoo`` (:class:`~terrabench.zoo.config.ZooConfig`) and
    ``self.footprint`` are set by the subclass's ``__init__``; it calls :meth:`zoo_init` too."""

    course: Any
    zoo: Any
    footprint: Any

    def zoo_init(self) -> None:
        pr = self.zoo.protocol
        self._zoo_stall = Stalled(pr.stuck_time, pr.stuck_progress)
        self._zoo_half_lane = 0.5 * self.course.lane
        self._zoo_pose_t = -1.0
        self._zoo_pose: tuple[float, float, float, float, float] = (0.0,) * 5
        self.columns = tuple(type(self).columns) + ZOO_COLUMNS

    def start_y(self, seed: int) -> float:
        """The start's sideways offset (m): 0 at seed 0 (the reference start), else drawn from
        +-``protocol.start_jitter`` by the seed."""
        j = self.zoo.protocol.start_jitter
        return float(np.random.default_rng(seed).uniform(-j, j)) if seed else 0.0

    def bind(self, model: Any, data: Any) -> Any:
        """The robot's own bind, then the rearmost point at the start (the progress origin)."""
        obs = super().bind(model, data)  # type: ignore[misc]
        self.zoo_start = self.pose()[0]
        return obs

    def pose(self) -> tuple[float, float, float, float, float]:
        """(rearmost x, reference y, lowest tracked body z, roll, pitch) now (m, rad). Default, a
        one-body robot: the rear end ``footprint.length - footprint.front`` behind the ``chassis``
        body's origin along its x axis, the chassis' y, z and attitude; a chain overrides it."""
        d, ch = self.data, self.chassis
        p = d.xpos[ch]
        ax = d.xmat[ch].reshape(3, 3)[:, 0]
        roll, pitch = roll_pitch(d.xquat[ch])
        rear = self.rear_length()
        return float(p[0] - rear * ax[0]), float(p[1]), float(p[2]), roll, pitch

    def rear_length(self) -> float:
        """How far the robot's rear end is behind its ``chassis`` origin (m); default from the
        footprint, a robot with the length in its own config returns that (its stored bits)."""
        return self.footprint.length - self.footprint.front

    def own_stop(self, obs: Any, rear_x: float) -> tuple[str, str] | None:
        """The robot's own stop rule (a controller's request); default none."""
        return None

    def zoo_pose(self) -> tuple[float, float, float, float, float]:
        t = float(self.data.time)  # type: ignore[attr-defined]
        if t != self._zoo_pose_t:
            self._zoo_pose, self._zoo_pose_t = self.pose(), t
        return self._zoo_pose

    def check(self, obs: Any, slow: bool) -> tuple[str, str] | None:
        rear, y, low, roll, pitch = self.zoo_pose()
        over = turned_over(roll, pitch, self.zoo.protocol.turn_over)
        if over is not None:
            return over
        c = self.course
        if low < c.fall_z:
            return "fell", f"a body below z = {c.fall_z:.2f} m (the lowest rim less {self.zoo.course.fall_drop} m)"
        if abs(y) > self._zoo_half_lane:
            return "fell", f"left the {c.lane:.2f} m lane (y = {y:+.2f} m)"
        if rear >= c.goal_x:
            return "success", f"rearmost point past the goal line x = {c.goal_x:.2f} m"
        own = self.own_stop(obs, rear)
        if own is not None:
            return own
        if slow:
            return self._zoo_stall(float(self.data.time), rear, 0.0, c.goal_x - rear,  # type: ignore[attr-defined]
                                   f"rear at x = {rear:.2f} m")
        return None

    def row(self, obs: Any, cmd: Any) -> Any:
        inner = super().row(obs, cmd)  # type: ignore[misc]
        extra = self.zoo_pose()
        if isinstance(inner, np.ndarray):
            return np.concatenate([inner, np.asarray(extra, float)])
        return (*inner, *extra)

    def metrics(self, log: Any) -> dict[str, float]:
        own = super().metrics(log)  # type: ignore[misc]
        out = {f"robot_{k}": float(v) for k, v in own.items() if isinstance(v, (int, float))}
        out.update(zoo_metrics(log, self.footprint.mass, self.course.goal_x, self.zoo_start))
        return out

    def zoo_info(self) -> dict[str, Any]:
        c = self.course
        return {"family": c.family, "severity": c.severity, "course": c.note, "goal_x": c.goal_x,
                "start_front": c.start_front, "lane": c.lane, "fall_z": c.fall_z, "soil": c.soil,
                "mass": self.footprint.mass, **{k: v for k, v in c.extra.items()}}


def start_height(course: Any, x_rear: float, x_front: float, width: float) -> float:
    """Highest ground (m) under the footprint's rectangle at the start."""
    return course.max_height(x_rear, x_front, 0.5 * width)


def yaw_quat(yaw: float) -> list[float]:
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
