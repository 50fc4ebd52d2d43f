"""Frozen-dataclass config helpers: to/from plain dicts and dotted (YAML-valued) overrides.

Configs are nested frozen dataclasses; a run stores ``to_dict(cfg)`` with every trial, and
``from_dict`` rebuilds the identical object in a worker. ``override(cfg, {"physics.timestep":
0.0025})`` returns a new config (``dataclasses.replace`` all the way down), never mutating.
"""

from __future__ import annotations

import dataclasses
import math
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
            v = _listify(v)
        out[f.name] = v
    return out


def _listify(v: Any) -> Any:
    return [_listify(x) for x in v] if isinstance(v, (tuple, list)) else v


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
    current = getattr(obj, head)
    if len(parts) == 1:
        if dataclasses.is_dataclass(current):
            sub = ", ".join(f"{full}.{f.name}" for f in dataclasses.fields(current))
            raise ValueError(f"config key {full!r} is a section; set one of its fields: {sub}")
        value = _coerce(current, value, full)
        try:
            return dataclasses.replace(obj, **{head: value})
        except (TypeError, ArithmeticError) as exc:
            raise ValueError(f"config key {full!r} = {value!r} is invalid: {exc}") from None
    if not dataclasses.is_dataclass(current):
        raise ValueError(f"config key {full!r}: {head!r} is a value, not a section")
    return dataclasses.replace(obj, **{head: _set(current, parts[1:], value, full)})


def _coerce(current: Any, value: Any, full: str) -> Any:
    """``value`` as the type of the field's current value; ValueError naming the key otherwise."""
    if isinstance(current, bool):
        if isinstance(value, bool):
            return value
        text = str(value).lower()
        if text in ("1", "true", "yes", "on"):
            return True
        if text in ("0", "false", "no", "off"):
            return False
        raise ValueError(f"config key {full!r} expects true or false, got {value!r}")
    if isinstance(current, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise ValueError(f"config key {full!r} expects a number, got {value!r}")
        kind = "an integer" if isinstance(current, int) else "a number"
        try:
            number = float(value)
        except ValueError:
            raise ValueError(f"config key {full!r} expects {kind}, got {value!r}") from None
        if isinstance(current, int):
            if not number.is_integer():
                raise ValueError(f"config key {full!r} expects an integer, got {value!r}")
            return int(number)
        if not math.isfinite(number):
            raise ValueError(f"config key {full!r} expects a finite number, got {value!r}")
        return number
    if isinstance(current, str):
        if not isinstance(value, (str, int, float)) or isinstance(value, bool):
            raise ValueError(f"config key {full!r} expects a string, got {value!r}")
        return str(value)
    if isinstance(current, tuple):
        if not isinstance(value, (list, tuple)):
            raise ValueError(f"config key {full!r} expects a list like {list(current)!r}, got {value!r}")
        if current and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in current):
            try:
                return tuple(float(v) for v in value)
            except (TypeError, ValueError):
                raise ValueError(f"config key {full!r} expects a list of numbers, got {value!r}") from None
        return tuple(value)
    return value


def parse_overrides(items: list[str]) -> dict[str, Any]:
    """``["physics.timestep=0.0025", ...]`` -> dict with YAML-parsed values."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, raw = item.partition("=")
        if not sep or not key:
            raise ValueError(f"bad override {item!r}; expected KEY=VALUE, e.g. physics.timestep=0.0025")
        out[key.strip()] = yaml.safe_load(raw)
    return out
