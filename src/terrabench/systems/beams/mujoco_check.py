"""Cross-check of the analytic contact model against MuJoCo.

The same geometry is built with ``mujoco.MjSpec``: a mocap ellipsoid (the robot, pose imposed)
and two thin plates on hinge joints with torsion springs (``stiffness``), frictionless
(``condim = 1``), no gravity. The robot is pushed forward in small steps at a fixed roll and
pitch; after each step the beams settle (damped) and we record each beam's hinge angle and the
total contact force on the robot, then compare with :func:`model.contact_scalar` at the same pose.
Differences come from MuJoCo's soft contact (small penetration), the plates' finite thickness and
MuJoCo's single-point convex collision.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from terrabench.benchmark.trial import TrialResult
from terrabench.config import param

from .model import Beam, BeamLayout, RobotParams, SimulatedTimeout, contact_scalar


@dataclass(frozen=True)
class CheckConfig:
    """Settings of the quasi-static pushes."""

    thickness: float = param(0.002, gt=0, unit="m", doc="Plate thickness in MuJoCo, m (the analytic plate has none)")
    """Plate thickness in MuJoCo, m (the analytic plate has none)."""
    beam_mass: float = param(0.002, gt=0, unit="kg", doc="Plate mass in MuJoCo, kg (the analytic beam is massless")
    """Plate mass in MuJoCo, kg (the analytic beam is massless; a small mass keeps MuJoCo stable)."""
    timestep: float = param(5e-5, gt=0, unit="s", doc="MuJoCo time step, s (small enough for the stiff contact below)")
    """MuJoCo time step, s (small enough for the stiff contact below)."""
    settle_time: float = param(0.05, ge=0, unit="s", doc="Dwell at each measurement position, s")
    """Dwell at each measurement position, s."""
    push_speed: float = param(0.02, gt=0, unit="m/s", doc="Speed of the imposed push between positions, m/s")
    """Speed of the imposed push between positions, m/s."""
    push: float = param(0.03, gt=0, unit="m", doc="Push distance past first contact, m")
    """Push distance past first contact, m."""
    n_positions: int = param(7, ge=1, doc="Push positions (the first is just after first contact)")
    """Push positions (the first is just after first contact)."""
    solref: tuple[float, float] = param((-1e6, -60.0), length=2,
                                        doc="contact solref: (timeconst s, dampratio) or (-stiffness, -damping)")
    """MuJoCo contact solref: (time constant s, damping ratio), or negative (-stiffness N/m,
    -damping N s/m) for direct stiffness."""
    soft_solref: tuple[float, float] = param((0.002, 1.0), length=2, gt=0,
                                             doc="solref of the second, default-like soft push")
    """solref of the second, default-like soft push that shows what penetration costs."""
    soft_timestep: float = param(2e-4, gt=0, unit="s", doc="MuJoCo time step of the soft push, s")
    """MuJoCo time step of the soft push, s."""


def build_model(robot: RobotParams, layout: BeamLayout, beams: tuple[Beam, Beam], cfg: CheckConfig):
    """MjSpec scene: mocap ellipsoid + two spring-hinged plates. Returns the compiled MjModel."""
    import mujoco

    from terrabench.sim.physics import PhysicsConfig

    spec = mujoco.MjSpec()
    spec.compiler.degree = False  # joint ranges below are in radians
    # no gravity (the analytic check is quasi-static); otherwise MuJoCo's own defaults
    PhysicsConfig(timestep=cfg.timestep, integrator="euler", gravity=0.0, iterations=100,
                  ccd_tolerance=1e-6).apply(spec)
    wb = spec.worldbody
    body = wb.add_body(name="robot", mocap=True, pos=[-0.2, 0.0, robot.height])
    body.add_geom(name="robot_geom", type=mujoco.mjtGeom.mjGEOM_ELLIPSOID, size=[robot.a, robot.b, robot.c],
                  condim=1, friction=[0.0, 0.0, 0.0], solref=list(cfg.solref),
                  solimp=[0.99, 0.999, 1e-4, 0.5, 2], contype=1, conaffinity=1)
    for i, bm in enumerate(beams):
        y0, y1 = layout.y_range(i)
        ell = layout.length - bm.h_b
        b = wb.add_body(name=f"beam{i}", pos=[0.0, 0.5 * (y0 + y1), bm.h_b])
        # damping near critical for the plate's inertia so it settles within the dwell
        inertia = cfg.beam_mass * ell ** 2 / 3
        b.add_joint(name=f"hinge{i}", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0], stiffness=bm.k,
                    damping=2.0 * math.sqrt(max(bm.k, 1e-6) * inertia), range=[0.0, 0.5 * math.pi], limited=True)
        # back face of the plate on the hinge line, like the analytic zero-thickness plate
        b.add_geom(name=f"plate{i}", type=mujoco.mjtGeom.mjGEOM_BOX,
                   size=[0.5 * cfg.thickness, 0.5 * (y1 - y0), 0.5 * ell],
                   pos=[0.5 * cfg.thickness, 0.0, 0.5 * ell], mass=cfg.beam_mass, condim=1,
                   friction=[0.0, 0.0, 0.0], contype=1, conaffinity=1)
    return spec.compile()


def _robot_force(model, data, geom_id: int) -> np.ndarray:
    import mujoco

    total = np.zeros(3)
    f6 = np.zeros(6)
    for i in range(data.ncon):
        c = data.contact[i]
        if geom_id not in (c.geom1, c.geom2):
            continue
        mujoco.mj_contactForce(model, data, i, f6)
        f = np.asarray(c.frame).reshape(3, 3).T @ f6[:3]  # contact frame -> world; acts on geom2
        total += f if c.geom2 == geom_id else -f
    return total


def _quat(alpha: float, beta: float) -> np.ndarray:
    """Quaternion (w, x, y, z) of Ry(-beta) Rx(alpha)."""
    qy = np.array([math.cos(-beta / 2), 0.0, math.sin(-beta / 2), 0.0])
    qx = np.array([math.cos(alpha / 2), math.sin(alpha / 2), 0.0, 0.0])
    w1, x1, y1, z1 = qy
    w2, x2, y2, z2 = qx
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def first_contact_x(alpha: float, beta: float, robot: RobotParams, layout: BeamLayout) -> float:
    """Smallest x (m, 0.1 mm resolution) at which the analytic robot touches a beam."""
    xs = np.arange(-0.2, 0.1, 1e-4)
    for x in xs:
        if any(contact_scalar((x, alpha, beta), Beam(1.0), i, robot, layout).in_contact for i in range(2)):
            return float(x)
    raise ValueError(f"no contact at roll {math.degrees(alpha):.1f} deg, pitch {math.degrees(beta):.1f} deg")


def compare_push(roll_deg: float, pitch_deg: float, cfg: CheckConfig = CheckConfig(),
                 robot: RobotParams = RobotParams(), layout: BeamLayout = BeamLayout(), k: float = 0.25,
                 timeout: float = math.inf) -> dict[str, np.ndarray]:
    """Push at fixed (roll, pitch) into two beams of stiffness ``k`` (N m/rad); return the
    per-position analytic and MuJoCo deflections/forces. Raises :class:`SimulatedTimeout` when
    the MuJoCo time would pass ``timeout`` s.

    Returns:
        Arrays keyed ``x`` (N,), ``theta_an`` / ``theta_mj`` (N, 2) rad, ``f_an`` / ``f_mj`` (N, 3) N.
    """
    import mujoco

    beams = (Beam(k), Beam(k))
    model = build_model(robot, layout, beams, cfg)
    data = mujoco.MjData(model)
    gid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "robot_geom")
    al, be = math.radians(roll_deg), math.radians(pitch_deg)
    x0 = first_contact_x(al, be, robot, layout)
    xs = x0 + np.linspace(0.002, cfg.push, cfg.n_positions)
    data.mocap_quat[0] = _quat(al, be)
    n_settle = int(round(cfg.settle_time / cfg.timestep))
    out = {k: [] for k in ("x", "theta_an", "theta_mj", "f_an", "f_mj")}
    # move the mocap body slowly and continuously (a few micrometres per step) so the thin
    # plates are never tunnelled, and dwell at each measurement position so the beams settle
    step = cfg.push_speed * cfg.timestep
    x = x0 - 0.005
    for xm in xs:
        while x < xm:
            x = min(x + step, xm)
            data.mocap_pos[0] = [x, 0.0, robot.height]
            mujoco.mj_step(model, data)
        if data.time + cfg.settle_time > timeout:
            raise SimulatedTimeout(f"the MuJoCo push reached the simulated-time cap of {timeout} s")
        for _ in range(n_settle):
            mujoco.mj_step(model, data)
        mujoco.mj_forward(model, data)
        cs = [contact_scalar((x, al, be), beams[i], i, robot, layout) for i in range(2)]
        out["x"].append(x)
        out["theta_an"].append([c.theta for c in cs])
        out["theta_mj"].append([data.qpos[model.jnt_qposadr[i]] for i in range(2)])
        out["f_an"].append(np.add(cs[0].force, cs[1].force))
        out["f_mj"].append(_robot_force(model, data, gid))
    return {k: np.asarray(v) for k, v in out.items()}


def agreement(res: dict[str, np.ndarray]) -> dict[str, float]:
    """Summary figures: deflection error (deg), relative force-magnitude error, force-direction error (deg)."""
    dth = np.degrees(np.abs(res["theta_mj"] - res["theta_an"]))
    fa, fm = res["f_an"], res["f_mj"]
    na, nm = np.linalg.norm(fa, axis=1), np.linalg.norm(fm, axis=1)
    ok = na > 1e-6
    rel = np.abs(nm[ok] - na[ok]) / na[ok]
    cos = np.clip((fa[ok] * fm[ok]).sum(1) / np.maximum(na[ok] * nm[ok], 1e-12), -1, 1)
    ang = np.degrees(np.arccos(cos))
    return {
        "theta_err_mean_deg": float(dth.mean()), "theta_err_max_deg": float(dth.max()),
        "theta_mean_deg": float(np.degrees(res["theta_an"]).mean()),
        "force_rel_err_median": float(np.median(rel)) if rel.size else math.nan,
        "force_rel_err_max": float(rel.max()) if rel.size else math.nan,
        "force_dir_err_max_deg": float(ang.max()) if ang.size else math.nan,
        "force_mean_N": float(na.mean()),
    }


def run_contact_check(cfg) -> TrialResult:
    """Trial wrapper: ``cfg`` is a :class:`scenarios.TrialConfig` (pose in ``protocol``, k = case.k1)."""
    t0 = time.perf_counter()
    p, ck = cfg.protocol, cfg.check
    res = compare_push(p.roll_deg, p.pitch_deg, ck, cfg.robot, cfg.layout, cfg.case.k1, p.timeout)
    metrics = agreement(res)
    # the same push with MuJoCo's default-like soft contact shows what penetration costs
    soft_cfg = replace(ck, solref=tuple(ck.soft_solref), timestep=ck.soft_timestep)
    soft = agreement(compare_push(p.roll_deg, p.pitch_deg, soft_cfg, cfg.robot, cfg.layout, cfg.case.k1, p.timeout))
    metrics.update({f"soft_{k}": v for k, v in soft.items()})
    ts = {"t": res["x"], "theta1_an": res["theta_an"][:, 0], "theta2_an": res["theta_an"][:, 1],
          "theta1_mj": res["theta_mj"][:, 0], "theta2_mj": res["theta_mj"][:, 1],
          "fx_an": res["f_an"][:, 0], "fz_an": res["f_an"][:, 2], "fx_mj": res["f_mj"][:, 0],
          "fz_mj": res["f_mj"][:, 2], "fy_an": res["f_an"][:, 1], "fy_mj": res["f_mj"][:, 1]}
    return TrialResult("done", metrics, ts, time.perf_counter() - t0, {"note": "timeseries 't' holds the push x, m"})
