"""Test oracles: the numpy / Python-float forms the compiled kernels of ``srwmr`` must equal
bitwise. They live here, not in the package: the compiled kernel is the code; these are its
specification, written in the most readable form (tests/srwmr/test_perf_contracts.py compares)."""

from __future__ import annotations

import math

import numpy as np

from terrabench.systems.srwmr import constraints as mc
from terrabench.systems.srwmr.constraints import (
    NAMES,
    Scales,
    eta_change,
    eta_rocker_vs_side,
    eta_roll,
    eta_roll_rate,
    eta_yaw,
    load_ratios,
    mc2_ratio,
)
from terrabench.systems.srwmr.ik import N_INEQ, N_U, IKLimits, IKState
from terrabench.systems.srwmr.kinematics import rocker_jacobian, wheelbase_front_middle
from terrabench.systems.srwmr.robot import RobotConfig
from terrabench.systems.srwmr.sensing import rpy_from_quat
from terrabench.systems.srwmr.task import _ETA, _ETA_END, _NC


def geometry_pair_reference(cfg: RobotConfig, delta, mu):
    """``kinematics.geometry_pair`` in Python floats (the form the compiled kernel must equal bitwise;
    tested): ``(geometry(cfg, delta), geometry(cfg, delta, mu))`` in one pass."""
    d0, d1 = float(delta[0]), float(delta[1])
    b, a, bm, z, th0, lpr, lpf, e, yl, bq, tf = (float(v) for v in cfg.kernel_lengths)
    ax, az = a * math.cos(tf), -a * math.sin(tf) - lpf
    mu = mu.tolist() if isinstance(mu, np.ndarray) else [float(m) for m in mu]
    s0, c0 = math.sin(0.0), math.cos(0.0)
    P0: list = [None] * 6
    P: list = [None] * 6
    J0: list = [None] * 6
    J: list = [None] * 6
    for s, dl in ((0, d0), (1, d1)):
        sg = 1.0 if s == 0 else -1.0
        ang = th0 + dl
        ca, sa = math.cos(ang), math.sin(ang)
        px, pz = -b * ca, -b * sa
        jrow = (b * sa, 0.0, -b * ca)
        for wi, xb in ((2 + s, bm), (4 + s, -bq)):
            m = mu[wi]
            P0[wi] = (px + xb - sg * e * s0, sg * yl + sg * e * c0, pz - lpr)
            P[wi] = (px + xb - sg * e * math.sin(m), sg * yl + sg * e * math.cos(m), pz - lpr)
            J0[wi] = J[wi] = jrow
        cq, sq = math.cos(z * dl), math.sin(z * dl)
        for PP, JJ, sm, cm in ((P0, J0, s0, c0), (P, J, math.sin(mu[s]), math.cos(mu[s]))):
            xa = ax - sg * e * sm
            PP[s] = (xa * cq + az * sq, sg * yl + sg * e * cm, -xa * sq + az * cq)
            JJ[s] = (z * (-xa * sq + az * cq), 0.0, z * (-xa * cq - az * sq))
    return (np.array(P0), np.array(J0)), (np.array(P), np.array(J))


def period_ratios_reference(cfg, sc: Scales, u, u_prev, J, dz, wb, delta, ddelta, mu, load, rim_cmd=None):
    """:func:`period_ratios` with the numpy functions of this module (the form it must equal)."""
    r = np.zeros(len(NAMES))
    if rim_cmd is not None and (np.abs(ddelta) > 1e-4).any():
        side = np.array([0, 1, 0, 1, 0, 1])
        v_kin = u_prev[0] + J[:, 0] * ddelta[side]
        r[0] = mc2_ratio(rim_cmd * np.cos(mu), v_kin, sc)
    fl = cfg.wheelbase_fm
    r[1] = max((fl - wb[0]) / fl, (fl - wb[1]) / fl)
    r[2] = eta_roll(dz * delta, sc)
    r[3] = eta_yaw(wb, sc)
    if u[3] or u[4]:
        half = cfg.track / 2
        v_side = np.array([u[0] - u[2] * half, u[0] + u[2] * half])
        r[4] = eta_rocker_vs_side(J[0:2, 0] * u[3:5], v_side, sc)
    r[5] = eta_change(u[0], u_prev[0], sc.v_floor)
    r[6] = eta_change(u[2], u_prev[2], sc.w_floor)
    r[7] = eta_roll_rate(dz * u[3:5], sc)
    r[8], r[9] = load_ratios(load, sc)
    return r


