"""The zoo's per-trial metrics: pure functions of a logged episode (tested on synthetic logs)."""

from __future__ import annotations

import math

import numpy as np

G = 9.81
#: below this progress (m) energy per metre is not a number (a robot that did not move)
MIN_PROGRESS = 0.1


def zoo_metrics(log, mass: float, goal_x: float, start_rear_x: float | None = None) -> dict[str, float]:
    """Figures that compare bodies.

    Args:
        log: the episode log, with the zoo columns (``zoo_rear_x``, ``zoo_roll``, ``zoo_pitch``).
        mass: the robot's mass (kg).
        goal_x: the goal line (m).
        start_rear_x: the rearmost x at the start (m; default the first logged one).

    Returns:
        ``success`` (1/0), ``time`` (s, NaN unless success), ``progress`` (m the rearmost point
        advanced), ``speed`` (progress / simulated time, m/s), ``energy`` (J), ``energy_per_m`` (J/m),
        ``energy_per_m_kg`` (J/(m kg)), ``cot`` (energy / (m g progress), -), ``max_pitch``,
        ``max_roll`` (largest |angle|, rad), ``goal_left`` (m from the rear to the goal line at the end).
    """
    rear = log.column("zoo_rear_x")
    roll, pitch = log.column("zoo_roll"), log.column("zoo_pitch")
    x0 = float(rear[0]) if start_rear_x is None else float(start_rear_x)
    return summarize(log.status, log.sim_time, log.energy, rear, roll, pitch, mass, goal_x, x0)


def summarize(status: str, sim_time: float, energy: float, rear: np.ndarray, roll: np.ndarray, pitch: np.ndarray,
              mass: float, goal_x: float, x0: float) -> dict[str, float]:
    """:func:`zoo_metrics` on plain arrays."""
    nan = float("nan")
    ok = status == "success"
    progress = float(np.nanmax(rear) - x0) if len(rear) else 0.0
    e = float(energy)
    per_m = e / progress if progress >= MIN_PROGRESS else nan
    return {
        "success": 1.0 if ok else 0.0,
        "time": float(sim_time) if ok else nan,
        "progress": progress,
        "speed": progress / sim_time if sim_time > 0 else nan,
        "energy": e,
        "energy_per_m": per_m,
        "energy_per_m_kg": per_m / mass if math.isfinite(per_m) else nan,
        "cot": per_m / (mass * G) if math.isfinite(per_m) else nan,
        "max_pitch": float(np.nanmax(np.abs(pitch))) if np.isfinite(pitch).any() else nan,
        "max_roll": float(np.nanmax(np.abs(roll))) if np.isfinite(roll).any() else nan,
        "goal_left": float(goal_x - rear[-1]) if len(rear) else nan,
    }
