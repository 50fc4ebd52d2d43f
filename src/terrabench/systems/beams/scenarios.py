"""Beam-traversal experiments as trials: planning specs, running them, the sense-estimate-plan-track
pipeline.

Scenario ids (all version 1) and their methods / instances:

* ``beams/estimation-v1`` (group ``estimation``): methods ``estimate-4``, ``estimate-3``,
  ``estimate-2`` (number of unknowns); instances ``sigma{5,10,20,50}-ts300`` (Tables 1-3) and
  ``sigma20-ts{50,100,600}`` (Table 4). One trial = one noise draw (status ``done``).
* ``beams/traversal-v1`` (group ``traversal``): methods ``interact`` (sense, estimate, plan on
  the landscape, track) and ``avoid`` (roll through the gap on a contact-free plan); instances
  ``stiff`` and ``flimsy``.
* ``beams/open-loop-v1`` (group ``open-loop``): method ``open-loop``; instances
  ``{stiff,flimsy}-f{0.1,1}`` (constant F_x after contact, Sec. III-A).
* ``beams/delay-v1`` (group ``delay``): method ``interact``; instances ``{stiff,flimsy}-d{100,300,600}``
  (sensory delay in ms, Sec. III-E).
* ``beams/experiment-v1`` (group ``experiment``): method ``estimate-ktau``; instances
  ``acrylic-sigma{0,10,20}`` (Sec. IV, eq. 12 on simulated data).
* ``beams/contact-check-v1`` (group ``contact-check``): method ``mujoco``; instances
  ``roll{R}-pitch{P}`` (MuJoCo cross-check of the contact model).
* ``beams/barriers-v1`` (group ``barriers``): method ``landscape``; instances ``gap0.06`` ...
  ``gap0.14`` (Sec. II-G barriers vs the gap).

The trial config lives in :mod:`.config`, running a trial in :mod:`.trials`.
"""

from __future__ import annotations

import re
from typing import Any, Sequence

from terrabench.benchmark.plan import check_id_list
from terrabench.benchmark.trial import TrialSpec
from terrabench.config import override

from .config import ALIASES, CASES, OPEN_LOOP_CASES, TrialConfig

SYSTEM_ID = "beams"
SCENARIOS = {
    "estimation": "beams/estimation-v1",
    "traversal": "beams/traversal-v1",
    "open-loop": "beams/open-loop-v1",
    "delay": "beams/delay-v1",
    "experiment": "beams/experiment-v1",
    "contact-check": "beams/contact-check-v1",
    "barriers": "beams/barriers-v1",
}
GROUPS = tuple(SCENARIOS)

METHODS = {
    "estimate-4": "Fit k1, k2, hb1, hb2 from noisy force data (Table 1)",
    "estimate-3": "Fit k1, k2 and a shared hb (Tables 2, 4)",
    "estimate-2": "Fit k1, k2 with hb = 0 known (Table 3)",
    "interact": "Sense, estimate (3 unknowns), plan on the energy landscape, track by feedback linearization",
    "avoid": "Obstacle avoidance: contact-free landscape plan (roll through the gap), same tracker",
    "open-loop": "Constant F_x after contact, no torques (Sec. III-A)",
    "estimate-ktau": "Physical-experiment variant: fit shared (k, tau0) with beam mass (eq. 12)",
    "mujoco": "Quasi-static pushes in MuJoCo vs the analytic contact model",
    "barriers": "Landscape pitch and roll barriers at k_low, k_high and the crossover stiffness vs the gap",
}
METHOD_GROUP = {
    "estimate-4": ("estimation",), "estimate-3": ("estimation",), "estimate-2": ("estimation",),
    "interact": ("traversal", "delay"), "avoid": ("traversal",), "open-loop": ("open-loop",),
    "estimate-ktau": ("experiment",), "mujoco": ("contact-check",), "barriers": ("barriers",),
}

EST_INSTANCES = [f"sigma{s}-ts300" for s in (5, 10, 20, 50)] + [f"sigma20-ts{t}" for t in (50, 100, 600)]
TRAVERSAL_INSTANCES = ["stiff", "flimsy"]
OPEN_LOOP_INSTANCES = [f"{c}-f{f}" for c in ("stiff", "flimsy") for f in ("0.1", "1")]
DELAY_INSTANCES = [f"{c}-d{d}" for c in ("stiff", "flimsy") for d in (100, 300, 600)]
EXPERIMENT_INSTANCES = [f"acrylic-sigma{s}" for s in (0, 10, 20)]
CONTACT_INSTANCES = [f"roll{r}-pitch{p}" for r, p in ((0, 0), (0, 20), (20, 0), (30, 10), (-15, 30))]
BARRIER_INSTANCES = [f"gap{g / 100:.2f}" for g in range(6, 15)]

INSTANCES = {
    "estimation": EST_INSTANCES, "traversal": TRAVERSAL_INSTANCES, "open-loop": OPEN_LOOP_INSTANCES,
    "delay": DELAY_INSTANCES, "experiment": EXPERIMENT_INSTANCES, "contact-check": CONTACT_INSTANCES,
    "barriers": BARRIER_INSTANCES,
}


