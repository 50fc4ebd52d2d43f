"""Each arm tip's world drift through OCTOPUS's first CLM climb: from the climb's start to the front
over the top (the nose lift, Fig. 9e) and from there to the release; the default foothold rule
against ``clm.climb_face_pivot``, seeds 0..N-1.

    python tools/probe_octopus_drift.py step-400 10

One JSON line per trial: (instance, seed, pivot on, {"lift": [LF, RF, LR, RR] m, "t": [start, over]
s, "over": [...] m}); an arm lifted clear by the end of a stretch reads null. The evidence behind
docs/octopus.md, "The nose lift's pivot". Evaluation only: it reads the simulator's tip positions,
which the controller never sees.
"""

from __future__ import annotations

import argparse
import json
from multiprocessing import Pool

import numpy as np

from terrabench.sim.episode import Episode
from terrabench.systems.octopus.clm import CLIMB, RELEASE
from terrabench.systems.octopus.robot import ARMS, Names
from terrabench.systems.octopus.scenarios import SYSTEM


def drifts(job: tuple[str, int, bool]) -> tuple[str, int, bool, dict]:
    instance, seed, pivot = job
    spec = SYSTEM.trial_spec("clm", instance, seed, {"clm.climb_face_pivot": pivot})
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    tips = [ep.model.body(Names.tip(k)).id for k in ARMS]
    marks: dict = {}
    while stop is None and "release" not in marks:
        cmd = ctl(obs)
        state = ctl.machine.state
        key = None
        if state == CLIMB and "start" not in marks:
            key = "start"
        elif state == CLIMB and ctl.over and "over" not in marks:
            key = "over"
        elif state == RELEASE and "start" in marks:
            key = "release"
        if key:
            marks[key] = (obs.t, ep.data.xpos[tips, :2].copy(), list(ctl.lifted))
        obs, stop = ep.step(cmd)
    out: dict = {}
    for name, a, b in (("lift", "start", "over"), ("over", "over", "release")):
        if a in marks and b in marks:
            d = np.linalg.norm(marks[b][1] - marks[a][1], axis=1)
            out[name] = [None if marks[b][2][i] else round(float(x), 3) for i, x in enumerate(d)]
    if "over" in marks:
        out["t"] = [round(marks["start"][0], 2), round(marks["over"][0], 2)]
    return instance, seed, pivot, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("instance")
    ap.add_argument("seeds", type=int)
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args()
    jobs = [(a.instance, s, p) for s in range(a.seeds) for p in (False, True)]
    with Pool(a.workers) as pool:
        for row in pool.imap(drifts, jobs):
            print(json.dumps(row))


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
