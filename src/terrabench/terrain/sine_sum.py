"""The sine-sum heightfield family of the MRS-CWC benchmark (spec section 1).

Every function here is pure: a :class:`SineSumParams` (one CSV row) in, heights in metres
out. The construction reproduces the released CoppeliaSim scenes: grid indices start at 1,
``u = i / nx`` runs from ``1/nx`` to 1, and the grid's ``j = 1`` row is the +Y edge.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Frequency multipliers and weights of the three channels (spec section 1).
CHANNEL_OMEGA = (20.0, 60.0, 150.0)
CHANNEL_WEIGHT = (1.0, 0.5, 0.1)
#: Where the terrain's centre sits in the world (m).
CENTRE_XY = (4.05, -4.475)


@dataclass(frozen=True)
class SineSumParams:
    """One row of the released terrain CSVs.

    Attributes:
        size: normalised size; side length ``L = 5 + 195*size`` (m).
        xy_proportion: grid aspect; 0.5 gives 64 x 64 vertices.
        height: normalised height; height scale ``Zs = 20*height`` (m).
        freq: the three channels' frequency parameters (dimensionless).
        ampl: the three channels' amplitudes (dimensionless).
        phase: the three channels' phases (cycles).
    """

    size: float
    xy_proportion: float
    height: float
    freq: tuple[float, float, float]
    ampl: tuple[float, float, float]
    phase: tuple[float, float, float]

    def __post_init__(self) -> None:
        for name in ("size", "height"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"terrain {name} must be a positive number, got {value!r}")
        if not (0.0 <= self.xy_proportion <= 1.0):
            raise ValueError(f"terrain xy_proportion must be in [0, 1], got {self.xy_proportion!r}")
        for name in ("freq", "ampl", "phase"):
            value = getattr(self, name)
            if len(value) != 3 or not all(math.isfinite(v) for v in value):
                raise ValueError(f"terrain {name} must be three finite numbers, got {value!r}")

    @property
    def side(self) -> float:
        """Side length L (m)."""
        return 5.0 + 195.0 * self.size

    @property
    def z_scale(self) -> float:
        """Height scale Zs (m)."""
        return 20.0 * self.height

    @property
    def shape(self) -> tuple[int, int]:
        """Vertex counts ``(nx, ny)``."""
        p = self.xy_proportion
        if p > 0.5:
            return 6 + 2 * math.floor(58 * (1 - p)), 64
        return 64, 6 + 2 * math.floor(58 * p)


def _surface(params: SineSumParams, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    total = np.zeros(np.broadcast(u, v).shape)
    for w, weight, f, a, ph in zip(CHANNEL_OMEGA, CHANNEL_WEIGHT, params.freq, params.ampl, params.phase):
        base = 2.0 * math.pi * ph
        total = total + weight * 0.5 * a * (np.sin(base + w * f * u) + np.sin(base + w * f * v))
    return params.z_scale * total


def heights(params: SineSumParams) -> np.ndarray:
    """Vertex heights, shape ``(nx, ny)``, indexed ``[i-1, j-1]`` as in the spec (m)."""
    nx, ny = params.shape
    u = (np.arange(1, nx + 1) / nx)[:, None]
    v = (np.arange(1, ny + 1) / ny)[None, :]
    return _surface(params, u, v)


def spacing(params: SineSumParams) -> tuple[float, float]:
    """Grid spacing ``(dx, dy)`` between vertices (m); the side spans nx-1 intervals."""
    nx, ny = params.shape
    return params.side / (nx - 1), params.side / (ny - 1)


def vertex_xy(params: SineSumParams) -> tuple[np.ndarray, np.ndarray]:
    """World coordinates of the vertices: ``x`` of shape (nx,), ``y`` of shape (ny,), y decreasing."""
    nx, ny = params.shape
    dx, dy = spacing(params)
    half = params.side / 2
    x = CENTRE_XY[0] - half + np.arange(nx) * dx
    y = CENTRE_XY[1] + half - np.arange(ny) * dy
    return x, y


def point_height(params: SineSumParams, x: float | np.ndarray, y: float | np.ndarray) -> np.ndarray:
    """The released scenes' look-up for placing start and target: u, v snapped to 1/64 (m)."""
    nx, ny = params.shape
    half = params.side / 2
    u = (np.asarray(x, float) - CENTRE_XY[0] + half) / params.side
    v = (half - (np.asarray(y, float) - CENTRE_XY[1])) / params.side
    u = np.round(u * nx) / nx
    v = np.round(v * ny) / ny
    return _surface(params, u, v)


def random_params(rng: np.random.Generator, *, height_range: tuple[float, float] = (0.0, 1.0)) -> SineSumParams:
    """Draw a new terrain of the same family (uniform channel parameters in [0, 1)).

    The released rows have Size 0.05 and XY Proportion 0.5 throughout and channel parameters
    in [0, 1); ``height_range`` bounds the normalised height (the released rows span
    0.002-0.98).
    """
    f, a, p = rng.random(3), rng.random(3), rng.random(3)
    return SineSumParams(
        size=0.05,
        xy_proportion=0.5,
        height=float(rng.uniform(*height_range)),
        freq=tuple(map(float, f)),
        ampl=tuple(map(float, a)),
        phase=tuple(map(float, p)),
    )
