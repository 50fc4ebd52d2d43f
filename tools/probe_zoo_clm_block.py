"""Probe OCTOPUS CLM on the mobility map's block: state, terrain case and tips every 0.5 s.

Runs the zoo trial ``octopus.clm`` on ``block@SEV`` (seed 0) through the system's own
``run_trial`` with a read-only wrapper around ``CLMController.__call__`` (the trial is not
changed) and prints, from 14 s: time, controller state (0 walk), the paper's terrain case from
the four tips (``rules.terrain_case``), the tips' contact bits and heights in {C}, the front
flipper angle, the IMU pitch and the crawler command. docs/zoo.md, "CLM on a short block".

Usage: python tools/probe_zoo_clm_block.py 0.15
"""

import sys

import numpy as np

import terrabench.systems.octopus.clm as clm
from terrabench import portable
from terrabench.catalog import system

portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)

sev = sys.argv[1] if len(sys.argv) > 1 else "0.15"
zoo = system("zoo")
spec = zoo.plan(methods=["octopus.clm"], instances=[f"block@{sev}"], seeds=1)[0]
rows = []
call = clm.CLMController.__call__


def probed(self, obs):
    c = call(self, obs)
    if int(round(obs.t * 50)) % 25 == 0:
        rows.append((round(obs.t, 2), self.state, self.last_case, self.contact.astype(int).tolist(),
                     np.round(self.tip_c[:, 2], 3).tolist(), round(float(obs.q_flip[0]), 2),
                     round(float(obs.pitch), 3), round(float(c.track[0]), 3)))
    return c


clm.CLMController.__call__ = probed
res = zoo.run_trial(spec)
print(res.status, res.metrics.get("progress"))
for r in rows:
    if r[0] > 14:
        print(*r)
