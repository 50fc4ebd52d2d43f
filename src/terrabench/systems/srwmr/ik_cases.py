"""Group ``ik``: trials in which the constraint-saturated IK is at work (issue 27, piece 5).

Each instance commands the rover, in the paper's chassis-lifting mode RCLM (the mode whose
threshold vector enforces every QP row, MC#3-#9), past one motion constraint's boundary, so the
projection (seed 001 eq. 41) changes the nominal command for a large share of the periods:

* ``ik-mc3-lift``: a lift while driving at 15 mm/s [S Task 10] to 520 mm [S Task 10 commands
  550 mm]: MC#3 (front-middle wheelbase reduction, RCLM kappa 0.61) stops it near 490 mm;
* ``ik-mc5-asym``: the right side alone lifted 250 -> 400 mm at 10 mm/s while driving (a one-side
  obstacle under the right wheels): first MC#9 (left-right vertical speed difference, 6 mm/s),
  then MC#5 (left-right wheelbase asymmetry, 50 mm) saturate;
* ``ik-mc4-low``: both sides lowered to 150 mm, then the right side alone raised to 250 mm: at the
  low clearance the hinge rises faster per closing angle than the wheelbase changes, so MC#4
  (left-right hinge-height asymmetry, 50 mm) is the row that binds;
* ``ik-mc4-cross``: a 10 deg cross slope [R: Task 5's angle, across], the left side uphill; both
  sides lowered to 150 mm, then the chassis levelled while driving: the right (downhill) side
  commanded up by the track x tan(10 deg) (~230 mm): MC#4 (50 mm) holds the asymmetry, so the
  chassis keeps most of the slope's roll (the paper's MC#4 with the slope, not an asymmetric lift,
  as its cause);
* ``ik-mc6-fastlift``: standing, a lift at 10 mm/s (2.8x Task 3's 3.6 mm/s) to 400 mm: MC#6 (the
  rocker-induced front-wheel speed against the side's speed, floor 8 mm/s, kappa 0.9) limits the
  closing rate;
* ``ik-mc78-step``: from standstill a step to 25 mm/s with a 0.03 rad/s differential yaw rate
  [S Task 15's rate] while lowering, then the yaw rate reversed: MC#7 / MC#8 (the per-period
  change of the forward speed and of the yaw rate) ramp the command.

Every instance has a ``-noqp`` twin with the same plan whose command bypasses the projection
(``Step.qp`` False; the supervisor still halts on MC#4/#5/#10/#11): the effect of the QP is the
difference. The posture cases (:data:`TARGET_CASES`) also run as ``-target``: the QP's rows
linearised about the rockers' servo targets instead of the measured closing angles (with the
measured ones the servo's lag carries the state past the boundary the QP stopped the target at,
and the one-period rows then admit no command: IK infeasible, a halt). All variants' supervisor
halts only above kappa (1 + :data:`HALT_TOL`). Every step
keeps the per-period QP trace (``Step.trace``, :mod:`~terrabench.systems.srwmr.qp_trace`). Flat
loose soil, the default configuration.
"""

from __future__ import annotations

import math

from terrabench.systems.srwmr.layouts import FLAT, Build, Layout, instance
from terrabench.systems.srwmr.modes import Step

#: the instances of group ``ik`` (each also as ``<id>-noqp``): the constraint each saturates
CASES = {
    "ik-mc3-lift": "MC3",
    "ik-mc5-asym": "MC5",
    "ik-mc4-low": "MC4",
    "ik-mc4-cross": "MC4",
    "ik-mc6-fastlift": "MC6",
    "ik-mc78-step": "MC7",
}
#: the cases whose saturated constraint is a posture (state) ratio: each also as ``<id>-target``,
#: the QP's rows linearised about the rockers' servo targets (``Step.qp_about_target``)
TARGET_CASES = ("ik-mc3-lift", "ik-mc5-asym", "ik-mc4-low", "ik-mc4-cross")
#: ik-mc4-cross: the cross slope (deg, left side up) [R: Task 5's 10 deg slope, turned across]
CROSS_DEG = 10.0
IK_INSTANCES = tuple(i for c in CASES for i in (c, f"{c}-noqp") + ((f"{c}-target",) if c in TARGET_CASES else ()))
#: the group's supervisor halts on a monitored ratio (MC#4, #5, #10, #11) above kappa (1 + HALT_TOL),
#: not at kappa: the QP holds a saturated posture ratio at kappa, the measured one follows it to the
#: servos' tracking (within 0.25 % of kappa in these runs), which the default supervisor (halting at
#: >= kappa) already counts as a halt, with or without the QP
HALT_TOL = 0.005


