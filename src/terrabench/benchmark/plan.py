"""Planning: a user's request (system, methods, instances or group, seeds, overrides) -> trial specs.

Generic over the system contract (:class:`terrabench.systems.base.System`): the system names its
methods, instances, groups and scenario ids, and says which config a trial stores
(``trial_config``) and which seeds it needs (``seeds_for``); everything a user typed is validated
here, with one line naming the bad value and the valid choices.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from terrabench.benchmark.trial import TrialSpec


def split_ids(value: Sequence[str] | None, what: str, valid: Sequence[str]) -> list[str] | None:
    """Validate a user's list of ids (None = not given). An empty list is an error."""
    if value is None:
        return None
    items = [v for v in value if v]
    if not items:
        raise ValueError(f"{what}: an empty list was given; valid: {', '.join(valid)}")
    bad = [v for v in items if v not in valid]
    if bad:
        raise ValueError(f"unknown {what} {', '.join(map(repr, bad))}; valid: {', '.join(valid)}")
    return items


def plan_specs(system: Any, *, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
               group: str | None = None, seeds: int = 1, overrides: Mapping[str, Any] | None = None) -> list[TrialSpec]:
    """Trial specs of ``system`` for (methods x instances x seeds), seed-major.

    ``methods=["all"]`` means every method; ``instances`` and ``group`` are exclusive; with
    neither, the system's ``default_group``.
    """
    if not isinstance(seeds, int) or seeds < 1:
        raise ValueError(f"seeds must be an integer >= 1, got {seeds!r}")
    known = system.methods()
    if methods is not None and list(methods) == ["all"]:
        mids = list(known)
    else:
        mids = split_ids(methods, f"{system.id} method(s)", list(known)) or system.default_methods()
    if group is not None:
        valid_groups = list(system.groups) + ["all"]
        if group not in valid_groups:
            raise ValueError(f"unknown {system.id} group {group!r}; valid: {', '.join(valid_groups)}")
        if instances is not None:
            raise ValueError("give either instances (--terrains) or --group, not both")
    if instances is not None:
        chosen = system.select_instances(instances)
    else:
        chosen = system.instances(group if group is not None else system.default_group)
    cfg = system.resolve_config(overrides)
    out: list[TrialSpec] = []
    planned: list[tuple[str, str, dict[str, Any], range]] = []
    for inst in chosen:
        for mid in mids:
            c = system.trial_config(mid, inst, cfg)
            planned.append((mid, inst, c, system.seeds_for(mid, inst, c, seeds)))
    if not planned:
        raise ValueError(f"no {system.id} trial matches methods {mids} on instances {list(chosen)[:6]}...")
    for seed in range(seeds):
        for mid, inst, c, ss in planned:
            if seed in ss:
                out.append(TrialSpec(system.id, system.scenario(mid, inst), mid, inst, seed, c))
    return out
