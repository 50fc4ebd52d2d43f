"""Who carries OCTOPUS at chosen instants of one trial: each robot geom's normal ground load (and
its vertical part), where it touches, the CLM climb's latches and the arms' tips and boom commands.

    python tools/probe_octopus_loads.py clm terrace2-front 1 48.5,49.5,52,54

The evidence behind docs/octopus.md's reading of the crawlers' zero load share in the terrace
climbs (a nose dropping onto its crawlers for one row; the robot held up on its arm tips
between the floor and the second top, crawlers in the air). Evaluation only: it reads the
task's contact pass, as the stored rows do.
"""

from __future__ import annotations

import argparse
import collections

import numpy as np

from terrabench.config import parse_overrides
from terrabench.sim.episode import Episode
from terrabench.systems.octopus.scenarios import SYSTEM


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("method", choices=SYSTEM.default_methods())
    ap.add_argument("instance")
    ap.add_argument("seed", type=int)
    ap.add_argument("times", help="comma-separated instants (s)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="config override")
    a = ap.parse_args()
    times = sorted(float(x) for x in a.times.split(","))
    specs = SYSTEM.plan(methods=[a.method], instances=[a.instance], seeds=a.seed + 1,
                        overrides={**parse_overrides(a.set), "protocol.timeout": times[-1] + 1.0})
    spec = next(s for s in specs if s.seed == a.seed)
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    m, d = ep.model, ep.data
    todo = list(times)
    while stop is None and todo:
        cmd = ctl(obs)
        if obs.t >= todo[0] - 1e-9:
            todo.pop(0)
            sel, rg, f, _ = task._contacts()
            load, vert, where = collections.defaultdict(float), collections.defaultdict(float), {}
            for i, (g, j) in enumerate(zip(rg.tolist(), sel.tolist())):
                name = m.geom(g).name
                load[name] += float(f[i, 0])
                vert[name] += abs(float(f[i, 0]) * float(d.contact.frame[j, 2]))  # the normal's world z
                where[name] = np.round(d.contact.pos[j], 3).tolist()
            latches = {k: getattr(ctl, k) for k in ("over", "up") if hasattr(ctl, k)}
            if hasattr(ctl, "lifted"):
                latches["lifted"] = np.asarray(ctl.lifted).tolist()
            print(f"t {obs.t:.2f} state {ctl.machine.state} pitch {obs.pitch:.2f} rad, "
                  f"normal load {sum(load.values()):.0f} N {latches}")
            for name, v in sorted(load.items(), key=lambda kv: -kv[1]):
                if v > 1.0:
                    print(f"    {name:24s} {v:7.1f} N (vertical {vert[name]:7.1f} N) at {where[name]}")
            if hasattr(ctl, "tip_r"):
                print("    arm tips z in {R} (m):", np.round(ctl.tip_r[:, 2], 3).tolist(),
                      " boom commands (rad):", np.round(cmd.arm[:, 1], 2).tolist())
        obs, stop = ep.step(cmd)
    if todo:
        print(f"the trial stopped at {obs.t:.2f} s ({stop[0] if stop else '?'}), before {todo}")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
