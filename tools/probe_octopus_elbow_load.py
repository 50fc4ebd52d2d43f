"""Can OCTOPUS sense its arms' share of the load? Each arm tip's true vertical load against what
its elbow torque says (the torque over the tip's horizontal lever about the elbow, level frame:
encoders + IMU, as the controller could compute it), through one CLM trial.

    python tools/probe_octopus_elbow_load.py step-400 0

Prints, per arm, the fit tau = k F lever + c over the rows with the tip loaded (> 20 N), then per
time window the arms' summed true load, the summed estimate tau / lever and their correlation.
The evidence behind docs/octopus.md's "The arms' press" (why the press is not regulated on a
sensed load). Evaluation only: it reads the simulator's contact forces.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from terrabench.sim.episode import Episode
from terrabench.systems.octopus import arm_kinematics as ak
from terrabench.systems.octopus.robot import ARMS, Names
from terrabench.systems.octopus.scenarios import SYSTEM


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("instance")
    ap.add_argument("seed", type=int)
    ap.add_argument("--windows", default="5,15,20,25,30,35,40", help="window edges (s), comma-separated")
    a = ap.parse_args()
    spec = SYSTEM.trial_spec("clm", a.instance, a.seed)
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    m, d, r = ep.model, ep.data, ctl.robot
    tip_of = {m.geom(Names.tip(k)).id: i for i, k in enumerate(ARMS)}
    mx, my, mz = r.arm_mount
    rows = []
    while stop is None:
        cmd = ctl(obs)
        sel, rg, f, _ = task._contacts()
        load = np.zeros(4)
        for c, (g, j) in enumerate(zip(rg.tolist(), sel.tolist())):
            if g in tip_of:  # the normal force's vertical part
                load[tip_of[g]] += abs(float(f[c, 0]) * float(d.contact.frame[j, 2]))
        rot = ak.rotation_rc(obs.roll, obs.pitch)
        tips = ak.fk_all(obs.q_arm, r)
        lever = np.zeros(4)
        for i in range(4):
            sw, bm, _ = obs.q_arm[i].tolist()
            sx, sy = ak.SIGNS[i]
            u = np.array([math.sin(sw), sy * math.cos(sw), 0.0])  # the arm's reach direction in {R}
            elbow = np.array([sx * mx, sy * my, mz + 0.04]) + r.l1 * math.cos(bm) * u - [0, 0, r.l1 * math.sin(bm)]
            v, uc = rot @ (tips[i] - elbow), rot @ u
            lever[i] = v[0] * uc[0] + v[1] * uc[1]
        rows.append([obs.t, *load, *obs.tau_elbow, *lever])
        obs, stop = ep.step(cmd)
    x = np.array(rows)
    t, load, tau, lever = x[:, 0], x[:, 1:5], x[:, 5:9], x[:, 9:13]
    for i, k in enumerate(ARMS):
        on = load[:, i] > 20.0
        fit, *_ = np.linalg.lstsq(np.c_[load[on, i] * lever[on, i], np.ones(on.sum())], tau[on, i], rcond=None)
        print(f"{k}: tau = {fit[0]:.3f} F lever {fit[1]:+.2f} N m over {on.sum()} loaded ticks")
    ok = np.abs(lever) > 0.05
    est = np.clip(np.where(ok, tau / np.where(ok, lever, 1.0), 0.0), 0.0, None)
    edges = [float(v) for v in a.windows.split(",")]
    for t0, t1 in zip(edges, edges[1:]):
        w = (t >= t0) & (t < t1)
        if w.sum() > 2:
            true, guess = load[w].sum(1), est[w].sum(1)
            print(f"{t0:5.1f}-{t1:5.1f} s: arms carry {true.mean():5.0f} N, the elbows say {guess.mean():5.0f} N "
                  f"(corr {np.corrcoef(true, guess)[0, 1]:.2f})")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()
    main()
