"""Courses: a lane with a start, one terrain feature and a goal line, for any robot footprint.

The zoo's terrain families (:mod:`terrabench.zoo.families`) build their scenes from these pure
pieces: :class:`Course` holds static boxes (:class:`terrabench.terrain.pieces.Box`), an optional
floor plane, an optional heightfield and an optional soil name. Conventions: the robot drives
along +x; the feature starts at x = 0; the lane is centred on y = 0.
:func:`add_course` puts a course into an ``MjSpec`` with the collision bits a robot needs (each
system has its own), :meth:`Course.height` samples it (tests, start heights, plots).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from terrabench.terrain.pieces import Box


def span_box(name: str, x0: float, x1: float, top: float, width: float, bottom: float = 0.0) -> Box:
    """A box across the lane from x0 to x1 (m), from ``bottom`` up to ``top`` (m), ``width`` wide."""
    if not (x1 > x0 and top > bottom and width > 0):
        raise ValueError(f"box {name!r} needs x1 > x0, top > bottom and width > 0; got x {x0}..{x1}, "
                         f"z {bottom}..{top}, width {width}")
    return Box(name, (0.5 * (x0 + x1), 0.0, 0.5 * (top + bottom)), (0.5 * (x1 - x0), 0.5 * width,
                                                                      0.5 * (top - bottom)))


@dataclass(frozen=True)
class HField:
    """A heightfield: heights ``h`` (nx, ny) at ``x`` (nx,) by ``y`` (ny,), both evenly spaced, increasing (m)."""

    h: np.ndarray
    x: np.ndarray
    y: np.ndarray

    def at(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Bilinear heights (m) at points (clamped to the field's edges)."""
        from scipy.interpolate import RegularGridInterpolator

        f = RegularGridInterpolator((self.x, self.y), self.h, bounds_error=False, fill_value=None)
        xx = np.clip(np.asarray(x, float), self.x[0], self.x[-1])
        yy = np.clip(np.asarray(y, float), self.y[0], self.y[-1])
        return f(np.stack([xx, yy], axis=-1))


