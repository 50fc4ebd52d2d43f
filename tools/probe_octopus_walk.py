"""Why OCTOPUS CLM's tracks stop while it walks, and which of its landings were false, in one trial.

    python tools/probe_octopus_walk.py block-500 0
    python tools/probe_octopus_walk.py terrace2-side 3 --set clm.relower_dz=0

Per walking tick with the crawlers waiting: the arm whose foothold is out of range and the arm
in transfer then (none: another arm is landing, settling or in the gait pause); the runs of
stopped ticks longer than a second; then every landing: the signal that landed the arm (elbow
torque, the tip stopped, the body tilted), how long it pressed before it settled and how far the
tip went on down (a drop beyond ``clm.relower_dz`` is a false landing, lowered again). The
evidence behind docs/octopus.md, "Tracks stopped". It reads the controller's state after each
call; the trial's bits are those of ``terrabench run`` with the same overrides.
"""

from __future__ import annotations

import argparse
import collections
import json

from terrabench.systems.base import run_task
from terrabench.systems.octopus.clm import ARMS, WALK
from terrabench.systems.octopus.scenarios import SYSTEM


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("instance")
    ap.add_argument("seed", type=int)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a config override (JSON value), as terrabench run --set")
    a = ap.parse_args()
    overrides = {}
    for kv in a.set:
        k, _, v = kv.partition("=")
        overrides[k] = json.loads(v)
    spec = SYSTEM.trial_spec("clm", a.instance, a.seed, overrides or None)
    _, task, ctl = SYSTEM.trial_parts(spec)

    ticks: list[tuple[float, bool, str, str]] = []   # walking ticks: (t, stopped, out arm, moving arm)
    landings: list[tuple[str, float, float, float, str]] = []   # (arm, t, pressed s, drop m, signal)
    start: dict[int, tuple[float, float, str]] = {}
    was = [False] * 4

    def probe(obs):
        cmd = ctl(obs)
        if ctl.state == WALK:
            moving = next((k for k, ph in ctl.phase.items() if ph), "")
            ticks.append((obs.t, ctl.out_of_reach, ctl.out_arm if ctl.out_of_reach else "", moving))
        for i, k in enumerate(ARMS):
            now = bool(ctl.landing[i])
            if now and not was[i]:
                start[i] = (obs.t, float(ctl.tip_r[i, 2]), ctl.land_why)
            if was[i] and not now:
                t0, z0, why = start[i]
                landings.append((k, t0, obs.t - t0, z0 - float(ctl.tip_r[i, 2]), why))
            was[i] = now
        return cmd

    r = run_task(task, probe)
    print(f"{a.instance} seed {a.seed}: {r.status} at {r.metrics['sim_time']:.1f} s "
          f"({r.info['reason']}); tracks stopped {r.metrics['tracks_stopped_share']:.3f}")
    stopped = [x for x in ticks if x[1]]
    print(f"walking ticks {len(ticks)}, stopped for an out-of-range foothold {len(stopped)}")
    for (out, moving), n in collections.Counter((x[2], x[3] or "none") for x in stopped).most_common():
        print(f"  {out} out of range, {moving} in transfer: {n} ticks")
    run0 = None
    for t, stop, out, moving in ticks + [(float("inf"), False, "", "")]:
        if stop and run0 is None:
            run0 = (t, out, moving)
        elif not stop and run0 is not None:
            if t - run0[0] > 1.0 and t != float("inf"):
                print(f"  stopped {run0[0]:.1f}-{t:.1f} s: {run0[1]} out of range, {run0[2] or 'none'} in transfer")
            run0 = None
    relower = SYSTEM.config_cls().clm.relower_dz if "clm.relower_dz" not in overrides else overrides["clm.relower_dz"]
    thr = relower or 0.08  # off: the arm stop cases' dD, the default relower_dz
    false = [x for x in landings if x[3] > thr - 1e-3]
    print(f"landings {len(landings)}, pressing {sum(x[2] for x in landings):.1f} s in all; the tip went on "
          f"down {thr:g} m or more in {len(false)} (clm.relower_dz = {relower:g})")
    for k, t0, dt, drop, why in landings:
        print(f"  {t0:6.2f} s {k}: {why or '-':14s} pressed {dt:4.2f} s, went on down {drop:+.3f} m")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
