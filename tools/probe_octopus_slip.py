"""Where OCTOPUS's arm tips slip: per arm, the largest drift within one support phase of a CLM
trial (tip in contact, its arm not the one in transfer), when that phase began and ended, the
controller's state then and whether the controller counted the arm as a support.

    python tools/probe_octopus_slip.py terrace2-front 5 70

The evidence behind docs/octopus.md, "Tip slip by phase" (a swing grazing the block's face; an arm
not yet re-placed after a release rolling on the top). Evaluation only.
"""

from __future__ import annotations

import argparse
import math

from terrabench.config import parse_overrides
from terrabench.sim.episode import Episode
from terrabench.systems.octopus.clm import ARMS
from terrabench.systems.octopus.scenarios import SYSTEM


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("instance")
    ap.add_argument("seed", type=int)
    ap.add_argument("timeout", type=float, help="simulated seconds")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="config override")
    a = ap.parse_args()
    spec = SYSTEM.trial_spec("clm", a.instance, a.seed, {**parse_overrides(a.set), "protocol.timeout": a.timeout})
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    start: list[tuple | None] = [None] * len(ARMS)
    worst: list[tuple] = [(0.0, None)] * len(ARMS)
    while stop is None:
        cmd = ctl(obs)
        tips = task.tip_contacts()
        tp = ep.data.geom_xpos[task.tip_geoms].tolist()
        for i in range(len(ARMS)):
            if tips >> i & 1 and i != cmd.moving_arm:
                if start[i] is None:
                    start[i] = (obs.t, tp[i], ctl.machine.state)
                drift = math.dist(tp[i], start[i][1])
                if drift > worst[i][0]:
                    delta = [round(p - q, 3) for p, q in zip(tp[i], start[i][1])]
                    worst[i] = (drift, (round(start[i][0], 2), round(obs.t, 2), start[i][2], ctl.machine.state,
                                        bool(ctl.contact[i]), bool(ctl.caster[i]), delta))
            else:
                start[i] = None
        obs, stop = ep.step(cmd)
    print("arm  drift m  (from s, to s, state then, state now, controller contact, caster, dx dy dz m)")
    for k, (drift, why) in zip(ARMS, worst):
        print(f"{k:4s} {drift:7.3f}  {why}")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
