"""Config variants of stored trials: so no report line mixes two configs.

A *variant* is a method under one set of user settings: the stored config's difference from the
config this version plans for the same (method, instance) with no overrides. Trials of one
method on different instances usually store different configs (the instance fixes some of them,
e.g. a beam's stiffness), yet belong to the same variant; a run made with ``--set key=value``
differs from the plan in ``key`` and is its own variant, labelled by the settings that tell the
method's variants apart (``"CLM (arm.press_force=40)"``). A method with one variant keeps its plain
label. Rows whose (method, instance) this version cannot plan any more are keyed by their config
hash.

Usage in a report::

    variants = find_variants(rows, default_config=Defaults(system))
    for v in variants:
        rs = v.rows_of(rows)      # that variant's trials
        ... one table line labelled v.label ...
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping, Sequence

from terrabench.benchmark.trial import canonical_json

if TYPE_CHECKING:
    from terrabench.systems.base import System

_ABSENT = "<absent>"


def flatten(cfg: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested config dict -> ``{"protocol.timeout": 2.0, ...}``."""
    out: dict[str, Any] = {}
    for k, v in cfg.items():
        if isinstance(v, dict):
            out.update(flatten(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


class Defaults:
    """``(method, instance) -> config dict`` that ``system`` plans with no overrides (cached; None
    when this version cannot plan the pair, e.g. a method since removed)."""

    def __init__(self, system: System) -> None:
        self.system = system
        self._cache: dict[tuple[str, str], dict[str, Any] | None] = {}

    def __call__(self, method: str, instance: str) -> dict[str, Any] | None:
        key = (method, instance)
        if key not in self._cache:
            try:
                specs = self.system.plan(methods=[method], instances=[instance])
            except ValueError:
                specs = []
            match = [s for s in specs if s.instance == instance and s.method == method]
            self._cache[key] = dict(match[0].config) if match else None
        return self._cache[key]


@dataclass(frozen=True)
class Variant:
    """One report line: a method under one set of settings.

    Attributes:
        id: the method id when the method has one variant in the rows, else ``"method@xxxxxxxx"``
            (8 hex digits of its settings).
        method: method id.
        label: the method's label, plus the settings that differ between its variants.
        diff: dotted key -> value where this variant's configs differ from the planned defaults
            (``{}`` for a default run).
        config_hash: the most common config hash of its trials (for tables and links).
        config: one stored config of the variant (the first trial's).
        hashes: every config hash of its trials.
    """

    id: str
    method: str
    label: str
    diff: Mapping[str, Any]
    config_hash: str
    config: Mapping[str, Any]
    hashes: tuple[str, ...] = field(default=())

    @property
    def is_default(self) -> bool:
        return not self.diff

    def rows_of(self, rows: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
        """The rows of this variant (by method and config hash)."""
        hs = set(self.hashes)
        return [r for r in rows if r["method"] == self.method and r["config_hash"] in hs]


def settings_diff(config: Mapping[str, Any], default: Mapping[str, Any] | None) -> dict[str, Any]:
    """Flattened ``config`` keys whose value differs from ``default`` (a key missing on one side
    counts; its value is then ``"<absent>"`` when missing from ``config``)."""
    flat, base = flatten(dict(config)), flatten(dict(default or {}))
    return {k: flat.get(k, _ABSENT) for k in sorted(set(flat) | set(base))
            if canonical_json(flat.get(k)) != canonical_json(base.get(k))}


def _hash8(diff: Mapping[str, Any]) -> str:
    import hashlib

    return hashlib.sha256(canonical_json(dict(diff)).encode()).hexdigest()[:8]


def find_variants(rows: Sequence[dict[str, Any]], *,
                  default_config: Callable[[str, str], Mapping[str, Any] | None] | None = None,
                  order: Sequence[str] = (), label: Callable[[str], str] | None = None,
                  describe: Callable[[str, Any], str] | None = None, key_order: Callable[[str], Any] | None = None,
                  most: int = 3) -> list[Variant]:
    """The variants of ``rows`` (each row: ``method``, ``instance``, ``config_hash``, ``config``).

    Args:
        default_config: ``(method, instance) -> planned config`` (e.g. :class:`Defaults`); None:
            every config hash is its own variant.
        order: method ids in report order (others follow, sorted).
        label: method id -> its display name (default: the id).
        describe: ``(key, value) -> text`` of one setting in a label (default ``key=value``).
        key_order: sort key of setting names in a label (default: alphabetical).
        most: at most this many settings in a label, then ``+N more``.

    Returns:
        Methods in ``order``; within a method the default variant first, then by trial count, then
        by config hash.
    """
    label = label or (lambda m: m)
    describe = describe or (lambda k, v: f"{k}={v}")
    groups: dict[str, dict[str, dict[str, Any]]] = {}  # method -> variant key -> info
    for r in rows:
        m = r["method"]
        default = default_config(m, r.get("instance", "")) if default_config is not None else None
        if default is None:
            diff, vkey = {"config_hash": r["config_hash"]}, "hash:" + r["config_hash"]
        else:
            diff = settings_diff(r["config"], default)
            vkey = canonical_json(diff)
        g = groups.setdefault(m, {}).setdefault(vkey, {"diff": diff, "n": 0, "hashes": {}, "config": r["config"],
                                                       "flat": flatten(dict(r["config"]))})
        g["n"] += 1
        g["hashes"][r["config_hash"]] = g["hashes"].get(r["config_hash"], 0) + 1
    rank = {m: i for i, m in enumerate(order)}
    out: list[Variant] = []
    for m in sorted(groups, key=lambda m: (rank.get(m, len(rank)), m)):
        vs = sorted(groups[m].items(), key=lambda kv: (bool(kv[1]["diff"]), -kv[1]["n"], min(kv[1]["hashes"])))
        base = label(m)
        if len(vs) == 1:
            labels = [base]
        else:
            keys = sorted({k for _, g in vs for k in g["diff"]}, key=key_order or (lambda k: k))
            differing = [k for k in keys if len({canonical_json(g["diff"].get(k, _ABSENT)) for _, g in vs}) > 1]
            # a section only one variant reads differs by absence: name the settings every variant
            # has, when they tell the variants apart
            shared = [k for k in differing if all(k in g["flat"] for _, g in vs)]
            if shared and len({tuple(canonical_json(g["flat"][k]) for k in shared) for _, g in vs}) == len(vs):
                differing = shared

            labels = [_label(base, g, differing, describe, most) for _, g in vs]
            if len(set(labels)) < len(labels):  # the shown keys did not tell them apart
                labels = [f"{lb} [{_hash8(g['diff'])}]" for lb, (_, g) in zip(labels, vs)]
        for lb, (_, g) in zip(labels, vs):
            hashes = tuple(sorted(g["hashes"], key=lambda h: (-g["hashes"][h], h)))
            vid = m if len(vs) == 1 else f"{m}@{_hash8(g['diff'])}"
            out.append(Variant(vid, m, lb, dict(g["diff"]), hashes[0], g["config"], hashes))
    return out


def _label(base: str, g: dict[str, Any], keys: Sequence[str], describe: Callable[[str, Any], str],
           most: int) -> str:
    """``"CLM (arm.press_force=40, +2 more)"``: the method's label and its values of ``keys``."""
    vals = [describe(k, g["diff"].get(k, g["flat"].get(k, "default"))) for k in keys[:most]]
    if len(keys) > most:
        vals.append(f"+{len(keys) - most} more")
    return f"{base} ({', '.join(vals)})" if vals else f"{base} (defaults)"


def tag_rows(rows: Sequence[dict[str, Any]], variants: Sequence[Variant]) -> list[dict[str, Any]]:
    """Copies of ``rows`` with ``variant`` (id) and ``label`` of their variant added."""
    of = {(v.method, h): v for v in variants for h in v.hashes}
    out = []
    for r in rows:
        v = of.get((r["method"], r["config_hash"]))
        if v is not None:
            out.append({**r, "variant": v.id, "label": v.label})
    return out


@dataclass(frozen=True)
class SettingsGroup:
    """Rows of every method run under one set of settings (a report section per group).

    Attributes:
        label: ``"defaults"`` or the settings, e.g. ``"arm.press_force=40"``.
        diff: dotted key -> value where these rows differ from the planned defaults.
        slug: ``""`` for the defaults, else a short file-name suffix (``"_v1a2b3c4d"``).
        rows: the rows.
    """

    label: str
    diff: Mapping[str, Any]
    slug: str
    rows: tuple[dict[str, Any], ...]


def settings_groups(rows: Sequence[dict[str, Any]], default_config: Callable[[str, str], Mapping[str, Any] | None],
                    *, ignore: Sequence[str] = (), describe: Callable[[str, Any], str] | None = None,
                    most: int = 4) -> list[SettingsGroup]:
    """Split ``rows`` by their settings (the config's difference from the planned defaults for the
    row's method and instance), whatever the method: a report that puts methods side by side
    shows one section per group, so no section mixes two configs. Keys in ``ignore`` (a setting
    the report already compares side by side) do not split. Defaults first, then by size."""
    describe = describe or (lambda k, v: f"{k}={v}")
    by: dict[str, dict[str, Any]] = {}
    for r in rows:
        default = default_config(r["method"], r.get("instance", ""))
        diff = ({"config_hash": r["config_hash"]} if default is None else
                {k: v for k, v in settings_diff(r["config"], default).items() if k not in ignore})
        g = by.setdefault(canonical_json(diff), {"diff": diff, "rows": []})
        g["rows"].append(r)
    out = []
    for _, g in sorted(by.items(), key=lambda kv: (bool(kv[1]["diff"]), -len(kv[1]["rows"]), kv[0])):
        diff = g["diff"]
        if not diff:
            label, slug = "defaults", ""
        else:
            keys = sorted(diff)
            label = ", ".join(describe(k, diff[k]) for k in keys[:most]) + (
                f", +{len(keys) - most} more" if len(keys) > most else "")
            slug = f"_v{_hash8(diff)}"
        out.append(SettingsGroup(label, dict(diff), slug, tuple(g["rows"])))
    return out
