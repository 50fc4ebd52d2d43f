"""Who carries OCTOPUS at chosen instants of one trial: each robot geom's normal ground load (and
its vertical part), where it touches, the CLM climb's latches and the arms' tips and boom commands.

    python tools/probe_octopus_loads.py clm terrace2-front 1 48.5,49.5,52,54
    python tools/probe_octopus_loads.py clm step-400 0 stages

The evidence behind docs/octopus.md's reading of the crawlers' zero load share in the terrace
climbs (a nose dropping onto its crawlers for one row; the robot held up on its arm tips
between the floor and the second top, crawlers in the air). With ``stages`` instead of instants:
the mean vertical ground load of each group of geoms (tracks, front and rear flippers, front and
rear arm tips) over each stage of CLM's first climb (the command's ``stage``: "The climb's stages").
Evaluation only: it reads the task's contact pass, as the stored rows do.
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
    ap.add_argument("times", help="comma-separated instants (s), or 'stages'")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="config override")
    a = ap.parse_args()
    if a.times == "stages":
        stages(a)
        return
    times = sorted(float(x) for x in a.times.split(","))
    spec = SYSTEM.trial_spec(a.method, a.instance, a.seed,
                             {**parse_overrides(a.set), "protocol.timeout": times[-1] + 1.0})
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


#: the geom groups of :func:`stages`, by name prefix (the first that matches)
GROUPS = (("front tips", ("arm_LF", "arm_RF")), ("rear tips", ("arm_",)),
          ("front flippers", ("flipper_LF", "flipper_RF")), ("rear flippers", ("flipper_",)), ("tracks", ("track_",)))


def stages(a) -> None:
    """Per stage of the first CLM climb: its span, mean pitch and each group's mean vertical load."""
    from terrabench.systems.octopus.clm import STAGE_NAMES, WALK

    spec = SYSTEM.trial_spec(a.method, a.instance, a.seed, parse_overrides(a.set))
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    m, d = ep.model, ep.data
    group = {g: next((name for name, pre in GROUPS if m.geom(g).name.startswith(pre)), None) for g in range(m.ngeom)}
    acc: dict = {}
    while stop is None:
        cmd = ctl(obs)
        k = getattr(cmd, "stage", 0)
        if k in STAGE_NAMES and k != max(STAGE_NAMES):  # the climb's stages, not the release
            sel, rg, f, _ = task._contacts()
            load = collections.defaultdict(float)
            for i, (g, j) in enumerate(zip(rg.tolist(), sel.tolist())):
                if group[g]:
                    load[group[g]] += abs(float(f[i, 0]) * float(d.contact.frame[j, 2]))
            row = acc.setdefault(k, {"t": [obs.t, obs.t], "pitch": [], **{name: [] for name, _ in GROUPS}})
            row["t"][1] = obs.t
            row["pitch"].append(obs.pitch)
            for name, _ in GROUPS:
                row[name].append(load[name])
        elif acc and ctl.machine.state == WALK:
            break  # the first climb is over
        obs, stop = ep.step(cmd)
    for k, row in sorted(acc.items()):
        print(f"{STAGE_NAMES[k]:10s} {row['t'][0]:6.1f}-{row['t'][1]:6.1f} s, pitch {np.mean(row['pitch']):.2f} rad: "
              + ", ".join(f"{name} {np.mean(row[name]):.0f} N" for name, _ in GROUPS))


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