def build_qp_reference(
    cfg: RobotConfig,
    st: IKState,
    kappa: np.ndarray,
    sc: mc.Scales,
    lim: IKLimits,
    ts: float,
    J: np.ndarray | None = None,
    wb: np.ndarray | None = None,
):
    """(G, h, lb, ub) of one control step, written row by row (the specification of
    :func:`_qp_kernel`, which must equal it bitwise; tested). Rows: MC3 x2, MC4 x2, MC5 x2, MC6 x4,
    MC7 x2, MC8 x2, MC9 x2."""
    d = st.delta
    J = rocker_jacobian(cfg, d) if J is None else J
    wb0 = cfg.wheelbase_fm  # nominal front-middle distance
    wb = wheelbase_front_middle(cfg, d) if wb is None else wb
    dwb = np.array([J[0, 0] - J[2, 0], J[1, 0] - J[3, 0]])  # d wb / d delta per side
    dz = np.array([-(J[0, 2] + J[2, 2] + J[4, 2]) / 3, -(J[1, 2] + J[3, 2] + J[5, 2]) / 3])  # hinge rise per delta
    G = np.zeros((N_INEQ, N_U))
    h = np.zeros(N_INEQ)
    big = 1e6
    k2, k3, k4, k5, k6, k7, k8, k9 = (kappa[i] for i in range(8))
    # MC3: eta_wb(next) = (wb0 - wb - dwb * rate * ts)/wb0 <= k3  ->  -dwb ts/wb0 * rate <= k3 - eta
    eta = (wb0 - wb) / wb0
    for s in (0, 1):
        G[s, 3 + s] = -dwb[s] * ts / wb0
        h[s] = (k3 - eta[s]) if np.isfinite(k3) else big
    # MC4: |(hL - hR) + ts(dzL rL - dzR rR)| <= k4 dh  (heights from the symmetric model: dz * delta)
    hl, hr = dz[0] * d[0], dz[1] * d[1]
    for j, sg in ((2, 1.0), (3, -1.0)):
        G[j, 3], G[j, 4] = sg * dz[0] * ts, -sg * dz[1] * ts
        h[j] = (k4 * sc.dh - sg * (hl - hr)) if np.isfinite(k4) else big
    # MC5: |(wbL - wbR) + ts(dwbL rL - dwbR rR)| <= k5 dd
    for j, sg in ((4, 1.0), (5, -1.0)):
        G[j, 3], G[j, 4] = sg * dwb[0] * ts, -sg * dwb[1] * ts
        h[j] = (k5 * sc.dd - sg * (wb[0] - wb[1])) if np.isfinite(k5) else big
    # MC6: |J_front,x rate_s| <= k6 max(|v_side_prev|, v6_floor), both signs per side
    half = cfg.track / 2
    v_side = np.array([st.u_prev[0] - st.u_prev[2] * half, st.u_prev[0] + st.u_prev[2] * half])
    for s in (0, 1):
        lim6 = k6 * max(abs(v_side[s]), sc.v6_floor) if np.isfinite(k6) else big
        G[6 + 2 * s, 3 + s], G[7 + 2 * s, 3 + s] = J[s, 0], -J[s, 0]
        h[6 + 2 * s] = h[7 + 2 * s] = lim6
    # MC7 / MC8: change of vx and wz per step
    lim7 = k7 * max(abs(st.u_prev[0]), sc.v_floor) if np.isfinite(k7) else big
    lim8 = k8 * max(abs(st.u_prev[2]), sc.w_floor) if np.isfinite(k8) else big
    G[10, 0], h[10] = 1.0, st.u_prev[0] + lim7
    G[11, 0], h[11] = -1.0, -st.u_prev[0] + lim7
    G[12, 2], h[12] = 1.0, st.u_prev[2] + lim8
    G[13, 2], h[13] = -1.0, -st.u_prev[2] + lim8
    # MC9: |dzL rL - dzR rR| <= k9 vz9
    lim9 = k9 * sc.vz9 if np.isfinite(k9) else big
    G[14, 3], G[14, 4], h[14] = dz[0], -dz[1], lim9
    G[15, 3], G[15, 4], h[15] = -dz[0], dz[1], lim9
    lb = np.array([-lim.v_max, -lim.v_max, -lim.w_max, -lim.rate_max, -lim.rate_max])
    ub = -lb
    # the rocker range: do not step past it
    lb[3:] = np.maximum(lb[3:], (lim.delta_range[0] - d) / ts)
    ub[3:] = np.minimum(ub[3:], (lim.delta_range[1] - d) / ts)
    return G, h, lb, ub