@dataclass(frozen=True)
class Course:
    """One scene of a terrain family at one severity for one footprint.

    Attributes:
        family, severity: what it is (severity in the family's unit).
        boxes: static boxes (rigid).
        floor_z: height of an infinite floor plane (m); None: no plane.
        hfield: the heightfield, or None.
        soil: soil name (a preset of :mod:`terrabench.soil.presets` / ``srwmr.soils``) of the ground
            under the wheels, None for rigid ground.
        feature: (x0, x1) of the feature along x (m).
        start_front: x of the robot's front at the start (m).
        goal_x: the goal line: success once the robot's rearmost point passes it (m).
        lane: lane width (m) (boxes and heightfields span it).
        fall_z: a robot whose lowest tracked body is below this has fallen (m).
        x_range: (x_min, x_max) of the built ground (m).
        note: one line saying what the scene is.
    """

    family: str
    severity: float
    boxes: tuple[Box, ...] = ()
    floor_z: float | None = 0.0
    hfield: HField | None = None
    soil: str | None = None
    feature: tuple[float, float] = (0.0, 0.0)
    start_front: float = -0.4
    goal_x: float = 0.3
    lane: float = 2.0
    fall_z: float = -0.5
    x_range: tuple[float, float] = (-5.0, 5.0)
    note: str = ""
    extra: dict = field(default_factory=dict)

    def height(self, x, y) -> np.ndarray:
        """Ground height (m) at world points: the highest of the floor, the boxes and the heightfield."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        shape = np.broadcast(x, y).shape
        h = np.full(shape, -np.inf if self.floor_z is None else self.floor_z)
        for b in self.boxes:
            inside = (np.abs(x - b.center[0]) <= b.half[0]) & (np.abs(y - b.center[1]) <= b.half[1])
            h = np.where(inside, np.maximum(h, b.top), h)
        if self.hfield is not None:
            hf = self.hfield
            inside = (x >= hf.x[0]) & (x <= hf.x[-1]) & (y >= hf.y[0]) & (y <= hf.y[-1])
            h = np.where(inside, np.maximum(h, hf.at(x, y)), h)
        return h

    def max_height(self, x0: float, x1: float, half_width: float, n: int = 41) -> float:
        """Highest ground (m) over the rectangle x0..x1, |y| <= half_width (the start footprint)."""
        X, Y = np.meshgrid(np.linspace(x0, x1, n), np.linspace(-half_width, half_width, 11), indexing="ij")
        h = self.height(X, Y)
        return float(np.max(h[np.isfinite(h)])) if np.isfinite(h).any() else 0.0


def profile_hfield(profile: Callable[[np.ndarray], np.ndarray], x0: float, x1: float, lane: float,
                   dx: float = 0.02, ny: int = 9) -> HField:
    """A heightfield that varies along x only: ``profile(x) -> z`` (m) over x0..x1, the lane wide."""
    x = np.arange(x0, x1 + 1e-9, dx)
    y = np.linspace(-lane / 2, lane / 2, ny)
    z = np.asarray(profile(x), float)
    return HField(np.repeat(z[:, None], ny, axis=1), x, y)


def window(x: np.ndarray, x0: float, x1: float, ramp: float) -> np.ndarray:
    """1 inside [x0 + ramp, x1 - ramp], 0 outside [x0, x1], a cosine ramp between (-)."""
    x = np.asarray(x, float)
    up = np.clip((x - x0) / ramp, 0.0, 1.0)
    down = np.clip((x1 - x) / ramp, 0.0, 1.0)
    return 0.5 * (1 - np.cos(math.pi * up)) * 0.5 * (1 - np.cos(math.pi * down))


#: the rough family's three channels: wavelength as a fraction of the base wavelength, and weight
#: (the weights of the MRS-CWC sine-sum channels, :data:`terrabench.terrain.sine_sum.CHANNEL_WEIGHT`)
ROUGH_CHANNELS = ((1.0, 1.0), (1.0 / 3.0, 0.5), (1.0 / 7.5, 0.1))


def sine_sum_field(amplitude: float, wavelength: float, x: np.ndarray, y: np.ndarray,
                   rng: np.random.Generator) -> np.ndarray:
    """Sine-sum roughness of peak amplitude at most ``amplitude`` (m): three channels at
    ``wavelength`` x (1, 1/3, 1/7.5) (m), weights 1, 0.5, 0.1, random phases; shape (nx, ny)."""
    X, Y = np.meshgrid(np.asarray(x, float), np.asarray(y, float), indexing="ij")
    total = np.zeros_like(X)
    wsum = sum(w for _, w in ROUGH_CHANNELS)
    for frac, w in ROUGH_CHANNELS:
        lam = wavelength * frac
        px, py = rng.uniform(0, 2 * math.pi, 2)
        total += w * 0.5 * (np.sin(2 * math.pi * X / lam + px) + np.sin(2 * math.pi * Y / lam + py))
    return amplitude * total / wsum


def add_course(spec, course: Course, *, contype: int, conaffinity: int, friction: float,
               hfield_name: str = "zoo_ground", rgba: Sequence[float] = (0.55, 0.52, 0.46, 1.0)) -> dict:
    """Add the course's ground to ``spec`` (floor plane, boxes, heightfield) with the robot's
    collision bits; returns ``{"plane": geom|None, "hfield": geom|None, "boxes": [geoms]}``."""
    import mujoco

    from terrabench.terrain.mjcf import add_heightfield

    out: dict = {"plane": None, "hfield": None, "boxes": []}
    fr = [friction, 0.005, 0.0001]
    if course.floor_z is not None:
        out["plane"] = spec.worldbody.add_geom(
            name="zoo_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[60, 60, 0.1], pos=[0, 0, course.floor_z],
            friction=fr, contype=contype, conaffinity=conaffinity, rgba=[0.5, 0.5, 0.5, 1])
    for b in course.boxes:
        out["boxes"].append(spec.worldbody.add_geom(
            name=f"zoo_{b.name}", type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(b.center), size=list(b.half),
            friction=fr, contype=contype, conaffinity=conaffinity, rgba=list(rgba)))
    if course.hfield is not None:
        hf = course.hfield
        g = add_heightfield(spec, hf.h, hf.x, hf.y, name=hfield_name, friction=friction)
        g.contype, g.conaffinity = contype, conaffinity
        out["hfield"] = g
    return out