def case_of(instance: str) -> str:
    """``ik-mc3-lift-noqp`` / ``ik-mc3-lift-target`` -> ``ik-mc3-lift``."""
    for tail in ("-noqp", "-target"):
        if instance.endswith(tail):
            return instance[: -len(tail)]
    return instance


def variant_of(instance: str) -> str:
    """``qp`` (the IK as every trial runs it), ``noqp`` (bypassed) or ``target`` (rows about the targets)."""
    return instance.rsplit("-", 1)[1] if instance.endswith(("-noqp", "-target")) else "qp"


def _plan(b: Build) -> tuple[tuple, str]:
    case = case_of(b.instance)
    var = variant_of(b.instance)
    kw = {"trace": True, "qp": var != "noqp", "qp_about_target": var == "target", "halt_tol": HALT_TOL}
    if case == "ik-mc3-lift":
        return (Step("RCLM", v=0.015, clearance=0.52, hold_s=90.0, **kw),), \
            "RCLM while driving at 15 mm/s to 520 mm [S Task 10: 550 mm]: MC#3 holds the wheelbase"
    if case == "ik-mc5-asym":
        return (Step("RCLM", v=0.015, vz=0.01, clearance=0.25, clearance_r=0.40, hold_s=30.0, **kw),), \
            "right side alone 250 -> 400 mm at 10 mm/s while driving at 15 mm/s: MC#9, then MC#5"
    if case == "ik-mc4-low":
        return (Step("RCLM", v=0.015, vz=0.01, clearance=0.15, **kw),
                Step("RCLM", v=0.015, clearance=0.15, clearance_r=0.25, hold_s=30.0, **kw)), \
            "both sides to 150 mm, then the right side alone back to 250 mm: MC#4"
    if case == "ik-mc4-cross":
        level = 0.15 + b.robot.track * math.tan(math.radians(CROSS_DEG))
        return (Step("RCLM", v=0.015, vz=0.01, clearance=0.15, **kw),
                Step("RCLM", v=0.015, clearance=0.15, clearance_r=level, hold_s=30.0, **kw)), \
            (f"a {CROSS_DEG:g} deg cross slope, left up: both sides to 150 mm, then the right side toward "
             f"{level * 1000:.0f} mm to level the chassis: MC#4")
    if case == "ik-mc6-fastlift":
        return (Step("RCLM", v=0.0, vz=0.01, clearance=0.40, hold_s=60.0, **kw),), \
            "standing, lift at 10 mm/s to 400 mm: MC#6"
    if case == "ik-mc78-step":
        return (Step("RCLM", v=0.025, wz=0.03, diff=True, clearance=0.22, hold_s=10.0, **kw),
                Step("RCLM", v=0.025, wz=-0.03, diff=True, clearance=0.19, hold_s=10.0, **kw)), \
            "steps to 25 mm/s and +-0.03 rad/s (differential) while lowering: MC#7, MC#8"
    raise ValueError(f"unknown ik instance {b.instance!r}; valid: {', '.join(IK_INSTANCES)}")


@instance(*IK_INSTANCES, group="ik", methods=("rclm",), timeout=120.0)
def _ik(b: Build) -> Layout:
    """Group ``ik``: one motion constraint driven to its QP boundary (module docstring)."""
    plan, note = _plan(b)
    if variant_of(b.instance) == "noqp":
        note += " (QP bypassed: the nominal command executed)"
    elif variant_of(b.instance) == "target":
        note += " (QP rows linearised about the rockers' servo targets)"
    cross = CROSS_DEG if case_of(b.instance) == "ik-mc4-cross" else 0.0
    return Layout(FLAT, (), "loose", plan, None, cross_deg=cross, note=note + " [issue 27 piece 5]")
