"""What carries the MRS-CWC leader when a chain is trapped: its wheels, its bumper or its body?

The CWC stiffness law reads the leader's wheel torques (tau_m = 1.2 (tau_R - tau_L)). A leader
whose wheels are off the ground reads tau_m ~ 0 however hard the chain is stuck, so the soft
latch (|tau_env| > 20 N m) cannot fire. This study re-runs stored trials (same spec, so the
same trajectory bitwise) and samples, every ``--every`` control periods, the normal force on
the leader's wheels, on its bumper disc and on its body capsule, and its wheel torques.

Per trial it prints the share of samples in which the leader's wheels carry less than 10 %
of its weight ("wheels unloaded"), the share in which the bumper carries load, and the
median |tau_L|, |tau_R| and |tau_env| while unloaded, over the whole trial and over its last
``--tail`` seconds.

Usage: python benchmarks/leader_contact_study.py STORE [--methods cwc-tdt] [--instances B-02,B-05]
       [--status timeout] [--seed 0] [--jobs 2]
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor

import duckdb
import mujoco
import numpy as np


def probe(args: tuple[str, str, str, int, dict, int]) -> dict:
    from terrabench import catalog
    from terrabench.benchmark.trial import TrialSpec

    system = catalog.system("mrs-cwc")
    scenario, method, instance, seed, config, every = args
    spec = TrialSpec("mrs-cwc", scenario, method, instance, seed, config)
    chain = system.load_config(config).chain
    weight = 9.81 * (chain.body_mass + 2 * chain.wheel_mass + chain.bumper_mass)  # the leader's
    samples: list[tuple[float, ...]] = []
    part_of: dict[int, int] = {}  # leader geom -> 0 wheels, 1 bumper, 2 body (built on first call)

    def on_step(task, obs, cmd) -> None:
        m, d = task.model, task.data
        if not part_of:
            parts = {m.body("unit0_wheel_left").id: 0, m.body("unit0_wheel_right").id: 0,
                     m.body("bumper").id: 1, m.body("unit0").id: 2}
            part_of.update({g: parts[int(b)] for g, b in enumerate(m.geom_bodyid) if int(b) in parts})
        if round(obs.t / task.timing.control_period) % every:
            return
        f = np.zeros(6)
        load = [0.0, 0.0, 0.0]
        for i in range(d.ncon):
            c = d.contact[i]
            for g in {c.geom1, c.geom2} & part_of.keys():
                mujoco.mj_contactForce(m, d, i, f)
                load[part_of[g]] += f[0]
        tl, tr = obs.wheel_torque[0]
        samples.append((obs.t, *load, abs(tl), abs(tr), abs(cmd.tau_env)))

    result = system.run_trial(spec, on_step=on_step)
    return {"method": method, "instance": instance, "seed": seed, "status": result.status,
            "samples": np.array(samples), "weight": weight}


def describe(r: dict, tail: float) -> str:
    s = r["samples"]
    w = 0.1 * r["weight"]
    out = []
    for label, sel in (("all", np.ones(len(s), bool)), (f"last {tail:g} s", s[:, 0] >= s[-1, 0] - tail)):
        x = s[sel]
        un = x[:, 1] < w
        part = (f"{label}: wheels unloaded {100 * un.mean():5.1f} %, "
                f"bumper loaded {100 * (x[:, 2] > 5).mean():5.1f} %, "
                f"body loaded {100 * (x[:, 3] > 5).mean():5.1f} %")
        if un.any():
            part += (f"; while unloaded median |tau_L| {np.median(x[un, 4]):.1f}, |tau_R| {np.median(x[un, 5]):.1f}, "
                     f"|tau_env| {np.median(x[un, 6]):.1f} N m")
        out.append(part)
    return f"{r['method']} {r['instance']} seed {r['seed']} {r['status']}\n    " + "\n    ".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("store")
    ap.add_argument("--methods", default="cwc-tdt")
    ap.add_argument("--instances", default=None, help="comma-separated (default: every stored one)")
    ap.add_argument("--status", default=None, help="only trials that ended so (e.g. timeout)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--every", type=int, default=4, help="sample every N control periods")
    ap.add_argument("--tail", type=float, default=300.0)
    ap.add_argument("--jobs", type=int, default=1)
    a = ap.parse_args()
    con = duckdb.connect(a.store, read_only=True)
    rows = con.execute("select scenario, method, instance, seed, status, config from trials where system = 'mrs-cwc' "
                       "and seed = ? order by instance, method, finished_at", [a.seed]).fetchall()
    latest = {(m, i): (sc, m, i, s, st, cfg) for sc, m, i, s, st, cfg in rows}  # a re-run row wins
    rows = list(latest.values())
    methods = set(a.methods.split(","))
    inst = set(a.instances.split(",")) if a.instances else None
    todo = [(sc, m, i, s, json.loads(cfg), a.every) for sc, m, i, s, st, cfg in rows
            if m in methods and (inst is None or i in inst) and (a.status is None or st == a.status)]
    print(f"{len(todo)} trials")
    with ProcessPoolExecutor(a.jobs) as pool:
        results = list(pool.map(probe, todo))
    for r in results:
        print(describe(r, a.tail))
    for st in sorted({r["status"] for r in results}):
        sel = [r for r in results if r["status"] == st]
        un = [100 * (r["samples"][:, 1] < 0.1 * r["weight"]).mean() for r in sel]
        print(f"{st}: {len(sel)} trials, leader wheels unloaded: median {np.median(un):.1f} % of the trial "
              f"(range {min(un):.1f}-{max(un):.1f})")


if __name__ == "__main__":
    from terrabench import portable

    portable.reexec_pinned()  # trials on the stored rows' code paths (terrabench.portable)
    main()
