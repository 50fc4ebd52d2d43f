"""The paper's tasks a simulation can repeat, as terrain + the scripted operator's plan.

Every instance is ``(ground profile, obstacles, soil, plan per method, goal, time limit)``. The
ground is a piecewise-linear profile along x (flat, a ramp, a pit), used both by the soil forces
(:func:`profile_ground`) and, as tilted planks, for the rigid links. Plans are lists of
:class:`~terrabench.systems.srwmr.modes.Step`.

Each instance is registered where its builder is defined, with :func:`instance`: its group, the
methods that apply (the paper ran one or two modes per task) and its time limit. Adding a task
is one decorated function; planning, ``terrabench list`` and the resolved time limit read the
registry (:data:`REGISTRY`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from terrabench.systems.srwmr.modes import Step
from terrabench.systems.srwmr.robot import RobotConfig

#: the slope sweep (group ``slopes``): angles (deg) on each soil
SLOPE_ANGLES = (0, 5, 10, 15, 20, 25)
SLOPE_SOILS = ("very_loose", "loose")
SLOPES = tuple(f"slope-{a}-{s}" for s in SLOPE_SOILS for a in SLOPE_ANGLES)
#: T14 obstacle (m): length along the path, width, height [S 150 x 550 x 190 mm]; margin [S 300 mm]
OBSTACLE = (0.15, 0.55, 0.19)
MARGIN = 0.3
#: T2 brick wall and rock pile (m): half sizes (x, y, z) [R: taller than the 250 mm clearance, so
#: the chassis cannot straddle them and the rover must crab past]
T2_WALL = (0.12, 0.5, 0.2)
T2_ROCKS = (0.15, 0.3, 0.15)
#: T9 end position B (m, start frame) and the obstacle centre on the start heading [R]
T9_B = (3.0, 2.0)
T9_OBSTACLE_X = 2.8
#: T9 WRM path: a straight start, a 45 deg left arc of this radius (m), then straight to B
T9_RADIUS = 2.0
#: T10 chassis heights (m), held and changed in this order [S Task 10: 250, 450, 150, 550, 250 mm;
#: the fitted linkage reaches 534 mm at most and RCLM's MC#3 stops it near 490 mm (docs/srwmr.md,
#: "Linkage fit"), so 480 (T3's height) for 550]
T10_HEIGHTS = (0.25, 0.45, 0.15, 0.48, 0.25)
#: T10 distance driven at each held height (m) [R]
T10_HOLD = 0.45
#: T15 yaw rates (rad/s) [S 0.02, 0.03] and the clearances the chassis is lowered between (m) [R]
T15_RATES = {"t15-w002": 0.02, "t15-w003": 0.03}
T15_CLEARANCE = (0.45, 0.15)
#: in-place steering at a held clearance: the yaw rates (rad/s) [S sec. 8.6: "commanded to rotate
#: about its vertical axis with constant desired body yaw rates 0.01 rad/s and 0.02 rad/s"; "the
#: measured yaw rates were approximately one-fifth of the commanded values"], the duration (s) [R:
#: the paper's T_s is lost; long enough for the rate to settle] at the nominal clearance [R]
STEER_RATES = {"steer-w001": 0.01, "steer-w002": 0.02}
STEER_S = 200.0


@dataclass(frozen=True)
class Layout:
    """One instance: ``profile`` ((x, z), ...) of the ground, ``boxes`` ((cx, cy, hx, hy, hz), ...)
    obstacles on it, the soil name, the plan, the success line ``goal_x`` (chassis x, m; None:
    the plan's end), the start height offset ``z0`` (m) of the ground, the slope ``slope_deg``
    (deg, along x, as reported) and the cross slope ``cross_deg`` (deg: the ground rises toward
    +y, the robot's left at the start, by tan(cross_deg) per m, added to the profile within the
    heightfield's |y| <= 2.5 m; ``boxes`` stand on the profile alone). The time limit is the
    registration's (:class:`Entry`)."""

    profile: tuple
    boxes: tuple
    soil: str
    plan: tuple
    goal_x: float | None
    z0: float = 0.0
    slope_deg: float = 0.0
    cross_deg: float = 0.0
    note: str = ""


def profile_ground(profile):
    """``ground(x, y) -> (z, normal)`` for the soil hook from a piecewise-linear profile."""
    px = np.array([p[0] for p in profile], float)
    pz = np.array([p[1] for p in profile], float)
    slope = np.diff(pz) / np.diff(px)

    def ground(x, y):
        x = np.asarray(x, float)
        z = np.interp(x, px, pz)
        i = np.clip(np.searchsorted(px, x) - 1, 0, len(slope) - 1)
        g = slope[i]
        n = np.empty((x.size, 3))
        inv = 1.0 / np.sqrt(1.0 + g * g)
        n[:, 0] = -g * inv
        n[:, 1] = 0.0
        n[:, 2] = inv
        return z, n

    return ground


def ramp(foot: float, deg: float, base: float = 0.0, length: float = 6.0) -> tuple:
    t = math.tan(math.radians(deg))
    return ((-20.0, base), (foot, base), (foot + length, base + t * length), (foot + length + 20.0, base + t * length))


# ---------------------------------------------------------------------------- the registry
@dataclass(frozen=True)
class Build:
    """What a layout builder is given: the instance and method ids, the robot, the approach run
    before a slope (m) and the wheels a T12/T13 trial lifts ("" = the instance's own)."""

    instance: str
    method: str
    robot: RobotConfig
    approach: float
    lift: str


@dataclass(frozen=True)
class Entry:
    """One registration: ``instance`` in ``group`` run with one of ``methods`` is built by
    ``build``, within ``timeout`` s of simulated time; ``uses_lift``: the builder reads
    ``scene.lift`` (T12, T13); ``burial``: the wheels' start sinkage below the undisturbed soil
    surface (m) when ``scene.burial`` is null (0: on the surface; T4: sunk in their ruts)."""

    instance: str
    group: str
    methods: tuple[str, ...]
    timeout: float
    build: Callable[[Build], Layout]
    uses_lift: bool = False
    burial: float = 0.0


#: instance id -> its registrations (one per set of methods), in registration order
REGISTRY: dict[str, list[Entry]] = {}


def instance(*ids: str, group: str, methods: tuple[str, ...], timeout: float, uses_lift: bool = False,
             burial: float = 0.0):
    """Register the decorated builder for ``ids`` run with ``methods`` (tagged by ``group``)."""

    def add(fn: Callable[[Build], Layout]) -> Callable[[Build], Layout]:
        for i in ids:
            entries = REGISTRY.setdefault(i, [])
            taken = {m for e in entries for m in e.methods} & set(methods)
            if taken:
                raise ValueError(f"srwmr instance {i!r} already has a layout for {', '.join(sorted(taken))}")
            if entries and entries[0].group != group:
                raise ValueError(f"srwmr instance {i!r} is in group {entries[0].group!r}, not {group!r}")
            entries.append(Entry(i, group, tuple(methods), float(timeout), fn, uses_lift, float(burial)))
        return fn

    return add


def instance_ids(group: str | None = None) -> list[str]:
    """The registered instances of ``group`` (None: all), in registration order."""
    return [i for i, es in REGISTRY.items() if group is None or es[0].group == group]


def entry(instance: str, method: str) -> Entry | None:
    """The registration that runs ``method`` on ``instance``, or None (it does not apply)."""
    for e in REGISTRY.get(instance, ()):
        if method in e.methods:
            return e
    return None


def methods_of(instance: str) -> tuple[str, ...]:
    """Every method that applies to ``instance``."""
    return tuple(m for e in REGISTRY.get(instance, ()) for m in e.methods)


def registered(instance: str, method: str) -> Entry:
    """The registration that runs ``method`` on ``instance``, or one ValueError naming the valid ids."""
    e = entry(instance, method)
    if e is None:
        if instance not in REGISTRY:
            raise ValueError(f"unknown srwmr instance {instance!r}; valid: {', '.join(REGISTRY)}")
        raise ValueError(f"method {method!r} does not apply to instance {instance!r}; valid: "
                         f"{', '.join(methods_of(instance))}")
    return e


def time_limit(cfg, instance: str, method: str) -> float:
    """The simulated time limit (s) of ``instance`` run with ``method`` under ``cfg``: its
    ``protocol.timeout`` if set, else the registration's (the planner writes it into every stored
    config, so a stored trial always carries its number)."""
    t = cfg.protocol.timeout
    return float(t) if t is not None else registered(instance, method).timeout


def start_burial(cfg, instance: str, method: str) -> float:
    """The wheels' start sinkage below the undisturbed soil surface (m) of ``instance`` run with
    ``method`` under ``cfg``: its ``scene.burial`` if set, else the registration's (written into
    every stored config at planning, as the time limit)."""
    b = cfg.scene.burial
    return float(b) if b is not None else registered(instance, method).burial


def layout(instance: str, method: str, robot: RobotConfig, approach: float = 0.6, lift: str = "") -> Layout:
    """The terrain, soil, plan and goal of ``instance`` run with ``method`` (``lift``: the wheels a
    T12/T13 SWLM/DWLM trial lifts, e.g. "c1" or "c1+c2"; empty: the instance's own)."""
    return registered(instance, method).build(Build(instance, method, robot, approach, lift))


FLAT = ((-50.0, 0.0), (50.0, 0.0))


def _slope(b: Build, deg: float, soil: str) -> Layout:
    """A flat approach then a ``deg`` slope of ``soil``, done when every wheel is on the slope: the
    chassis x with the rear wheels' trailing edge 0.1 m past the foot [S Task 11 "all wheels reached
    the slope", Task 5 "Once the rear wheels were positioned on the slope"]."""
    foot = b.robot.nose + b.approach
    goal = foot + b.robot.tail + 0.1
    v = 0.025
    plan = (
        (Step("WRM", v=v, dist=10.0, until_x=goal, auto_rcm=True),)
        if b.method == "rcm"
        else (Step("WRM", v=v, dist=10.0, until_x=goal),)
    )
    return Layout(ramp(foot, deg), (), soil, plan, goal, slope_deg=deg,
                  note=f"flat approach then a {deg:g} deg slope of {soil} soil")


# ---------------------------------------------------------------------------- group "tasks"
@instance("t1-very-loose", "t1-loose", group="tasks", methods=("wrm",), timeout=150.0)
def _t1(b: Build) -> Layout:
    """T1: WRM straight on very loose / loose soil."""
    soil = "very_loose" if "very" in b.instance else "loose"
    return Layout(FLAT, (), soil, (Step("WRM", v=0.025, dist=1.5),), None,
                  note="WRM 25 mm/s straight [S Task 1]; the paper ran 153.82 s commanded")


@instance("t2-wall", group="tasks", methods=("wcm",), timeout=900.0)
def _t2(b: Build) -> Layout:
    """T2: WRM to a brick wall, WCM past it, WRM to a rock pile, WCM past it, WRM on."""
    robot = b.robot
    nose, tail = robot.nose, robot.tail
    v = 0.025
    lead = 0.3  # period A: WRM towards the wall
    face = nose + lead + MARGIN
    wx, wy, wz_ = T2_WALL
    rx, ry, rz = T2_ROCKS
    side = wy + MARGIN + robot.track / 2 + robot.wheel_width / 2
    past_wall = face + 2 * wx + MARGIN + tail  # chassis x with the rear wheels 300 mm past the wall
    rock_face = past_wall + nose + MARGIN
    end = rock_face + 2 * rx + MARGIN + tail
    boxes = ((face + wx, 0.0, wx, wy, wz_), (rock_face + rx, -side, rx, ry, rz))
    plan = (
        Step("WRM", v=v, dist=lead),  # A
        Step("WCM", v=v, dy=-side),  # B: clockwise 90 deg, crab right past the wall, back
        Step("WRM", v=v, dist=10.0, until_x=past_wall),  # C
        Step("WCM", v=v, dy=side),  # D: counterclockwise 90 deg, crab left past the rocks, back
        Step("WRM", v=v, dist=10.0, until_x=end),  # E
    )
    return Layout(FLAT, boxes, "loose", plan, end,
                  note="WRM to a brick wall, WCM right past it, WRM to the rocks, WCM left past them, WRM on "
                       "[S Task 2]; 25 mm/s (Task 1's speed) and the obstacle sizes [R]")


@instance("t3-rclm", group="tasks", methods=("rclm",), timeout=600.0)
def _t3(b: Build) -> Layout:
    """T3: RCLM through three clearances with WRM between them."""
    plan = (
        Step("RCLM", v=0.0, clearance=0.33),
        Step("WRM", v=0.025, dist=0.4),
        Step("RCLM", v=0.0, clearance=0.48),
        Step("WRM", v=0.025, dist=0.4),
        Step("RCLM", v=0.0, clearance=0.25),
    )
    return Layout(FLAT, (), "loose", plan, None, note="RCLM 250 -> 330 -> 480 -> 250 mm [S Task 3]")


@instance("t4-sinkage", group="tasks", methods=("rcm", "wrm"), timeout=600.0, burial=0.15)
def _t4(b: Build) -> Layout:
    """T4: out of a pit of very loose soil with every wheel sunk in its own rut, 150 mm (the wheel
    radius) below the pit floor's surface (the paper's 'all wheels are totally sunk';
    ``scene.burial``, docs/assumptions-srwmr.md)."""
    depth = 0.12
    wall = 1.0 + depth / math.tan(math.radians(20))
    prof = ((-20.0, -depth), (1.05, -depth), (wall, 0.0), (30.0, 0.0))
    goal = wall + 0.2
    plan = (
        (Step("RCM", v=0.025, cycles=999, amp=0.45, until_x=goal),)
        if b.method == "rcm"
        else (Step("WRM", v=0.025, dist=5.0, until_x=goal),)
    )
    return Layout(prof, (), "very_loose", plan, goal, z0=-depth,
                  note="start in a 120 mm pit with 20 deg walls of very loose soil, the wheels sunk in their ruts "
                       "(scene.burial) [R for 'all wheels are totally sunk']")


@instance("t5-slope10", group="tasks", methods=("rcm", "wrm"), timeout=600.0)
def _t5(b: Build) -> Layout:
    """T5: a 10 deg loose slope, WRM alone or with the supervisor's switch to RCM."""
    return _slope(b, 10.0, "loose")


@instance("t8-speeds", group="tasks", methods=("wrm",), timeout=700.0)
def _t8(b: Build) -> Layout:
    """T8: WRM at five speeds in turn."""
    plan = tuple(Step("WRM", v=v, dist=v * 60.0) for v in (0.005, 0.015, 0.025, 0.015, 0.005))
    return Layout(FLAT, (), "loose", plan, None, note="WRM 5/15/25/15/5 mm/s, 60 s each [S Task 8]")


@instance("t9-avoid", group="tasks", methods=("wrm", "wcm"), timeout=900.0)
def _t9(b: Build) -> Layout:
    """T9: from A to B past an obstacle, WRM on an arc or WCM on the straight line."""
    v = 0.015
    bx, by = T9_B
    L, W, H = OBSTACLE
    box = ((T9_OBSTACLE_X, 0.0, L / 2, W / 2, H / 2),)
    if b.method == "wcm":
        plan = (Step("WCM", v=v, dx=bx, dy=by),)
    else:
        R = T9_RADIUS
        s45 = math.sin(math.pi / 4)
        # straight start s1 so that the 45 deg line from the arc's end passes through B
        s1 = bx - by - R * s45 + R * (1 - s45)
        pts = [(s1 * k / 2, 0.0) for k in (1, 2)]
        pts += [(s1 + R * math.sin(p), R * (1 - math.cos(p))) for p in np.linspace(0, math.pi / 4, 6)[1:]]
        ex, ey = pts[-1]
        n = max(2, int(math.hypot(bx - ex, by - ey) / 0.3))
        pts += [(ex + (bx - ex) * k / n, ey + (by - ey) * k / n) for k in range(1, n + 1)]
        plan = (Step("WRM", v=v, waypoints=tuple(pts)),)
    return Layout(FLAT, box, "loose", plan, bx,
                  note=f"from A to B = ({bx:g}, {by:g}) m past an obstacle on the start heading: WRM (Ackermann) "
                       f"on a 45 deg arc of radius {T9_RADIUS:g} m, WCM on the straight line at "
                       f"{math.degrees(math.atan2(by, bx)):.1f} deg [S Task 9; geometry R]; 15 mm/s")


@instance("t10-heights", group="tasks", methods=("rclm",), timeout=900.0)
def _t10(b: Build) -> Layout:
    """T10: RCLM while driving, through the paper's five heights."""
    v = 0.015
    hs = T10_HEIGHTS
    plan = [Step("WRM", v=v, dist=T10_HOLD)]
    for h in hs[1:-1]:
        plan += [Step("RCLM", v=v, clearance=h), Step("WRM", v=v, dist=T10_HOLD)]
    plan.append(Step("RCLM", v=v, clearance=hs[-1]))
    return Layout(FLAT, (), "loose", tuple(plan), None,
                  note="RCLM while driving at 15 mm/s: 250 -> 450 -> 150 -> 550 -> 250 mm, "
                       f"{T10_HOLD:g} m at each held height [S Task 10]")


@instance("t11-slope15", group="tasks", methods=("wrm", "rcm"), timeout=3100.0)
def _t11(b: Build) -> Layout:
    """T11: a 15 deg loose slope until every wheel is on it; the limit leaves room for the paper's
    time [S Task 11 "By 3030 s, all wheels had successfully reached the slope"]."""
    return _slope(b, 15.0, "loose")


@instance("t14-obstacle", group="tasks", methods=("wrm", "wcm", "rclm"), timeout=900.0)
def _t14(b: Build) -> Layout:
    """T14: past a 150 x 550 x 190 mm obstacle by WRM around it, WCM beside it or RCLM over it."""
    robot = b.robot
    L, W, H = OBSTACLE
    near = robot.nose + MARGIN
    far = near + L
    end = far + MARGIN + robot.tail
    box = ((near + L / 2, 0.0, L / 2, W / 2, H / 2),)
    v = 0.015
    if b.method == "rclm":
        plan = (
            Step("RCLM", v=0.0, clearance=0.33),
            Step("WRM", v=v, dist=10.0, until_x=end),
            Step("RCLM", v=0.0, clearance=0.25),
        )
    elif b.method == "wcm":
        dy = W / 2 + MARGIN + robot.track / 2 + robot.wheel_width / 2
        plan = (Step("WCM", v=v, dy=dy), Step("WRM", v=v, dist=10.0, until_x=end), Step("WCM", v=v, dy=-dy))
    else:
        side = W / 2 + MARGIN + robot.track / 2 + robot.wheel_width / 2
        wps = (
            (near - 1.0, 0.0),
            (near - 0.2, side * 0.8),
            (near + L / 2, side),
            (far + 0.2, side * 0.8),
            (end, 0.0),
        )
        plan = (Step("WRM", v=v, waypoints=wps),)
    return Layout(FLAT, box, "loose", plan, end,
                  note="obstacle 150 x 550 x 190 mm at 15 mm/s, start/end 300 mm from it [S Task 14]")


@instance("t15-w002", "t15-w003", group="tasks", methods=("rclm",), timeout=400.0)
def _t15(b: Build) -> Layout:
    """T15: differential steering in place while the chassis is lowered."""
    w = T15_RATES[b.instance]
    hi, lo = T15_CLEARANCE
    plan = (
        Step("RCLM", v=0.0, clearance=hi),
        Step("RCLM", v=0.0, wz=w, diff=True, clearance=lo),
    )
    return Layout(FLAT, (), "loose", plan, None,
                  note=f"differential steering in place at {w:g} rad/s while the chassis is lowered "
                       f"{hi * 1000:.0f} -> {lo * 1000:.0f} mm (the wheelbase lengthens) [S Task 15; heights R]")


@instance(*STEER_RATES, group="steer", methods=("rclm",), timeout=STEER_S + 60.0)
def _steer(b: Build) -> Layout:
    """In-place steering at a held clearance (the paper's sec. 8.6 experiment beside Task 15)."""
    w = STEER_RATES[b.instance]
    plan = (Step("RCLM", v=0.0, wz=w, diff=True, clearance=0.25, steer_s=STEER_S),)
    return Layout(FLAT, (), "loose", plan, None,
                  note=f"differential steering in place at {w:g} rad/s for {STEER_S:g} s at the 250 mm "
                       f"clearance [S sec. 8.6: yaw about one-fifth of the command; duration R]")


# ---------------------------------------------------------------------------- wheel-legged tasks
#: T6 brick pile (m): length along x, width, height [S height 150 mm; R: bricks laid crosswise, one
#: brick width (115 mm) along x, 300 mm wide under the right wheels' track: with a brick length (240
#: mm) along x the fitted linkage's middle wheel, once the front one is down past the pile and the
#: chassis back at 250 mm, would already stand on the pile]; T7 stair step height (m) [R: the T6 pile
#: height]
T6_PILE = (0.115, 0.30, 0.15)
T7_STEP = 0.15
#: wheel lift heights (m): T6 and T7 180 mm [S Task 6 "lift the front wheel 180 mm"]; T14 the
#: obstacle height plus the 30 mm T6 keeps over its pile [R]
LEGGED_HEIGHT = 0.18
#: gap (m) from the front wheel's outer edge to the obstacle at the start [S T14: 300 mm]; clearance
#: (m) a lowered wheel keeps past an obstacle edge [R]
LEGGED_GAP, LEGGED_CLEAR = 0.3, 0.05
#: T12 / T13: lifted heights (m) and the roll (m) at 25 mm/s [S Tasks 12, 13]
T12_HEIGHTS = {"t12-lift100": 0.10, "t12-lift150": 0.15, "t12-lift200": 0.20}
T13_POS = {"t13-front": "front", "t13-middle": "middle", "t13-rear": "rear"}
T12_ROLL = 0.9


def _right(pos: str) -> str:
    return {"front": "c2", "middle": "c4", "rear": "c6"}[pos]


def _pair(pos: str) -> tuple[str, str]:
    return {"front": ("c1", "c2"), "middle": ("c3", "c4"), "rear": ("c5", "c6")}[pos]


def _crossing_plan(robot: RobotConfig, mode: str, x_near: float, land: float, height: float, v: float):
    """Three legged steps (front, middle, rear) that carry each lifted wheel from before ``x_near``
    to ``land`` (its centre's x, m) and the chassis x where the plan ends. Each roll follows from
    the axle's x at the step's clearance (kinematics at the CoM-shift clearance)."""
    from terrabench.systems.srwmr.kinematics import axle_positions, delta_for_clearance, level_zeta
    from terrabench.systems.srwmr.legged import SHIFT

    plan, xc = [], 0.0
    for pos, wi in (("front", 0), ("middle", 2), ("rear", 4)):
        cl = SHIFT[pos] if SHIFT[pos] is not None else robot.clearance
        d = delta_for_clearance(robot, cl)
        xw = float(axle_positions(robot, [d, d], level_zeta(robot, [d, d]))[wi, 0])
        if xc + xw + robot.wheel_radius > x_near - 0.01:
            raise ValueError(f"the {pos} wheel starts against the obstacle (x {xc + xw:.2f} m); layout too short")
        dist = land - (xc + xw)
        lift = (_right(pos),) if mode == "SWLM" else _pair(pos)
        plan.append(Step(mode, v=v, lift=lift, height=height, dist=dist))
        xc += dist
    return plan, xc


@instance("t6-bricks", group="tasks", methods=("swlm",), timeout=900.0)
def _t6(b: Build) -> Layout:
    """T6: SWLM, the right wheels in turn over a brick pile."""
    robot, r = b.robot, b.robot.wheel_radius
    x_near = robot.nose + LEGGED_GAP
    L, W, H = T6_PILE
    plan, xc = _crossing_plan(robot, "SWLM", x_near, x_near + L + r + LEGGED_CLEAR, LEGGED_HEIGHT, 0.025)
    box = ((x_near + L / 2, -robot.track / 2, L / 2, W / 2, H / 2),)
    return Layout(FLAT, box, "loose", tuple(plan), xc - 0.05,
                  note="SWLM right wheels in sequence over a 150 mm brick pile [S Task 6]; pile 240 x 300 mm [R]")


@instance("t7-stairs", group="tasks", methods=("dwlm",), timeout=900.0)
def _t7(b: Build) -> Layout:
    """T7: DWLM, the wheel pairs in turn up a stair step."""
    robot, r = b.robot, b.robot.wheel_radius
    x_near = robot.nose + LEGGED_GAP
    floor, top = 0.01, 0.01 + T7_STEP
    plan, xc = _crossing_plan(robot, "DWLM", x_near, x_near + r + LEGGED_CLEAR, LEGGED_HEIGHT, 0.025)
    boxes = ((0.0, 0.0, 10.0, 2.0, floor / 2), (x_near + 2.0, 0.0, 2.0, 2.0, top / 2))
    return Layout(FLAT, boxes, "loose", tuple(plan), xc - 0.05, z0=0.05,
                  note="DWLM pairs in sequence up a 150 mm stair step, rigid floor and step [S Task 7 'hard, "
                       "stair, and wood terrains'; step height R]")


@instance(*T12_HEIGHTS, *T13_POS, group="tasks", methods=("swlm", "dwlm"), timeout=400.0, uses_lift=True)
def _t12_t13(b: Build) -> Layout:
    """T12 (lift heights) and T13 (lift positions): lift, roll 900 mm, lower."""
    mode = b.method.upper()
    h = T12_HEIGHTS.get(b.instance, 0.20)
    pos = T13_POS.get(b.instance, "front")
    wheels = tuple(b.lift.split("+")) if b.lift else ((_right(pos),) if mode == "SWLM" else _pair(pos))
    plan = (Step(mode, v=0.025, lift=wheels, height=h, dist=T12_ROLL),)
    what = "Task 12: the front-right wheel / both front wheels" if b.instance in T12_HEIGHTS else \
        f"Task 13: the {pos} wheel(s)"
    # success: the plan ended with the chassis at least 0.8 m on (the 900 mm roll was run)
    return Layout(FLAT, (), "loose", plan, T12_ROLL - 0.05,
                  note=f"{mode} lift {'+'.join(wheels)} {1000 * h:.0f} mm, roll 900 mm at 25 mm/s, lower "
                       f"[S {what}]")


@instance("t14-obstacle", group="tasks", methods=("swlm",), timeout=1500.0)
def _t14_swlm(b: Build) -> Layout:
    """T14's SWLM row: the right wheels in turn over the obstacle, then WRM to the end."""
    robot = b.robot
    r = robot.wheel_radius
    x_near = robot.nose + LEGGED_GAP
    L, W, H = OBSTACLE
    far = x_near + L
    end = far + MARGIN + robot.tail
    plan, xc = _crossing_plan(robot, "SWLM", x_near, far + r + LEGGED_CLEAR, H + 0.03, 0.015)
    plan.append(Step("WRM", v=0.015, dist=10.0, until_x=end))
    box = ((x_near + L / 2, -robot.track / 2, L / 2, W / 2, H / 2),)
    return Layout(FLAT, box, "loose", tuple(plan), end,
                  note="SWLM right wheels in sequence over the 150 x 550 x 190 mm obstacle at 15 mm/s [S Task "
                       "14]; the obstacle lies under the right wheels' track [R: centred it passes between them]")


# ---------------------------------------------------------------------------- group "slopes"
@instance(*SLOPES, group="slopes", methods=("wrm", "rcm"), timeout=500.0)
def _slope_sweep(b: Build) -> Layout:
    """The slope sweep: ``slope-<deg>-<soil>``, success with every wheel on the slope."""
    _, deg_s, soil = b.instance.split("-", 2)
    return _slope(b, float(deg_s), soil)


#: the wheel-legged instances (SWLM / DWLM: T6, T7, T12, T13; T14's SWLM row is in t14-obstacle)
LEGGED_TASKS = tuple(i for i in instance_ids("tasks") if set(methods_of(i)) <= {"swlm", "dwlm"})
