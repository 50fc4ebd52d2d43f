"""What a real rover can know about slip and sinkage (controllers use these, never the
simulator's ground truth in :attr:`SoilWheels.truth`).

- Slip: wheel odometry (encoder rate x radius) against a body-velocity estimate (IMU
  integration, visual odometry, or a motion-capture stand-in). :class:`ImuVelocity` is a
  minimal IMU integrator (leaky, so its drift stays bounded; it under-reads slow changes).
- Sinkage: wheel-hub position (body pose estimate + suspension kinematics) against an
  estimated ground plane (e.g. fitted to stereo/LIDAR points of the terrain ahead before the
  rover drove onto it): ``z = r - distance(hub, plane)``.
"""

from __future__ import annotations

import numpy as np

from terrabench.soil.terramechanics import SLIP_MAX, SLIP_MIN


def estimated_slip(wheel_rate, radius: float, body_speed, v_eps: float = 0.02):
    """Slip estimate per wheel, the convention of :mod:`terrabench.soil.terramechanics`.

    Args:
        wheel_rate: encoder spin rates (rad/s), shape (N,).
        radius: nominal wheel radius (m) (the rover does not know its sinkage-reduced radius).
        body_speed: estimated forward speed of each hub in its heading (m/s), (N,) or scalar.
        v_eps: speed below which slip is regularised towards 0 (m/s).

    Returns:
        (N,) slip in [SLIP_MIN, 1]: ``(r w - v)/max(|r w|, |v|, v_eps)``.
    """
    rw = radius * np.asarray(wheel_rate, float)
    v = np.broadcast_to(np.asarray(body_speed, float), rw.shape)
    return np.clip((rw - v) / np.maximum(np.maximum(np.abs(rw), np.abs(v)), v_eps), SLIP_MIN, SLIP_MAX)


def fit_ground_plane(points) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares plane through terrain points (M, 3) (m): (point on plane, unit normal, +z up)."""
    P = np.asarray(points, float)
    if P.ndim != 2 or P.shape[1] != 3 or len(P) < 3:
        raise ValueError(f"points shape {P.shape} is invalid; valid: (M >= 3, 3)")
    c = P.mean(axis=0)
    n = np.linalg.svd(P - c)[2][-1]
    return c, n if n[2] >= 0 else -n


def estimated_sinkage(hub_positions, plane: tuple[np.ndarray, np.ndarray], radius: float):
    """Sinkage estimate per wheel (m): ``r - (hub - point) . normal``.

    Args:
        hub_positions: estimated hub centres (N, 3) (m), from the body pose estimate and the
            suspension's joint angles.
        plane: (point, unit normal) of the estimated undisturbed ground, e.g. from
            :func:`fit_ground_plane`.
        radius: nominal wheel radius (m).
    """
    p0, n = (np.asarray(x, float) for x in plane)
    return radius - (np.asarray(hub_positions, float) - p0) @ n


class ImuVelocity:
    """Body velocity from an accelerometer (gravity removed with the attitude estimate).

    ``v <- (1 - dt/tau) v + a_world dt`` with a leak time constant tau (s): an IMU alone
    cannot hold a velocity (bias integrates to drift), so real rovers fuse it with visual
    odometry; the leak stands in for that correction.
    """

    def __init__(self, tau: float = 5.0, v0=(0.0, 0.0, 0.0)):
        if tau <= 0:
            raise ValueError(f"tau={tau!r} is invalid; valid range: tau > 0 s")
        self.tau = tau
        self.v = np.array(v0, float)

    def update(self, specific_force_body, R_world_body, dt: float, gravity=(0.0, 0.0, -9.81)) -> np.ndarray:
        """One IMU sample: accelerometer reading (body frame, m/s^2), attitude (3x3), dt (s)."""
        a = np.asarray(R_world_body, float) @ np.asarray(specific_force_body, float) + np.asarray(gravity, float)
        self.v = (1.0 - dt / self.tau) * self.v + a * dt
        return self.v.copy()
