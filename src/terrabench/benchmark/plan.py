"""Planning: a user's request (system, methods, instances or group, seeds, overrides) -> trial specs.

Generic over the system contract (:class:`terrabench.systems.base.System`): the system names its
methods, instances, groups and scenario ids, and says which config a trial stores
(``trial_config``) and which seeds it needs (``seeds_for``); everything a user typed is validated
here, with one line naming the bad value and the valid choices.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping, Sequence

from terrabench.benchmark.trial import TrialSpec


def choices_text(valid: Sequence[str], system_id: str = "", limit: int = 30) -> str:
    """The valid ids for an error line: all of them, or (more than ``limit``) a few and the count."""
    valid = list(valid)
    if len(valid) <= limit:
        return ", ".join(valid)
    more = f"; every id: `terrabench list {system_id}`" if system_id else ""
    return f"{', '.join(valid[:4])} ... {', '.join(valid[-2:])} ({len(valid)} ids{more})"


def check_id_list(value: Any, what: str, valid: Sequence[str] | Callable[[], Sequence[str]],
                  system_id: str = "") -> list[str] | None:
    """``value`` as a list of ids (None = not given), or ValueError naming the bad value and the
    valid ids: a bare string or a non-list, an item that is not a string, an empty list or an
    empty item (``"A-01,"`` on the command line) are refused, never dropped or split."""
    if value is None:
        return None

    def choices() -> str:
        return choices_text(valid() if callable(valid) else valid, system_id)

    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple)):
        raise ValueError(f"{what}: expected a list of ids, got {value!r}; valid: {choices()}")
    items = list(value)
    if not items:
        raise ValueError(f"{what}: an empty list was given; valid: {choices()}")
    bad = [v for v in items if not isinstance(v, str)]
    if bad:
        raise ValueError(f"{what}: {bad[0]!r} is not an id (a string); valid: {choices()}")
    if any(not v.strip() for v in items):
        raise ValueError(f"{what}: {','.join(items)!r} has an empty item (ids are separated by single "
                         f"commas); valid: {choices()}")
    return items


def split_ids(value: Sequence[str] | None, what: str, valid: Sequence[str]) -> list[str] | None:
    """Validate a user's list of ids (None = not given). An empty list or an empty item is an error."""
    items = check_id_list(value, what, valid)
    if items is None:
        return None
    bad = [v for v in items if v not in valid]
    if bad:
        raise ValueError(f"unknown {what} {', '.join(map(repr, bad))}; valid: {', '.join(valid)}")
    return items


def check_group(system: Any, group: str | None, instances: Sequence[str] | None = None) -> None:
    """ValueError for a group ``system`` does not have (one line with the valid ones) or for a
    group given together with instances; None: no group."""
    if group is None:
        return
    valid_groups = list(system.groups) + ["all"]
    if group not in valid_groups:
        raise ValueError(f"unknown {system.id} group {group!r}; valid: {', '.join(valid_groups)}")
    if instances is not None:
        raise ValueError("give either instances (--terrains) or --group, not both")


def plan_specs(system: Any, *, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
               group: str | None = None, seeds: int = 1, overrides: Mapping[str, Any] | None = None) -> list[TrialSpec]:
    """Trial specs of ``system`` for (methods x instances x seeds), seed-major.

    ``methods=["all"]`` means every method; ``instances`` and ``group`` are exclusive; with
    neither, the system's ``default_group``. Only pairs the system says apply
    (:meth:`~terrabench.systems.base.System.applies`) are planned, each checked by its
    ``check_trial`` before any simulation; a request in which no pair applies is an error naming
    the methods that do.
    """
    if not isinstance(seeds, int) or seeds < 1:
        raise ValueError(f"seeds must be an integer >= 1, got {seeds!r}")
    known = system.methods()
    if isinstance(methods, (list, tuple)) and list(methods) == ["all"]:
        mids = list(known)
    else:
        mids = split_ids(methods, f"{system.id} method(s)", list(known)) or system.default_methods()
    check_group(system, group, instances)
    if instances is not None:
        check_id_list(instances, f"{system.id} instance(s)", lambda: system.instances(None), system.id)
        chosen = system.select_instances(instances)
    else:
        chosen = system.instances(group if group is not None else system.default_group)
    cfg = system.resolve_config(overrides)
    pairs = [(mid, inst) for inst in chosen for mid in mids if system.applies(mid, inst)]
    if not pairs:
        where = list(chosen) if len(chosen) <= 6 else list(chosen)[:6] + ["..."]
        valid = [m for m in known if any(system.applies(m, i) for i in chosen)]
        raise ValueError(f"no {system.id} method among {', '.join(mids)} applies to {', '.join(where)}; "
                         f"methods that apply there: {', '.join(valid) or 'none'}")
    out: list[TrialSpec] = []
    planned: list[tuple[str, str, dict[str, Any], range]] = []
    for mid, inst in pairs:
        system.check_trial(mid, inst, cfg)
        c = system.trial_config(mid, inst, cfg)
        planned.append((mid, inst, c, system.seeds_for(mid, inst, c, seeds)))
    for seed in range(seeds):
        for mid, inst, c, ss in planned:
            if seed in ss:
                out.append(TrialSpec(system.id, system.scenario(mid, inst), mid, inst, seed, c))
    return out


def plan_variations(system: Any, *, vary: Mapping[str, Sequence[Any]], overrides: Mapping[str, Any] | None = None,
                    **request: Any) -> list[TrialSpec]:
    """Trial specs of one request under every combination of ``vary`` (key -> values; the
    cartesian product, each combination on top of ``overrides``).

    ``request`` is :meth:`~terrabench.systems.base.System.plan`'s (methods, instances, group,
    seeds). Every combination is planned, so every value is checked against its field's range,
    before any trial runs; a key both set and varied is bad input. A trial two combinations plan
    alike (a method that does not read the varied section) is planned once. Seed-major: an
    interrupted run holds every combination's first seeds.
    """
    import itertools

    overrides = dict(overrides or {})
    both = sorted(set(vary) & set(overrides))
    if both:
        raise ValueError(f"{', '.join(both)} is both set (--set) and varied (--vary); give it in one of them")
    keys = list(vary)
    combos = [dict(zip(keys, values)) for values in itertools.product(*(vary[k] for k in keys))]
    planned: list[tuple[int, int, TrialSpec]] = []
    seen: set[str] = set()
    for ci, combo in enumerate(combos):
        try:
            specs = system.plan(overrides={**overrides, **combo}, **request)
        except ValueError as exc:
            where = ", ".join(f"{k}={v!r}" for k, v in combo.items())
            raise ValueError(f"with {where}: {exc}") from None
        for si, spec in enumerate(specs):
            if spec.key not in seen:
                seen.add(spec.key)
                planned.append((spec.seed, ci * len(specs) + si, spec))
    for key in keys:  # a setting no planned trial stores cannot vary anything: say so, do not run copies
        section = key.split(".")[0]
        if not any(section in spec.config for _, _, spec in planned):
            read = sorted({k for _, _, spec in planned for k in spec.config})
            raise ValueError(f"--vary {key}: no planned trial reads it (the methods' configs hold "
                             f"{', '.join(read)}); vary a setting of those sections")
    planned.sort(key=lambda t: (t[0], t[1]))
    return [p[2] for p in planned]
