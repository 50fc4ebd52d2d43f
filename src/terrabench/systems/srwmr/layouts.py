"""The paper's tasks a simulation can repeat, as terrain + the scripted operator's plan.

Every instance is ``(ground profile, obstacles, soil, plan per method, goal, time limit)``. The
ground is a piecewise-linear profile along x (flat, a ramp, a pit), used both by the soil forces
(:func:`profile_ground`) and, as tilted planks, for the rigid links. Plans are lists of
:class:`~terrabench.systems.srwmr.control.Step`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from terrabench.systems.srwmr.control import Step
from terrabench.systems.srwmr.robot import RobotConfig

TASKS = (
    "t1-very-loose",
    "t1-loose",
    "t2-wall",
    "t3-rclm",
    "t4-sinkage",
    "t5-slope10",
    "t8-speeds",
    "t9-avoid",
    "t10-heights",
    "t11-slope15",
    "t14-obstacle",
    "t15-w002",
    "t15-w003",
)
SLOPE_ANGLES = (0, 5, 10, 15, 20, 25)
SLOPE_SOILS = ("very_loose", "loose")
SLOPES = tuple(f"slope-{a}-{s}" for s in SLOPE_SOILS for a in SLOPE_ANGLES)
#: methods that apply to each instance (the paper ran one or two modes per task)
APPLIES = {
    "t1-very-loose": ("wrm",),
    "t1-loose": ("wrm",),
    "t2-wall": ("wcm",),
    "t3-rclm": ("rclm",),
    "t4-sinkage": ("rcm", "wrm"),
    "t5-slope10": ("rcm", "wrm"),
    "t8-speeds": ("wrm",),
    "t9-avoid": ("wrm", "wcm"),
    "t10-heights": ("rclm",),
    "t11-slope15": ("wrm", "rcm"),
    "t14-obstacle": ("wrm", "wcm", "rclm"),
    "t15-w002": ("rclm",),
    "t15-w003": ("rclm",),
    **{s: ("wrm", "rcm") for s in SLOPES},
    **{s: ("swlm", "dwlm") for s in ("t12-lift100", "t12-lift150", "t12-lift200", "t13-front", "t13-middle",
                                     "t13-rear")},
    "t6-bricks": ("swlm",),
    "t7-stairs": ("dwlm",),
}
APPLIES["t14-obstacle"] = APPLIES["t14-obstacle"] + ("swlm",)
#: the wheel-legged instances (SWLM / DWLM: T6, T7, T12, T13; T14's SWLM row is in t14-obstacle)
LEGGED_TASKS = ("t6-bricks", "t7-stairs", "t12-lift100", "t12-lift150", "t12-lift200", "t13-front", "t13-middle",
                "t13-rear")
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
#: T10 chassis heights (m), held and changed in this order [S Task 10: 250, 450, 150, 550, 250 mm]
T10_HEIGHTS = (0.25, 0.45, 0.15, 0.55, 0.25)
#: T10 distance driven at each held height (m) [R]
T10_HOLD = 0.45
#: T15 yaw rates (rad/s) [S 0.02, 0.03] and the clearances the chassis is lowered between (m) [R]
T15_RATES = {"t15-w002": 0.02, "t15-w003": 0.03}
T15_CLEARANCE = (0.45, 0.15)


@dataclass(frozen=True)
class Layout:
    """One instance: ``profile`` ((x, z), ...) of the ground, ``boxes`` ((cx, cy, hx, hy, hz), ...)
    obstacles on it, the soil name, the plan, the success line ``goal_x`` (chassis x, m; None:
    the plan's end), the time limit (s), the start height offset ``z0`` (m) of the ground."""

    profile: tuple
    boxes: tuple
    soil: str
    plan: tuple
    goal_x: float | None
    timeout: float
    z0: float = 0.0
    slope_deg: float = 0.0
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


def layout(instance: str, method: str, robot: RobotConfig, approach: float = 0.6, lift: str = "") -> Layout:
    """The terrain, soil, plan and goal of ``instance`` run with ``method`` (``lift``: the wheels a
    T12/T13 SWLM/DWLM trial lifts, e.g. "c1" or "c1+c2"; empty: the instance's own)."""
    if method not in APPLIES.get(instance, ()):
        valid = ", ".join(APPLIES.get(instance, ())) or "none"
        raise ValueError(f"method {method!r} does not apply to instance {instance!r}; valid: {valid}")
    a = robot.front_len
    r = robot.wheel_radius
    flat = ((-50.0, 0.0), (50.0, 0.0))
    if instance in ("t1-very-loose", "t1-loose"):
        soil = "very_loose" if "very" in instance else "loose"
        return Layout(
            flat,
            (),
            soil,
            (Step("WRM", v=0.025, dist=1.5),),
            None,
            150.0,
            note="WRM 25 mm/s straight [S Task 1]; the paper ran 153.82 s commanded",
        )
    if instance == "t3-rclm":
        plan = (
            Step("RCLM", v=0.0, clearance=0.33),
            Step("WRM", v=0.025, dist=0.4),
            Step("RCLM", v=0.0, clearance=0.48),
            Step("WRM", v=0.025, dist=0.4),
            Step("RCLM", v=0.0, clearance=0.25),
        )
        return Layout(flat, (), "loose", plan, None, 600.0, note="RCLM 250 -> 330 -> 480 -> 250 mm [S Task 3]")
    if instance == "t4-sinkage":
        depth = 0.12
        wall = 1.0 + depth / math.tan(math.radians(20))
        prof = ((-20.0, -depth), (1.05, -depth), (wall, 0.0), (30.0, 0.0))
        goal = wall + 0.2
        plan = (
            (Step("RCM", v=0.025, cycles=999, amp=0.45, until_x=goal),)
            if method == "rcm"
            else (Step("WRM", v=0.025, dist=5.0, until_x=goal),)
        )
        return Layout(
            prof,
            (),
            "very_loose",
            plan,
            goal,
            600.0,
            z0=-depth,
            note="start in a 120 mm pit with 20 deg walls of very loose soil [R for 'all wheels sunk']",
        )
    if instance in ("t5-slope10", "t11-slope15") or instance.startswith("slope-"):
        if instance.startswith("slope-"):
            _, deg_s, soil = instance.split("-", 2)
            deg, timeout = float(deg_s), 500.0
        else:
            deg, soil, timeout = (10.0, "loose", 600.0) if instance == "t5-slope10" else (15.0, "loose", 600.0)
        foot = a + r + approach
        goal = foot + 0.6 - a  # the front wheels 0.6 m up the slope
        if instance == "t11-slope15":
            goal = foot + a + r + 0.1  # every wheel on the slope [S 'all wheels reached the slope']
        v = 0.025
        plan = (
            (Step("WRM", v=v, dist=10.0, until_x=goal, auto_rcm=True),)
            if method == "rcm"
            else (Step("WRM", v=v, dist=10.0, until_x=goal),)
        )
        return Layout(
            ramp(foot, deg),
            (),
            soil,
            plan,
            goal,
            timeout,
            slope_deg=deg,
            note=f"flat approach then a {deg:g} deg slope of {soil} soil",
        )
    if instance == "t2-wall":
        v = 0.025
        lead = 0.3  # period A: WRM towards the wall
        face = a + r + lead + MARGIN
        wx, wy, wz_ = T2_WALL
        rx, ry, rz = T2_ROCKS
        side = wy + MARGIN + robot.track / 2 + robot.wheel_width / 2
        past_wall = face + 2 * wx + MARGIN + a + r  # chassis x with the rear wheels 300 mm past the wall
        rock_face = past_wall + a + r + MARGIN
        end = rock_face + 2 * rx + MARGIN + a + r
        boxes = ((face + wx, 0.0, wx, wy, wz_), (rock_face + rx, -side, rx, ry, rz))
        plan = (
            Step("WRM", v=v, dist=lead),  # A
            Step("WCM", v=v, dy=-side),  # B: clockwise 90 deg, crab right past the wall, back
            Step("WRM", v=v, dist=10.0, until_x=past_wall),  # C
            Step("WCM", v=v, dy=side),  # D: counterclockwise 90 deg, crab left past the rocks, back
            Step("WRM", v=v, dist=10.0, until_x=end),  # E
        )
        return Layout(
            flat,
            boxes,
            "loose",
            plan,
            end,
            900.0,
            note="WRM to a brick wall, WCM right past it, WRM to the rocks, WCM left past them, WRM on [S Task 2]; "
            "25 mm/s (Task 1's speed) and the obstacle sizes [R]",
        )
    if instance == "t9-avoid":
        v = 0.015
        bx, by = T9_B
        L, W, H = OBSTACLE
        box = ((T9_OBSTACLE_X, 0.0, L / 2, W / 2, H / 2),)
        if method == "wcm":
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
        return Layout(
            flat,
            box,
            "loose",
            plan,
            bx,
            900.0,
            note=f"from A to B = ({bx:g}, {by:g}) m past an obstacle on the start heading: WRM (Ackermann) "
            f"on a 45 deg arc of radius {T9_RADIUS:g} m, WCM on the straight line at "
            f"{math.degrees(math.atan2(by, bx)):.1f} deg [S Task 9; geometry R]; 15 mm/s",
        )
    if instance == "t10-heights":
        v = 0.015
        hs = T10_HEIGHTS
        plan = [Step("WRM", v=v, dist=T10_HOLD)]
        for h in hs[1:-1]:
            plan += [Step("RCLM", v=v, clearance=h), Step("WRM", v=v, dist=T10_HOLD)]
        plan.append(Step("RCLM", v=v, clearance=hs[-1]))
        return Layout(
            flat,
            (),
            "loose",
            tuple(plan),
            None,
            900.0,
            note="RCLM while driving at 15 mm/s: 250 -> 450 -> 150 -> 550 -> 250 mm, "
            f"{T10_HOLD:g} m at each held height [S Task 10]",
        )
    if instance in T15_RATES:
        w = T15_RATES[instance]
        hi, lo = T15_CLEARANCE
        plan = (
            Step("RCLM", v=0.0, clearance=hi),
            Step("RCLM", v=0.0, wz=w, diff=True, clearance=lo),
        )
        return Layout(
            flat,
            (),
            "loose",
            plan,
            None,
            400.0,
            note=f"differential steering in place at {w:g} rad/s while the chassis is lowered "
            f"{hi * 1000:.0f} -> {lo * 1000:.0f} mm (the wheelbase lengthens) [S Task 15; heights R]",
        )
    if instance == "t8-speeds":
        plan = tuple(Step("WRM", v=v, dist=v * 60.0) for v in (0.005, 0.015, 0.025, 0.015, 0.005))
        return Layout(flat, (), "loose", plan, None, 700.0, note="WRM 5/15/25/15/5 mm/s, 60 s each [S Task 8]")
    if instance == "t14-obstacle" and method == "swlm":
        return legged_layout(instance, method, robot, lift)
    if instance == "t14-obstacle":
        L, W, H = OBSTACLE
        near = a + r + MARGIN
        far = near + L
        end = far + MARGIN + a + r
        box = ((near + L / 2, 0.0, L / 2, W / 2, H / 2),)
        v = 0.015
        if method == "rclm":
            plan = (
                Step("RCLM", v=0.0, clearance=0.33),
                Step("WRM", v=v, dist=10.0, until_x=end),
                Step("RCLM", v=0.0, clearance=0.25),
            )
        elif method == "wcm":
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
        return Layout(
            flat,
            box,
            "loose",
            plan,
            end,
            900.0,
            note="obstacle 150 x 550 x 190 mm at 15 mm/s, start/end 300 mm from it [S Task 14]",
        )
    if instance in LEGGED_TASKS:
        return legged_layout(instance, method, robot, lift)
    raise ValueError(f"unknown srwmr instance {instance!r}; valid: {', '.join(TASKS + LEGGED_TASKS + SLOPES)}")


# ---------------------------------------------------------------------------- wheel-legged tasks
#: T6 brick pile (m): length along x, width, height [S height 150 mm; R: one brick length 240 mm,
#: 300 mm wide under the right wheels' track]; T7 stair step height (m) [R: the T6 pile height]
T6_PILE = (0.24, 0.30, 0.15)
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


def legged_layout(instance: str, method: str, robot: RobotConfig, lift: str = "") -> Layout:
    """T6 (SWLM over a brick pile), T7 (DWLM up a stair), T12/T13 (SWLM/DWLM lifts on loose soil)
    and T14's SWLM row: the scripted operator's legged plans (legged.py)."""
    a, r = robot.front_len, robot.wheel_radius
    mode = method.upper()
    flat = ((-50.0, 0.0), (50.0, 0.0))
    x_near = a + r + LEGGED_GAP
    if instance == "t6-bricks":
        L, W, H = T6_PILE
        plan, xc = _crossing_plan(robot, "SWLM", x_near, x_near + L + r + LEGGED_CLEAR, LEGGED_HEIGHT, 0.025)
        box = ((x_near + L / 2, -robot.track / 2, L / 2, W / 2, H / 2),)
        return Layout(flat, box, "loose", tuple(plan), xc - 0.05, 900.0,
                      note="SWLM right wheels in sequence over a 150 mm brick pile [S Task 6]; pile 240 x 300 mm [R]")
    if instance == "t7-stairs":
        floor, top = 0.01, 0.01 + T7_STEP
        plan, xc = _crossing_plan(robot, "DWLM", x_near, x_near + r + LEGGED_CLEAR, LEGGED_HEIGHT, 0.025)
        boxes = ((0.0, 0.0, 10.0, 2.0, floor / 2), (x_near + 2.0, 0.0, 2.0, 2.0, top / 2))
        return Layout(flat, boxes, "loose", tuple(plan), xc - 0.05, 900.0, z0=0.05,
                      note="DWLM pairs in sequence up a 150 mm stair step, rigid floor and step [S Task 7 'hard, "
                           "stair, and wood terrains'; step height R]")
    if instance == "t14-obstacle":
        L, W, H = OBSTACLE
        far = x_near + L
        end = far + MARGIN + a + r
        plan, xc = _crossing_plan(robot, "SWLM", x_near, far + r + LEGGED_CLEAR, H + 0.03, 0.015)
        plan.append(Step("WRM", v=0.015, dist=10.0, until_x=end))
        box = ((x_near + L / 2, -robot.track / 2, L / 2, W / 2, H / 2),)
        return Layout(flat, box, "loose", tuple(plan), end, 1500.0,
                      note="SWLM right wheels in sequence over the 150 x 550 x 190 mm obstacle at 15 mm/s [S Task "
                           "14]; the obstacle lies under the right wheels' track [R: centred it passes between them]")
    if instance in T12_HEIGHTS or instance in T13_POS:
        h = T12_HEIGHTS.get(instance, 0.20)
        pos = T13_POS.get(instance, "front")
        wheels = tuple(lift.split("+")) if lift else ((_right(pos),) if mode == "SWLM" else _pair(pos))
        plan = (Step(mode, v=0.025, lift=wheels, height=h, dist=T12_ROLL),)
        what = "Task 12: the front-right wheel / both front wheels" if instance in T12_HEIGHTS else \
            f"Task 13: the {pos} wheel(s)"
        # success: the plan ended with the chassis at least 0.8 m on (the 900 mm roll was run)
        return Layout(flat, (), "loose", plan, T12_ROLL - 0.05, 400.0,
                      note=f"{mode} lift {'+'.join(wheels)} {1000 * h:.0f} mm, roll 900 mm at 25 mm/s, lower "
                           f"[S {what}]")
    raise ValueError(f"instance {instance!r} has no legged layout; valid: {', '.join(LEGGED_TASKS)}, t14-obstacle")
