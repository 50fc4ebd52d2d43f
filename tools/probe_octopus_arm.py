"""One OCTOPUS arm, tick by tick: its transfer phase, whether the controller holds it as a support,
the tip's ground-truth contact, the IMU pitch, the tip height in {R} against the descent target,
the elbow torque against its reference, the tip in {R} and in the world, and the boom and elbow
encoders against their commands (every fifth tick from T0 to T1).

    python tools/probe_octopus_arm.py octopus clm terrace2-front 15 LF 43.6 44.6
    python tools/probe_octopus_arm.py zoo octopus.clm step-down@0.6 0 LF 17.8 19.0

The evidence behind docs/octopus.md, "A pit that was a top" (a straight arm hanging free holds its
forearm up; one resting on a top presses it down). Evaluation only.
"""

from __future__ import annotations

import argparse

from terrabench import get_system
from terrabench.config import parse_overrides
from terrabench.sim.episode import Episode
from terrabench.systems.octopus.clm import ARMS


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("system", help="octopus, or zoo (method octopus.clm)")
    ap.add_argument("method")
    ap.add_argument("instance")
    ap.add_argument("seed", type=int)
    ap.add_argument("arm", choices=ARMS)
    ap.add_argument("t0", type=float, help="first simulated second printed")
    ap.add_argument("t1", type=float, help="last simulated second (the trial stops there)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="config override")
    a = ap.parse_args()
    system = get_system(a.system)
    spec = system.trial_spec(a.method, a.instance, a.seed, {**parse_overrides(a.set), "protocol.timeout": a.t1})
    _, task, ctl = system.trial_parts(spec)
    i = ARMS.index(a.arm)
    ep = Episode(task)
    obs, stop = ep.begin()
    tick = 0
    print("t s  phase support landing touch  pitch  tip z {R}  target z  tau_elbow  tau_ref  tip x, y {R}"
          "  world x, z  boom, elbow  command")
    while stop is None:
        cmd = ctl(obs)
        if obs.t >= a.t0 and tick % 5 == 0:
            w = ep.data.geom_xpos[task.tip_geoms][i]
            tr = ctl.tip_r[i]
            print(f"{obs.t:6.2f} {ctl.phase[a.arm]} {int(ctl.contact[i])} {int(ctl.landing[i])} "
                  f"{task.tip_contacts() >> i & 1}  {obs.pitch:+.3f}  {tr[2]:+.3f}  {ctl.low_z[i]:+.3f}  "
                  f"{obs.tau_elbow[i]:+6.1f}  {ctl.tau_ref[i]:+6.1f}  {tr[0]:+.3f} {tr[1]:+.3f}  "
                  f"{w[0]:.3f} {w[2]:.3f}  {obs.q_arm[i][1]:+.2f} {obs.q_arm[i][2]:+.2f}  "
                  f"{cmd.arm[i][1]:+.2f} {cmd.arm[i][2]:+.2f}")
        tick += 1
        obs, stop = ep.step(cmd)


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
