"""Frozen-dataclass config helpers: to/from plain dicts and dotted (YAML-valued) overrides.

Configs are nested frozen dataclasses; a run stores ``to_dict(cfg)`` with every trial, and
``from_dict`` rebuilds the identical object in a worker. ``override(cfg, {"physics.timestep":
0.0025})`` returns a new config (``dataclasses.replace`` all the way down), never mutating.
"""

from __future__ import annotations

import dataclasses
import typing
from typing import Any, Mapping, TypeVar

import yaml

T = TypeVar("T")


def to_dict(cfg: Any) -> dict[str, Any]:
    """A nested dataclass as plain, JSON/YAML-serialisable values (tuples become lists)."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if dataclasses.is_dataclass(v):
            v = to_dict(v)
        elif isinstance(v, tuple):
            v = list(v)
        out[f.name] = v
    return out


def from_dict(cls: type[T], data: Mapping[str, Any]) -> T:
    """Rebuild ``cls`` from :func:`to_dict` output; unknown keys raise ValueError."""
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = set(data) - names
    if unknown:
        raise ValueError(f"unknown {cls.__name__} field(s) {sorted(unknown)}; valid: {sorted(names)}")
    kwargs = {}
    for name, value in data.items():
        hint = hints[name]
        if dataclasses.is_dataclass(hint) and isinstance(value, Mapping):
            value = from_dict(hint, value)
        elif isinstance(value, list):
            value = tuple(tuple(v) if isinstance(v, list) else v for v in value)
        kwargs[name] = value
    return cls(**kwargs)


def override(cfg: T, changes: Mapping[str, Any]) -> T:
    """Apply ``{"a.b.c": value}`` changes; an unknown path raises ValueError naming valid keys."""
    for path, value in changes.items():
        cfg = _set(cfg, path.split("."), value, path)
    return cfg


def _set(obj: Any, parts: list[str], value: Any, full: str) -> Any:
    names = [f.name for f in dataclasses.fields(obj)]
    head = parts[0]
    if head not in names:
        raise ValueError(f"unknown config key {full!r} (at {head!r}); valid here: {', '.join(names)}")
    if len(parts) == 1:
        current = getattr(obj, head)
        if isinstance(current, bool):
            value = value if isinstance(value, bool) else str(value).lower() in ("1", "true", "yes")
        elif isinstance(current, (int, float)) and not isinstance(value, (int, float)):
            try:
                value = type(current)(value)
            except ValueError:
                raise ValueError(f"config key {full!r} expects a number, got {value!r}") from None
        elif isinstance(current, tuple) and isinstance(value, list):
            value = tuple(value)
        return dataclasses.replace(obj, **{head: value})
    return dataclasses.replace(obj, **{head: _set(getattr(obj, head), parts[1:], value, full)})


def parse_overrides(items: list[str]) -> dict[str, Any]:
    """``["physics.timestep=0.0025", ...]`` -> dict with YAML-parsed values."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, raw = item.partition("=")
        if not sep or not key:
            raise ValueError(f"bad override {item!r}; expected KEY=VALUE, e.g. physics.timestep=0.0025")
        out[key.strip()] = yaml.safe_load(raw)
    return out
