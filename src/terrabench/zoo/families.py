"""The zoo's terrain families: one severity parameter each, a scene for any robot footprint.

Every family builds a :class:`~terrabench.terrain.course.Course` from the shared terrain code
(boxes of :mod:`terrabench.terrain.pieces`, heightfields, the sine-sum channels of
:mod:`terrabench.terrain.sine_sum`, the released MRS-CWC terrains of
:mod:`terrabench.terrain.dataset`, the soil presets). The layout is the same for every family
and robot: the robot's front starts ``course.run_up`` before the feature at x = 0, the goal
line is ``course.goal_past`` past the feature's end, and success is the robot's *rearmost*
point passing it (the whole body crossed). The lane is the robot's width plus two margins.

A severity is a token in the instance id (``step-up@0.15``) with a number for the plots
(:meth:`Family.value`); two families have named points: ``rough-mrs@A`` / ``@B`` (the released
MRS-CWC groups; value: the terrain's mean axis slope, deg) and ``soft-flat@<soil>`` (value: the
HIT-MRII wheel's static Bekker sinkage on that soil, mm, so the points sort by softness).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from terrabench.terrain.course import Course, HField, profile_hfield, sine_sum_field, span_box, window
from terrabench.zoo.adapter import Footprint
from terrabench.zoo.config import CourseConfig

#: soils of the slope families (one family per soil) and of soft-flat; the srwmr calibrated pair
#: first (``srwmr.soils``), then presets of :mod:`terrabench.soil.presets`
SLOPE_SOILS = ("very_loose", "loose", "dry_sand", "lunar_regolith")
SOFT_SOILS = ("very_loose", "loose", "mars_soft", "mars_very_loose", "mars_loose", "dry_sand", "lunar_regolith")
#: the HIT-MRII wheel and its nominal load: the reference of soft-flat's sinkage scale
REF_WHEEL_B, REF_WHEEL_D, REF_LOAD = 0.12, 0.30, 225.0 * 9.81 / 6


@dataclass(frozen=True)
class Family:
    """One terrain family.

    Attributes:
        id: family id (the part of an instance id before ``@``).
        title: one line for the report.
        severity: what the severity is (``"step height"``).
        unit: its unit (``"m"``, ``"deg"``, ``"mm sinkage"``).
        quick, full: severity tokens of the quick and full groups.
        build: ``(token, footprint, course cfg, rng) -> Course``.
        relative: ``(label, fn(value, footprint) -> float)``: the severity in the robot's own size.
        rigid: no soil (every robot with a rigid contact model may enter).
    """

    id: str
    title: str
    severity: str
    unit: str
    quick: tuple[str, ...]
    full: tuple[str, ...]
    build: Callable[[str, Footprint, CourseConfig, np.random.Generator], Course]
    relative: tuple[tuple[str, Callable[[float, Footprint], float]], ...] = ()
    rigid: bool = True

    def value(self, token: str) -> float:
        """The severity of ``token`` as a number (in :attr:`unit`)."""
        if self.id == "rough-mrs":
            return mrs_group_terrain(token)[1]
        if self.id == "soft-flat":
            return soil_sinkage_mm(token)
        return float(token)

    def instance(self, token: str) -> str:
        return f"{self.id}@{token}"

    def course(self, token: str, fp: Footprint, cfg: CourseConfig, seed: int = 0) -> Course:
        if token not in self.full and token not in self.quick:
            # numeric families take any value in range (a user's own severity)
            if self.id in ("rough-mrs", "soft-flat"):
                raise ValueError(f"zoo family {self.id!r} has no severity {token!r}; valid: {', '.join(self.full)}")
        return self.build(token, fp, cfg, np.random.default_rng(7000 + seed))


# ---------------------------------------------------------------------------- shared layout
def _frame(fp: Footprint, cfg: CourseConfig, feature_end: float) -> tuple[float, float, float, float]:
    """(lane width, x_min, goal_x, x_max) of a course whose feature ends at ``feature_end``."""
    lane = fp.width + 2 * cfg.lane_margin
    # ground behind the start: 1 m plus two robot lengths (courses without a floor plane end
    # there, and a robot that backs or scatters, like the MRS-D units, must not fall off it)
    x_min = -cfg.run_up - 3.0 * fp.length - 1.0
    goal = feature_end + cfg.goal_past
    return lane, x_min, goal, goal + fp.length + cfg.run_out


def _positive(token: str, what: str, hi: float) -> float:
    v = float(token)
    if not (0 < v <= hi):
        raise ValueError(f"zoo {what} {token!r} out of range; valid: (0, {hi:g}]")
    return v


def _step_up(token, fp, cfg, rng) -> Course:
    h = _positive(token, "step-up height (m)", 2.0)
    lane, x0, goal, x1 = _frame(fp, cfg, 0.0)
    return Course("step-up", h, (span_box("step", 0.0, x1, h, lane),), 0.0, None, None, (0.0, 0.0),
                  -cfg.run_up, goal, lane, -cfg.fall_drop, (x0, x1), f"a {h:g} m step up at x = 0")


def _step_down(token, fp, cfg, rng) -> Course:
    h = _positive(token, "step-down height (m)", 2.0)
    lane, x0, goal, x1 = _frame(fp, cfg, 0.0)
    return Course("step-down", h, (span_box("ledge", x0, 0.0, h, lane),), 0.0, None, None, (0.0, 0.0),
                  -cfg.run_up, goal, lane, -cfg.fall_drop, (x0, x1), f"a {h:g} m step down at x = 0")


def _gap(token, fp, cfg, rng) -> Course:
    w = _positive(token, "gap width (m)", 5.0)
    d = cfg.ditch_depth
    lane, x0, goal, x1 = _frame(fp, cfg, w)
    boxes = (span_box("rim_near", x0, 0.0, d, lane), span_box("rim_far", w, x1, d, lane))
    return Course("gap", w, boxes, 0.0, None, None, (0.0, w), -cfg.run_up, goal, lane, d - cfg.fall_drop, (x0, x1),
                  f"a ditch {w:g} m wide and {d:g} m deep from x = 0")


def _block(token, fp, cfg, rng) -> Course:
    h = _positive(token, "block height (m)", 2.0)
    L = cfg.block_length
    lane, x0, goal, x1 = _frame(fp, cfg, L)
    return Course("block", h, (span_box("block", 0.0, L, h, lane),), 0.0, None, None, (0.0, L), -cfg.run_up, goal,
                  lane, -cfg.fall_drop, (x0, x1), f"a block {h:g} m high, {L:g} m long across the lane at x = 0")


def _slope_family(soil: str | None):
    fid = "slope-rigid" if soil is None else f"slope-{soil}"

    def build(token, fp, cfg, rng) -> Course:
        deg = float(token)
        if not (0 <= deg < 60):
            raise ValueError(f"zoo slope angle {token!r} out of range; valid: [0, 60) deg")
        L, t = cfg.slope_length, math.tan(math.radians(deg))
        lane, x0, goal, x1 = _frame(fp, cfg, L)
        hf = profile_hfield(lambda x: t * np.clip(x, 0.0, L), x0, x1, lane, dx=cfg.grid)
        where = "rigid ground" if soil is None else f"{soil} soil"
        return Course(fid, deg, (), None, hf, soil, (0.0, L), -cfg.run_up, goal, lane, -cfg.fall_drop, (x0, x1),
                      f"a {deg:g} deg ramp {L:g} m long of {where}, then level")

    return fid, build


def _grid(x0: float, x1: float, lane: float, d: float) -> tuple[np.ndarray, np.ndarray]:
    """Grid points along x on multiples of ``d`` (the same samples for every footprint), and
    across the lane (an odd count: y = 0 is a sample)."""
    n = max(3, int(round(lane / d)) + 1)
    n += 1 - n % 2
    k0, k1 = math.floor(x0 / d), math.ceil(x1 / d)
    return np.arange(k0, k1 + 1) * d, np.linspace(-lane / 2, lane / 2, n)


def _rough_sine(token, fp, cfg, rng) -> Course:
    a = _positive(token, "roughness amplitude (m)", 2.0)
    L = cfg.rough_length
    lane, x0, goal, x1 = _frame(fp, cfg, L)
    x, y = _grid(x0, x1, lane, cfg.grid)
    h = window(x, 0.0, L, cfg.rough_ramp)[:, None] * sine_sum_field(a, cfg.rough_wavelength, x, y, rng)
    return Course("rough-sine", a, (), None, HField(h, x, y), None, (0.0, L), -cfg.run_up, goal, lane,
                  -a - cfg.fall_drop, (x0, x1),
                  f"sine-sum roughness, amplitude {a:g} m, wavelength {cfg.rough_wavelength:g} m, {L:g} m long")


@functools.cache
def mrs_group_terrain(group: str) -> tuple[str, float]:
    """The released MRS-CWC terrain standing for ``group`` (A or B): the one of median mean axis
    slope in its group; (terrain id, its mean axis slope in deg)."""
    from terrabench.terrain import dataset

    if group not in dataset.GROUPS:
        raise ValueError(f"zoo rough-mrs point {group!r}; valid: {', '.join(dataset.GROUPS)}")
    ts = sorted(dataset.select(None, group), key=lambda t: (t.stats()["mean_axis_slope_deg"], t.id))
    t = ts[len(ts) // 2]
    return t.id, float(t.stats()["mean_axis_slope_deg"])


def _rough_mrs(token, fp, cfg, rng) -> Course:
    from scipy.interpolate import RegularGridInterpolator

    from terrabench.terrain import dataset, sine_sum

    tid, slope = mrs_group_terrain(token)
    p = dataset.get(tid).params
    vx, vy = sine_sum.vertex_xy(p)
    H = sine_sum.heights(p)
    f = RegularGridInterpolator((vx, vy[::-1]), H[:, ::-1])
    L = cfg.rough_length
    lane, x0, goal, x1 = _frame(fp, cfg, L)
    x, y = _grid(x0, x1, lane, cfg.grid)
    # the strip runs along +x through the terrain's centre line, its start 3 m into the terrain
    # (the feature's start x = 0 is 3 m into the terrain for every footprint: the same strip for
    # every robot; outside the feature the window is 0, so points there are clamped to the terrain)
    X, Y = np.meshgrid(np.clip(x + vx[0] + 3.0, vx[0], vx[-1]), y + sine_sum.CENTRE_XY[1], indexing="ij")
    Hs = f(np.stack([X, Y], axis=-1))
    w = window(x, 0.0, L, cfg.rough_ramp)[:, None]
    inside = w > 0
    band = np.abs(y) <= 0.5  # the mean over a fixed band, not the robot's lane: one strip for all
    h = w * (Hs - float(Hs[inside.ravel()][:, band].mean()))
    return Course("rough-mrs", slope, (), None, HField(h, x, y), None, (0.0, L), -cfg.run_up, goal, lane,
                  float(h.min()) - cfg.fall_drop, (x0, x1),
                  f"a {L:g} m strip of released terrain {tid} (group {token}, mean axis slope {slope:.1f} deg)",
                  {"terrain": tid})


def soil_sinkage_mm(name: str) -> float:
    """Static sinkage (mm) of the HIT-MRII wheel (b 0.12 m, D 0.30 m) at its nominal load on soil
    ``name`` (Bekker's rigid-wheel formula z0 = (3W / ((3 - n)(k_c + b k_phi) sqrt(D)))^(2/(2n+1)))."""
    from terrabench.systems.srwmr.soils import srwmr_soil

    s = srwmr_soil(name)
    z = (3 * REF_LOAD / ((3 - s.n) * (s.k_c + REF_WHEEL_B * s.k_phi) * math.sqrt(REF_WHEEL_D))) ** (2 / (2 * s.n + 1))
    return 1000.0 * z


def _soft_flat(token, fp, cfg, rng) -> Course:
    from terrabench.systems.srwmr.soils import SOIL_NAMES

    if token not in SOIL_NAMES:
        raise ValueError(f"zoo soft-flat soil {token!r}; valid: {', '.join(SOIL_NAMES)}")
    L = cfg.soft_length
    lane, x0, goal, x1 = _frame(fp, cfg, L)
    return Course("soft-flat", soil_sinkage_mm(token), (), 0.0, None, token, (0.0, L), -cfg.run_up, goal, lane,
                  -cfg.fall_drop - 0.5, (x0, x1), f"level {token} soil ({soil_sinkage_mm(token):.0f} mm reference "
                  f"sinkage); {L:g} m counted")


def _mixed(token, fp, cfg, rng) -> Course:
    s = _positive(token, "mixed-course scale", 10.0)
    H, g, b = 0.1 * s, 0.15 * s, 0.06 * s
    end = 2.9 + g
    lane, x0, goal, x1 = _frame(fp, cfg, end)
    boxes = (span_box("terrace_a", 0.0, 1.0, H, lane), span_box("terrace_b", 1.0 + g, 2.0 + g, H, lane),
             span_box("block", 2.6 + g, end, b, lane))
    return Course("mixed", s, boxes, 0.0, None, None, (0.0, end), -cfg.run_up, goal, lane, -cfg.fall_drop, (x0, x1),
                  f"step up {H:g} m, a {g:g} m gap in the terrace, step down {H:g} m, a {b:g} m block")


def _wheel_radii(v: float, fp: Footprint) -> float:
    return v / fp.wheel_radius


def _heights(v: float, fp: Footprint) -> float:
    return v / fp.height


def _lengths(v: float, fp: Footprint) -> float:
    return v / fp.length


STEP_REL = (("wheel radii", _wheel_radii), ("body heights", _heights))
_FAMILIES: list[Family] = [
    Family("step-up", "step up onto a terrace", "step height", "m", ("0.05", "0.15", "0.3"),
           ("0.025", "0.05", "0.1", "0.15", "0.2", "0.3", "0.4", "0.5"), _step_up, STEP_REL),
    Family("step-down", "step down off a ledge", "drop height", "m", ("0.1", "0.3", "0.6"),
           ("0.05", "0.1", "0.2", "0.3", "0.45", "0.6", "0.8"), _step_down, STEP_REL),
    Family("gap", "a ditch across the path", "gap width", "m", ("0.1", "0.3", "0.6"),
           ("0.05", "0.1", "0.2", "0.3", "0.45", "0.6", "0.8"), _gap,
           (("body lengths", _lengths), ("wheel radii", _wheel_radii))),
    Family("block", "a block across the path", "block height", "m", ("0.05", "0.15", "0.3"),
           ("0.025", "0.05", "0.1", "0.15", "0.2", "0.3", "0.4"), _block, STEP_REL),
]
for _soil in (None,) + SLOPE_SOILS:
    _fid, _build = _slope_family(_soil)
    _FAMILIES.append(Family(
        _fid, "a ramp on rigid ground" if _soil is None else f"a ramp of {_soil} soil", "slope angle", "deg",
        ("10", "20", "30") if _soil is None else ("10", "20"),
        ("5", "10", "15", "20", "25", "30", "35") if _soil is None else ("5", "10", "15", "20", "25"),
        _build, (), _soil is None))
_FAMILIES += [
    Family("rough-sine", "sine-sum roughness at a fixed wavelength", "amplitude", "m", ("0.02", "0.05", "0.1"),
           ("0.01", "0.02", "0.035", "0.05", "0.075", "0.1", "0.15"), _rough_sine,
           (("wheel radii", _wheel_radii), ("body heights", _heights))),
    Family("rough-mrs", "a strip of the released MRS-CWC terrains (groups A, B)", "mean axis slope", "deg",
           ("A", "B"), ("A", "B"), _rough_mrs),
    Family("soft-flat", "level soft soil (the soil presets)", "reference sinkage", "mm",
           ("loose", "very_loose", "lunar_regolith", "mars_soft"), SOFT_SOILS, _soft_flat, (), False),
    Family("mixed", "a mixed course: step up, a gap in the terrace, step down, a block", "scale", "x",
           ("0.5", "1", "2"), ("0.25", "0.5", "1", "1.5", "2", "3"), _mixed,
           (("step in wheel radii", lambda v, fp: 0.1 * v / fp.wheel_radius),)),
]
FAMILIES: dict[str, Family] = {f.id: f for f in _FAMILIES}


def family(fid: str) -> Family:
    """A family by id; ValueError naming the valid ones."""
    if fid not in FAMILIES:
        raise ValueError(f"unknown zoo family {fid!r}; valid: {', '.join(FAMILIES)}")
    return FAMILIES[fid]


def parse_instance(instance: str) -> tuple[Family, str]:
    """``"step-up@0.15"`` -> (the step-up family, ``"0.15"``); ValueError naming the form."""
    fid, at, token = instance.partition("@")
    if not at or not token:
        raise ValueError(f"zoo instance {instance!r} is not FAMILY@SEVERITY (e.g. step-up@0.15); "
                         f"families: {', '.join(FAMILIES)}")
    return family(fid), token


def instances(group: str) -> list[str]:
    """Instance ids of ``quick`` or ``full`` (family-major, severities rising)."""
    out = []
    for f in FAMILIES.values():
        toks = f.quick if group == "quick" else f.full
        out += [f.instance(t) for t in toks]
    return out