# --------------------------------------------------------------------------- specs

def _instance_config(group: str, method: str, instance: str) -> dict[str, Any]:
    """The dotted settings an instance fixes (applied on top of the defaults, before ``--set``)."""
    if group == "estimation":
        sig, ts = instance.split("-")
        return {"kind": "estimation", "sensing.sigma": int(sig[5:]) / 100, "sensing.sensing_time": int(ts[2:]) / 1000,
                "estimator.n_unknowns": int(method.split("-")[1]), "sensing.push_force": 1.0}
    if group == "traversal":
        k1, k2 = CASES[instance]
        return {"kind": "traversal", "case.k1": k1, "case.k2": k2, "protocol.strategy": method,
                "sensing.push_force": 0.1, "protocol.delay": 0.3, "sensing.sigma": 0.2}
    if group == "delay":
        case, d = instance.split("-d")
        k1, k2 = CASES[case]
        return {"kind": "traversal", "case.k1": k1, "case.k2": k2, "protocol.strategy": "interact",
                "sensing.push_force": 0.1, "protocol.delay": int(d) / 1000, "sensing.sigma": 0.2}
    if group == "open-loop":
        case, f = instance.split("-f")
        k1, k2 = OPEN_LOOP_CASES[case]
        return {"kind": "open-loop", "case.k1": k1, "case.k2": k2, "sensing.push_force": float(f)}
    if group == "experiment":
        return {"kind": "experiment", "sensing.sigma": int(instance.split("sigma")[1]) / 100}
    if group == "contact-check":
        m = re.fullmatch(r"roll(-?[\d.]+)-pitch(-?[\d.]+)", instance)
        if not m:
            raise ValueError(f"contact-check instance {instance!r} must look like 'roll20-pitch-10'")
        return {"kind": "contact-check", "protocol.roll_deg": float(m.group(1)),
                "protocol.pitch_deg": float(m.group(2))}
    if group == "barriers":
        return {"kind": "barriers", "layout.gap": float(instance[3:])}
    raise ValueError(f"unknown group {group!r}; valid: {', '.join(GROUPS)}")


def normalize_overrides(overrides: dict[str, Any]) -> dict[str, Any]:
    """Dotted keys; a leading ``beams.`` is dropped and the old flat names map through ALIASES."""
    out = {}
    for k, v in overrides.items():
        k = k.split(".", 1)[1] if k.startswith("beams.") else k
        out[ALIASES.get(k, k)] = v
    return out


def build_config(group: str, method: str, instance: str, overrides: dict[str, Any] | None = None) -> TrialConfig:
    """The resolved config of one trial: defaults, then the instance's settings, then overrides."""
    cfg = override(TrialConfig(), _instance_config(group, method, instance))
    if overrides:
        cfg = override(cfg, normalize_overrides(overrides))
    return cfg


def plan_specs(*, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
               group: str | None = None, seeds: int = 1, overrides: dict[str, Any] | None = None) -> list[TrialSpec]:
    """Expand a request into trial specs (see the module docstring for ids)."""
    overrides = normalize_overrides(dict(overrides or {}))
    if overrides:
        override(TrialConfig(), overrides)  # validate keys and values early
    groups = GROUPS if group in (None, "all") else (group,)
    for g in groups:
        if g not in SCENARIOS:
            raise ValueError(f"unknown beams group {g!r}; valid: {', '.join(GROUPS)}, all")
    known = sorted({i for g in GROUPS for i in INSTANCES[g]})
    # an empty list, an empty item or a bare string is refused, never read as 'every one'
    methods = check_id_list(methods, "beams method(s)", list(METHODS) + ["all"])
    instances = check_id_list(instances, "beams instance(s)", known)
    if methods is not None and methods == ["all"]:  # as for every system: 'all' = every method
        methods = None
    if methods:
        bad = [m for m in methods if m not in METHODS]
        if bad:
            raise ValueError(f"unknown beams method(s) {bad}; valid: {', '.join(METHODS)}, all")
    if instances:
        bad = [i for i in instances if i not in known]
        if bad:
            raise ValueError(f"unknown beams instance(s) {bad}; valid: {', '.join(known)}")
    if seeds < 1:
        raise ValueError(f"seeds = {seeds}; it must be >= 1")
    specs = []
    for g in groups:
        for m in METHODS:
            if g not in METHOD_GROUP[m] or (methods and m not in methods):
                continue
            for inst in INSTANCES[g]:
                if instances and inst not in instances:  # ids match exactly: 'stiff' is not 'stiff-d100'
                    continue
                cfg = build_config(g, m, inst, overrides)
                # noise-free or deterministic trials need one seed only
                deterministic = g in ("open-loop", "contact-check", "barriers") or m == "avoid" or \
                    (g == "experiment" and cfg.sensing.sigma == 0)
                for s in range(1 if deterministic else seeds):
                    specs.append(TrialSpec(SYSTEM_ID, SCENARIOS[g], m, inst, s, cfg.to_dict()))
    return specs
