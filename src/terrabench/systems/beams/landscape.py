"""Potential-energy landscape over (x, alpha, beta) (paper Sec. II-F, eq. 8).

The beam deflections depend only on the geometry and the hinge heights, never on the
stiffness, so the expensive part (two deflection fields over ~10^6 poses) is computed once per
hinge height and cached in memory and on disk (``$TERRABENCH_CACHE`` or
``~/.cache/terrabench/beams``), keyed by a hash of the geometry, grid and hinge height rounded to
0.1 mm. Rebuilding the energy for a new stiffness is then a few array operations.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import asdict, dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from terrabench.config import ConfigError, check_fields, param

from .model import Beam, BeamLayout, RobotParams, com_height, deflection_vec


@dataclass(frozen=True)
class LandscapeConfig:
    """The landscape grid (paper Sec. II-F)."""

    x_min: float = param(-0.12, unit="m", doc="Lowest forward position, m")
    """Lowest forward position, m."""
    x_max: float = param(0.12, unit="m", doc="Highest forward position, m")
    """Highest forward position, m."""
    dx: float = param(0.002, gt=0, unit="m", doc="Forward step, m")
    """Forward step, m."""
    angle_max_deg: float = param(90.0, gt=0, le=180, unit="deg", doc="Roll and pitch span [-angle_max, angle_max], deg")
    """Roll and pitch span [-angle_max, angle_max], deg."""
    dangle_deg: float = param(2.0, gt=0, unit="deg", doc="Roll and pitch step, deg")
    """Roll and pitch step, deg."""
    hb_quantum: float = param(1e-4, gt=0, unit="m",
                              doc="Hinge heights are rounded to this before building deflection fields, m")
    """Hinge heights are rounded to this before building deflection fields, m."""

    def __post_init__(self) -> None:
        check_fields(self)
        if not self.x_max > self.x_min:
            raise ConfigError("x_max", self.x_max, f"a number > x_min = {self.x_min} (m)")
        ratio = self.angle_max_deg / self.dangle_deg
        if abs(ratio - round(ratio)) > 1e-9:
            raise ValueError(f"dangle_deg = {self.dangle_deg} must divide angle_max_deg = {self.angle_max_deg} "
                             "so that the level pose (0, 0) is a grid node")

    @property
    def xs(self) -> np.ndarray:
        """Grid of x, m, shape (nx,)."""
        n = int(round((self.x_max - self.x_min) / self.dx)) + 1
        return self.x_min + self.dx * np.arange(n)

    @property
    def angles(self) -> np.ndarray:
        """Grid of roll = grid of pitch, rad, shape (na,)."""
        n = int(round(2 * self.angle_max_deg / self.dangle_deg)) + 1
        return np.deg2rad(-self.angle_max_deg + self.dangle_deg * np.arange(n))

    @property
    def shape(self) -> tuple[int, int, int]:
        """(nx, n_alpha, n_beta)."""
        return (self.xs.size, self.angles.size, self.angles.size)


def cache_dir() -> Path:
    """Directory of the on-disk deflection-field cache."""
    root = os.environ.get("TERRABENCH_CACHE")
    base = Path(root) if root else Path.home() / ".cache" / "terrabench"
    return base / "beams"


def _key(robot: RobotParams, layout: BeamLayout, grid: LandscapeConfig, h_b: float, i: int) -> str:
    payload = json.dumps([asdict(robot), asdict(layout), asdict(grid), round(h_b, 9), i, "v1"], sort_keys=True)
    return hashlib.sha256(payload.encode()).hexdigest()[:20]


@lru_cache(maxsize=8)
def _field_cached(robot: RobotParams, layout: BeamLayout, grid: LandscapeConfig, h_b: float, i: int,
                  use_disk: bool) -> np.ndarray:
    path = cache_dir() / f"theta_{_key(robot, layout, grid, h_b, i)}.npy"
    if use_disk and path.exists():
        try:
            arr = np.load(path)
            if arr.shape == grid.shape:
                return arr
        except (OSError, ValueError):
            pass
    if i == 1:
        # beam 2 is the mirror image of beam 1 (y -> -y), i.e. roll -> -roll on the symmetric grid
        arr = _field_cached(robot, layout, grid, h_b, 0, use_disk)[:, ::-1, :].copy()
    else:
        xs, ang = grid.xs, grid.angles
        arr = np.empty(grid.shape, dtype=np.float32)
        for j, x in enumerate(xs):  # one x-slab at a time keeps memory near 100 MB
            arr[j] = deflection_vec(x, ang[:, None], ang[None, :], h_b, 0, robot, layout, iters=32)
    if use_disk:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".{os.getpid()}.tmp.npy")
            np.save(tmp, arr)
            os.replace(tmp, path)
        except OSError:
            pass
    return arr


def deflection_field(robot: RobotParams, layout: BeamLayout, grid: LandscapeConfig, h_b: float, i: int,
                     use_disk: bool = True) -> np.ndarray:
    """Deflection of beam ``i`` over the grid, rad, float32 array of shape ``grid.shape``."""
    h = round(h_b / grid.hb_quantum) * grid.hb_quantum
    return _field_cached(robot, layout, grid, float(h), int(i), use_disk)


@dataclass
class Landscape:
    """Eq. 8 on the grid plus what built it."""

    grid: LandscapeConfig
    energy: np.ndarray
    """Total potential energy, J, shape (nx, na, na)."""
    theta: tuple[np.ndarray, np.ndarray]
    """Deflection fields of both beams, rad."""
    gravity_energy: np.ndarray
    """M g Z_com over (alpha, beta), J, shape (na, na)."""

    def contact_mask(self) -> np.ndarray:
        """True where either beam touches the robot, shape (nx, na, na)."""
        return (self.theta[0] > 0) | (self.theta[1] > 0)

    def index(self, q) -> tuple[int, int, int]:
        """Nearest grid node of a pose (x, alpha, beta), clipped into the grid."""
        xs, ang = self.grid.xs, self.grid.angles
        ix = int(np.clip(np.rint((q[0] - xs[0]) / self.grid.dx), 0, xs.size - 1))
        da = ang[1] - ang[0]
        ia = int(np.clip(np.rint((q[1] - ang[0]) / da), 0, ang.size - 1))
        ib = int(np.clip(np.rint((q[2] - ang[0]) / da), 0, ang.size - 1))
        return ix, ia, ib


def build_landscape(beams: tuple[Beam, Beam], robot: RobotParams = RobotParams(),
                    layout: BeamLayout = BeamLayout(), grid: LandscapeConfig = LandscapeConfig(),
                    gravity: float = 9.81, use_disk: bool = True) -> Landscape:
    """Eq. 8: E(x, alpha, beta) = M g Z_com + 1/2 k1 theta1^2 + 1/2 k2 theta2^2 on the grid.

    Args:
        beams: the (estimated or true) beams; preload and beam mass add tau0 theta and the
            beam-weight energy when present.
        robot, layout: geometry.
        grid: the grid.
        use_disk: read/write the on-disk deflection cache.

    Returns:
        The :class:`Landscape`.
    """
    th = tuple(deflection_field(robot, layout, grid, b.h_b, i, use_disk).astype(np.float64)
               for i, b in enumerate(beams))
    ang = grid.angles
    eg = robot.mass * gravity * com_height(ang[:, None], ang[None, :], robot)
    energy = np.broadcast_to(eg, grid.shape).copy()
    for b, t in zip(beams, th):
        energy += 0.5 * b.k * t * t + b.tau0 * t
        if b.mass:
            energy += 0.5 * (layout.length - b.h_b) * b.mass * gravity * (np.cos(t) - 1.0)
    return Landscape(grid, energy, th, eg)


def pitch_roll_barriers(k: float, robot: RobotParams = RobotParams(), layout: BeamLayout = BeamLayout(),
                        grid: LandscapeConfig = LandscapeConfig()) -> dict[str, float]:
    """Landscape check of Sec. II-G: barrier of the best pure-pitch (alpha = 0) passage versus
    the best contact-free roll passage, both with h_b = 0 and k1 = k2 = k.

    The barrier of a passage is the lowest possible maximum energy rise along a monotone-in-x
    sweep: for each x slice the cheapest admissible pose, then the maximum over x.

    Returns:
        ``pitch`` and ``roll`` barriers in J (relative to the level pose without contact).
    """
    ls = build_landscape((Beam(k), Beam(k)), robot, layout, grid)
    e0 = robot.mass * 9.81 * (robot.height - robot.h_c)
    ia0 = grid.angles.size // 2
    pitch = float((ls.energy[:, ia0, :].min(axis=1)).max() - e0)
    free = np.where(ls.contact_mask(), np.inf, ls.energy)
    roll = float(free.reshape(grid.shape[0], -1).min(axis=1).max() - e0)
    return {"pitch": pitch, "roll": roll}


def critical_stiffness_landscape(robot: RobotParams = RobotParams(), layout: BeamLayout = BeamLayout(),
                                 grid: LandscapeConfig = LandscapeConfig(), k_lo: float = 1e-4,
                                 k_hi: float = 10.0, iters: int = 40) -> float:
    """The landscape's own critical stiffness (N m/rad): the k = k1 = k2 (h_b = 0) at which the
    pitch barrier of :func:`pitch_roll_barriers` equals the roll barrier (the counterpart of the
    paper's k_0 = M g h_c / arccos(H/L)^2). NaN if the crossover is outside [k_lo, k_hi], if no
    roll clears the beams, or if the level robot passes without contact (no choice to make)."""
    th = [deflection_field(robot, layout, grid, 0.0, i).astype(np.float64) for i in range(2)]
    ang = grid.angles
    ia0 = ang.size // 2
    e0 = robot.mass * 9.81 * (robot.height - robot.h_c)
    eg = robot.mass * 9.81 * com_height(ang[:, None], ang[None, :], robot)
    free = np.where((th[0] > 0) | (th[1] > 0), np.inf, np.broadcast_to(eg, grid.shape))
    roll = float(free.reshape(grid.shape[0], -1).min(axis=1).max() - e0)
    sq = th[0][:, ia0, :] ** 2 + th[1][:, ia0, :] ** 2
    eg0 = eg[ia0][None, :]

    def pitch(k: float) -> float:
        return float((eg0 + 0.5 * k * sq).min(axis=1).max() - e0)

    if not np.isfinite(roll) or roll <= 1e-12 or pitch(k_lo) > roll or pitch(k_hi) < roll:
        return float("nan")
    lo, hi = np.log(k_lo), np.log(k_hi)
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        if pitch(float(np.exp(mid))) < roll:
            lo = mid
        else:
            hi = mid
    return float(np.exp(0.5 * (lo + hi)))
