"""Terrain pieces built from boxes: steps, terraces, blocks (reusable by any system).

Every generator is a pure function: explicit arguments (and an explicit
``np.random.Generator`` where anything is random) in, a tuple of :class:`Box` out. Boxes are
axis-aligned in a frame rotated by ``yaw`` about the world z axis through ``origin``; the floor
is z = 0. :func:`add_boxes` puts them into an ``MjSpec`` as static ground geoms and
:func:`height_grid` samples them as a height map (for plots and reports).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from terrabench.terrain.mjcf import GROUND_BIT


@dataclass(frozen=True)
class Box:
    """A static box.

    Attributes:
        name: geom name.
        center: world centre (m), shape (3,).
        half: half sizes along the box's own axes (m), shape (3,).
        yaw: rotation about world z (rad).
    """

    name: str
    center: tuple[float, float, float]
    half: tuple[float, float, float]
    yaw: float = 0.0

    @property
    def top(self) -> float:
        return self.center[2] + self.half[2]


def _place(name: str, x0: float, x1: float, y_half: float, z_top: float, yaw: float,
           origin: tuple[float, float] = (0.0, 0.0), y_center: float = 0.0) -> Box:
    """Box spanning local x in [x0, x1], |y - y_center| < y_half, z in [0, z_top], turned by yaw."""
    cx, cy = 0.5 * (x0 + x1), y_center
    c, s = math.cos(yaw), math.sin(yaw)
    wx = origin[0] + c * cx - s * cy
    wy = origin[1] + s * cx + c * cy
    return Box(name, (wx, wy, 0.5 * z_top), (0.5 * (x1 - x0), y_half, 0.5 * z_top), yaw)


def step(height: float, *, edge_x: float = 0.0, depth: float = 2.0, width: float = 3.0,
         yaw: float = 0.0) -> tuple[Box, ...]:
    """One terrace: a block of ``height`` whose near edge is at local x = ``edge_x``.

    Args:
        height: step height (m), > 0.
        edge_x: distance of the edge from the origin along the (yawed) approach axis (m).
        depth: extent of the top along the approach axis (m).
        width: extent across (m).
        yaw: turn of the step's frame about the world z axis (rad).
    """
    if not height > 0:
        raise ValueError(f"step height must be > 0 m, got {height!r}")
    return (_place("step_0", edge_x, edge_x + depth, width / 2, height, yaw),)


def terraces(heights: Sequence[float], treads: Sequence[float], *, edge_x: float = 0.0,
             last_depth: float = 2.0, width: float = 3.0, yaw: float = 0.0) -> tuple[Box, ...]:
    """A staircase: terrace k rises to the cumulative height ``sum(heights[:k+1])``.

    Args:
        heights: rise of each terrace (m), each > 0.
        treads: depth of every terrace but the last (m), ``len(heights) - 1`` values.
        edge_x: the first edge along the approach axis (m).
        last_depth: depth of the top terrace (m).
    """
    if len(treads) != len(heights) - 1:
        raise ValueError(f"need {len(heights) - 1} treads for {len(heights)} terraces, got {len(treads)}")
    if any(not h > 0 for h in heights):
        raise ValueError(f"terrace heights must be > 0 m, got {list(heights)}")
    out, x, z = [], edge_x, 0.0
    for k, h in enumerate(heights):
        z += h
        # each terrace is a box from its edge to the far end (boxes overlap: a solid staircase)
        end = edge_x + sum(treads) + last_depth
        out.append(_place(f"terrace_{k}", x, end, width / 2, z, yaw))
        if k < len(treads):
            x += treads[k]
    return tuple(out)


def block(height: float, length: float, width: float, *, x0: float, y_center: float,
          yaw: float = 0.0) -> tuple[Box, ...]:
    """A lone block (e.g. a concrete block beside a path) from local x0 to x0 + length."""
    if not height > 0:
        raise ValueError(f"block height must be > 0 m, got {height!r}")
    return (_place("block_0", x0, x0 + length, width / 2, height, yaw, y_center=y_center),)


def jitter(rng: np.random.Generator, offset: float, yaw_deg: float) -> tuple[float, float]:
    """A random lateral offset (m) and yaw (rad) of an approach, uniform in +-offset, +-yaw_deg."""
    return float(rng.uniform(-offset, offset)), float(math.radians(rng.uniform(-yaw_deg, yaw_deg)))


def add_boxes(spec, boxes: Sequence[Box], *, friction: float = 1.0, rgba=(0.6, 0.58, 0.52, 1.0)) -> list:
    """Add static boxes to ``spec``'s world body as ground geoms (collision bit ``GROUND_BIT``)."""
    import mujoco

    geoms = []
    for b in boxes:
        half = b.yaw / 2
        geoms.append(spec.worldbody.add_geom(
            name=b.name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(b.center), size=list(b.half),
            quat=[math.cos(half), 0.0, 0.0, math.sin(half)], friction=[friction, 0.005, 0.0001],
            contype=GROUND_BIT, conaffinity=0, rgba=list(rgba)))
    return geoms


def height_at(boxes: Sequence[Box], x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Ground height (m) at world points (any equal shapes): the highest box top covering it, else 0."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    h = np.zeros(np.broadcast(x, y).shape)
    for b in boxes:
        c, s = math.cos(b.yaw), math.sin(b.yaw)
        dx, dy = x - b.center[0], y - b.center[1]
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        inside = (np.abs(lx) <= b.half[0]) & (np.abs(ly) <= b.half[1])
        h = np.where(inside, np.maximum(h, b.top), h)
    return h


def height_grid(boxes: Sequence[Box], x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Heights (m) on the grid ``x`` (nx,) by ``y`` (ny,): shape (nx, ny)."""
    X, Y = np.meshgrid(np.asarray(x, float), np.asarray(y, float), indexing="ij")
    return height_at(boxes, X, Y)