def refresh_reference(self):
    """``Observation.refresh`` with numpy gathers (the form the compiled read must equal); ``self``
    is the observation, refreshed in place."""
    d = self._d
    s = d.sensordata
    self.t = float(d.time)
    qp = d.qpos[self._q_idx]  # rocker L R, differential L R, bogie L R, steering c1..c6
    qv = d.qvel[self._v_idx]  # rocker L R, wheel spin c1..c6
    self.delta = -qp[0:2]
    self.phi, self.zeta, self.mu = qp[2:4], qp[4:6], qp[6:12]
    self.ddelta = -qv[0:2]
    self.spin = qv[2:8]
    self.tau = d.actuator_force[self._drive]
    q = s[self._quat : self._quat + 4]
    self.rpy = np.array(rpy_from_quat(q))
    self.gyro = s[self._gyro : self._gyro + 3].copy()
    # F/T sensor: force the pillar transmits (site frame); the load is the component along
    # the pillar (-z of the site frame carries the wheel)
    load = -s[self._ftz] + self._below
    if self.load_noise:
        z = self.rng.standard_normal(10)
        self.load = load + z[0:6] * self.load_noise
        z = z[6:10]
    else:
        z = self.rng.standard_normal(4)
        self.load = load
    yaw = self.rpy[2]
    self.xy = d.xpos[self._chassis, :2] + z[0:2] * self.pose_noise
    self.yaw = yaw
    vw = d.qvel[self._root : self._root + 3]  # free joint: linear velocity of the origin, world frame
    c, sn = math.cos(yaw), math.sin(yaw)
    fwd, lat = c * vw[0] + sn * vw[1], -sn * vw[0] + c * vw[1]
    self.v_body = np.array([fwd, lat]) + z[2:4] * self.speed_noise
    return self


def row_reference(self, obs, cmd) -> np.ndarray:
    """``SRWMRTask.row`` filled slice by slice with numpy (the form the kernel must equal); ``self``
    is the task."""
    d, t = self.data, self.soil_wheels.truth
    out = np.empty(_NC)
    p = d.xpos[self.chassis]
    vw = d.qvel[0:3]
    rpy = obs.rpy
    yaw = rpy[2]
    c, s = math.cos(yaw), math.sin(yaw)
    out[0:3] = p
    out[3], out[4], out[5] = yaw, rpy[1], rpy[0]
    out[6] = c * vw[0] + s * vw[1]
    out[8:10] = obs.delta
    slip, sink, dp = t["slip"], t["sinkage"], t["DP"]
    soil = sink > 0.0  # the wheels in the soil: a lifted wheel has no soil slip or sinkage
    n = int(soil.sum())
    out[12] = slip[soil].sum() / n if n else np.nan  # = np.mean over the wheels in the soil
    out[13] = sink[soil].sum() / n if n else np.nan
    out[14:20] = t["Fn"]
    out[20] = dp.sum()
    a = self.a_drive
    out[21] = np.abs(d.actuator_force[a] * d.actuator_velocity[a]).sum()
    out[22:28] = dp
    out[28:34] = obs.load
    out[_ETA] = np.nan if cmd is None else cmd.ratios
    out[_ETA_END] = -s * vw[0] + c * vw[1]
    out[_ETA_END + 2] = d.qvel[5]
    if cmd is None:
        out[7] = out[10] = out[11] = out[_ETA_END + 1] = out[_ETA_END + 3] = np.nan
    else:
        u = cmd.u
        out[7], out[10], out[11] = u[0], cmd.mode, getattr(cmd, "step", np.nan)
        out[_ETA_END + 1], out[_ETA_END + 3] = u[1], u[2]
    return out
