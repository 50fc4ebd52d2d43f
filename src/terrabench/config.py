"""Frozen-dataclass config helpers: declared ranges, to/from plain dicts, dotted overrides.

Configs are nested frozen dataclasses; a run stores ``to_dict(cfg)`` with every trial, and
``from_dict`` rebuilds the identical object in a worker. ``override(cfg, {"physics.timestep":
0.0025})`` returns a new config (``dataclasses.replace`` all the way down), never mutating.

Every field declares what it may hold where it is declared, with :func:`param`::

    @dataclass(frozen=True)
    class ChainConfig:
        n_units: int = param(5, ge=2, doc="number of wheeled units")
        body_mass: float = param(0.8, gt=0, unit="kg", doc="mass of one unit's body")

The range and the one-line meaning live in the field's metadata (:func:`spec_of`), so
:func:`validate` (run by :func:`override` and :func:`from_dict`), ``terrabench config SYSTEM``
and the generic tests all read the same declaration. Every error is one line naming the dotted
key, the bad value and what is valid (:class:`ConfigError`, a ``ValueError``).

What must hold *between* fields is declared next to them, on the config that holds all of them
(a relation spanning sections on the root), as a ``relations`` class attribute of
:class:`Relation` objects (:func:`le`, :func:`lt`, :func:`ge`, :func:`ordered`,
:func:`multiple_of`, :func:`relation`) naming the fields by dotted keys relative to that config::

    @dataclass(frozen=True)
    class MRSConfig:
        relations: ClassVar[tuple[Relation, ...]] = (le("stiffness.k_low", "stiffness.k_high"),)
        ...

:func:`validate` checks them after every field's own range, once all overrides are applied (so
the order of ``--set`` items does not matter), and a broken one is one line naming every field
and its value: ``stiffness.k_low=150 must be <= stiffness.k_high=100`` (:class:`RelationError`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import typing
from collections.abc import Callable, Iterator, Mapping
from typing import Any, TypeVar

import yaml

T = TypeVar("T")

_META = "terrabench.param"


@dataclasses.dataclass(frozen=True)
class Param:
    """What one config field may hold (stored in the dataclass field's metadata).

    Attributes:
        ge, gt, le, lt: bounds on a number (or on every number of a list field); None = open.
        unit: the unit shown beside the range (``"m"``, ``"s"``, ``"kg"``...).
        doc: one line saying what the field means.
        choices: the only values allowed (strings or numbers), None = any.
        length: exact number of entries of a list field, None = any.
        optional: None (null) is also allowed (it means "off"; the field's doc says what).
    """

    ge: float | None = None
    gt: float | None = None
    le: float | None = None
    lt: float | None = None
    unit: str = ""
    doc: str = ""
    choices: tuple[Any, ...] | None = None
    length: int | None = None
    optional: bool = False

    def bounds_text(self) -> str:
        """The numeric range alone, e.g. ``> 0``, ``in [0, 1]``, ``>= 1``; '' if unbounded."""
        lo = hi = None
        if self.ge is not None or self.gt is not None:
            lo = (f"[{_num(self.ge)}", self.ge) if self.ge is not None else (f"({_num(self.gt)}", self.gt)
        if self.le is not None or self.lt is not None:
            hi = (f"{_num(self.le)}]", self.le) if self.le is not None else (f"{_num(self.lt)})", self.lt)
        if lo and hi:
            return f"in {lo[0]}, {hi[0]}"
        if lo:
            return (">= " if self.ge is not None else "> ") + _num(lo[1])
        if hi:
            return ("<= " if self.le is not None else "< ") + _num(hi[1])
        return ""

    @property
    def has_range(self) -> bool:
        return self.choices is not None or any(b is not None for b in (self.ge, self.gt, self.le, self.lt))

    def describe(self, default: Any = None) -> str:
        """What is valid, in words: ``an integer >= 2``, ``one of euler, rk4``, ``3 numbers in [0, 1]``."""
        if self.choices is not None:
            return "one of " + ", ".join(str(c) for c in self.choices)
        rng = self.bounds_text()
        unit = f" ({self.unit})" if self.unit else ""
        if isinstance(default, tuple):
            count = f"{self.length} " if self.length is not None else "a list of "
            kind = "integers" if default and all(_is_int(v) for v in default) else "numbers"
            if not default or all(_is_number(v) for v in default):
                return f"{count}{kind}" + (f" each {rng}" if rng else "") + unit
            return f"{count}entries" + unit
        if isinstance(default, bool):
            return "true or false"
        kind = "an integer" if _is_int(default) else "a number" if _is_number(default) or (
            default is None and self.has_range) else "a value"
        return kind + (f" {rng}" if rng else "") + unit


def _num(x: float) -> str:
    for k, name in ((1, "pi"), (0.5, "pi/2")):  # angle bounds read as what they are
        if abs(abs(x) - k * math.pi) < 1e-12:
            return ("-" if x < 0 else "") + name
    return repr(int(x)) if float(x).is_integer() and abs(x) < 1e15 else repr(x)


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _is_int(v: Any) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


class ConfigError(ValueError):
    """A bad config value: one line naming the dotted key, the value and what is valid."""

    def __init__(self, key: str, value: Any, valid: str, *, problem: str = "is invalid") -> None:
        self.key, self.value, self.valid, self.problem = key, value, valid, problem
        super().__init__(f"config key {key!r} = {_show(value)} {problem}; valid: {valid}")

    def under(self, prefix: str) -> ConfigError:
        """The same error with ``prefix.`` in front of its key (a nested section's check)."""
        return ConfigError(f"{prefix}.{self.key}" if prefix else self.key, self.value, self.valid, problem=self.problem)


def _show(value: Any) -> str:
    return repr(list(value)) if isinstance(value, tuple) else repr(value)


class RelationError(ConfigError):
    """A relation between config fields that does not hold: one line naming each field and its value,
    e.g. ``stiffness.k_low=150 must be <= stiffness.k_high=100``."""

    def __init__(self, keys: tuple[str, ...], values: tuple[Any, ...], says: str, why: str = "") -> None:
        self.keys, self.values, self.says, self.why = tuple(keys), tuple(values), says, why
        self.key, self.value, self.problem = self.keys[0], self.values[0], "breaks a relation"
        self.valid = says.format(*self.keys)
        text = says.format(*(f"{k}={_brief(v)}" for k, v in zip(self.keys, self.values)))
        ValueError.__init__(self, text + (f" ({why})" if why else ""))

    def under(self, prefix: str) -> RelationError:
        keys = tuple(f"{prefix}.{k}" for k in self.keys) if prefix else self.keys
        return RelationError(keys, self.values, self.says, self.why)


def _brief(v: Any) -> str:
    """A value as a user types it after ``--set KEY=``: 150 (not 150.0), [1.4, -1.2], a string bare."""
    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(_brief(x) for x in v) + "]"
    if isinstance(v, float) and v.is_integer() and abs(v) < 1e15:
        return repr(int(v))
    return v if isinstance(v, str) else repr(v)


@dataclasses.dataclass(frozen=True)
class Relation:
    """What must hold between fields of one config (declared in its ``relations`` class attribute).

    Attributes:
        keys: the fields, as dotted keys relative to the config declaring the relation.
        holds: their values -> True when they are consistent (not called while any is None, an
            optional field that is off).
        says: what must hold, ``{0}``, ``{1}``... standing for the fields (``"{0} must be <= {1}"``);
            in an error each reads ``key=value``.
        why: optional reason shown after it in brackets.
        detail: optional values -> a line on what *is* valid for these values (a bound computed from
            other fields, e.g. what a linkage reaches), added to ``why`` in an error.
    """

    keys: tuple[str, ...]
    holds: Callable[..., bool]
    says: str
    why: str = ""
    detail: Callable[..., str] | None = None

    def text(self, prefix: str = "") -> str:
        """The relation in words with the keys alone (``terrabench config SYSTEM``)."""
        return self.says.format(*(f"{prefix}{k}" for k in self.keys)) + (f" ({self.why})" if self.why else "")

    def check(self, cfg: Any) -> None:
        """RelationError (keys relative to ``cfg``) unless the relation holds on ``cfg``."""
        values = tuple(_get(cfg, k) for k in self.keys)
        if any(v is None for v in values):
            return
        try:
            ok = bool(self.holds(*values))
        except (TypeError, ValueError, ArithmeticError, IndexError):
            ok = False
        if not ok:
            why = self.why
            if self.detail is not None:
                why = f"{why}; {self.detail(*values)}" if why else self.detail(*values)
            raise RelationError(self.keys, values, self.says, why)


def _get(cfg: Any, key: str) -> Any:
    for part in key.split("."):
        cfg = getattr(cfg, part)
    return cfg


def relation(keys: typing.Sequence[str], holds: Callable[..., bool], says: str, why: str = "",
             detail: Callable[..., str] | None = None) -> Relation:
    """A relation between ``keys`` (see :class:`Relation`)."""
    return Relation(tuple(keys), holds, says, why, detail)


def le(a: str, b: str, why: str = "") -> Relation:
    """``a <= b``."""
    return Relation((a, b), lambda x, y: x <= y, "{0} must be <= {1}", why)


def lt(a: str, b: str, why: str = "") -> Relation:
    """``a < b``."""
    return Relation((a, b), lambda x, y: x < y, "{0} must be < {1}", why)


def ge(a: str, b: str, why: str = "") -> Relation:
    """``a >= b``."""
    return Relation((a, b), lambda x, y: x >= y, "{0} must be >= {1}", why)


def ordered(key: str, strict: bool = False, why: str = "") -> Relation:
    """A ``(lower, upper, ...)`` list field whose first entry must not exceed its second."""
    if strict:
        return Relation((key,), lambda v: v[0] < v[1], "{0} must be (lower, upper) with lower < upper", why)
    return Relation((key,), lambda v: v[0] <= v[1], "{0} must be (lower, upper) with lower <= upper", why)


def multiple_of(period: str, step: str, why: str = "") -> Relation:
    """``period`` is a whole number (>= 1) of ``step`` (e.g. a control period of physics steps)."""

    def holds(p: float, s: float) -> bool:
        ratio = p / s
        return round(ratio) >= 1 and abs(ratio - round(ratio)) <= 1e-6

    return Relation((period, step), holds, "{0} must be a whole number of physics steps ({1})", why)


def clock_relations(check: str = "protocol.check_period", control: str = "protocol.control_period",
                    log: str = "protocol.log_period", step: str = "physics.timestep") -> tuple[Relation, ...]:
    """The episode loop's clock, the same for every system (``sim.episode``): the control period
    is a whole number of physics steps, and the slow check and the stored series run at control
    instants, so neither is faster than the controller."""
    return (
        multiple_of(control, step),
        ge(check, control, "checks run at control instants"),
        ge(log, control, "rows are stored at control instants"),
    )


def relations_of(cfg: Any, prefix: str = "") -> list[tuple[str, Relation]]:
    """Every (prefix, relation) declared by ``cfg`` and its nested sections (prefix ends in '.')."""
    out = [(prefix, r) for r in getattr(type(cfg), "relations", ())]
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            out.extend(relations_of(v, f"{prefix}{f.name}."))
    return out


def check_relations(cfg: Any, prefix: str = "") -> None:
    """RelationError (full dotted keys) for the first declared relation of ``cfg`` or its sections
    that does not hold; the sections' own before the ones spanning them."""
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            check_relations(v, f"{prefix}.{f.name}" if prefix else f.name)
    for r in getattr(type(cfg), "relations", ()):
        try:
            r.check(cfg)
        except RelationError as e:
            raise e.under(prefix) from None


def param(default: Any = dataclasses.MISSING, *, ge: float | None = None, gt: float | None = None,
          le: float | None = None, lt: float | None = None, unit: str = "", doc: str = "",
          choices: typing.Iterable[Any] | None = None, length: int | None = None,
          default_factory: Any = dataclasses.MISSING, optional: bool = False) -> Any:
    """A dataclass ``field()`` that declares its valid range and one-line meaning.

    Numbers must be finite and inside the bounds (``ge``/``gt``/``le``/``lt``); a list field's
    bounds hold for every entry and ``length`` fixes its number of entries; ``choices`` lists the
    only values allowed; ``optional`` also allows None (a field whose default is None is optional
    anyway). Checked by :func:`validate`; read back with :func:`spec_of`.
    """
    if ge is not None and gt is not None or le is not None and lt is not None:
        raise TypeError("param: give at most one lower bound (ge or gt) and one upper bound (le or lt)")
    meta = {_META: Param(ge, gt, le, lt, unit, doc, tuple(choices) if choices is not None else None, length,
                         optional)}
    return dataclasses.field(default=default, default_factory=default_factory, metadata=meta)


def spec_of(f: dataclasses.Field) -> Param | None:
    """The :class:`Param` a field was declared with, or None for a plain field."""
    return f.metadata.get(_META)


def check_value(key: str, value: Any, spec: Param, default: Any = None) -> None:
    """ConfigError naming ``key`` unless ``value`` satisfies ``spec`` (``default`` gives the kind)."""
    if value is None and (default is None or spec.optional):  # an optional field set to null
        return

    def fail(problem: str) -> ConfigError:  # the message is built only for a bad value
        valid = spec.describe(default) + (", or null" if default is None or spec.optional else "")
        return ConfigError(key, value, valid, problem=problem)

    if spec.choices is not None:
        if not any(value == c and isinstance(value, bool) == isinstance(c, bool) for c in spec.choices):
            raise ConfigError(key, value, ", ".join(str(c) for c in spec.choices), problem="is unknown")
        return
    if isinstance(value, (tuple, list)):
        if spec.length is not None and len(value) != spec.length:
            raise fail(f"has {len(value)} entries")
        items = list(_flatten(value))
    else:
        if spec.length is not None:
            raise fail("is not a list")
        items = [value]
    numeric = None
    for v in items:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            if numeric is None:
                kind = default if default is not None else value
                numeric = _is_number(kind) or (isinstance(kind, (tuple, list)) and bool(kind) and
                                               all(_is_number(x) for x in _flatten(kind)))
            if numeric or spec.has_range:
                raise fail("is not a number")
            continue
        if not math.isfinite(v):
            raise fail("is not finite")
        if (spec.ge is not None and not v >= spec.ge) or (spec.gt is not None and not v > spec.gt) or \
                (spec.le is not None and not v <= spec.le) or (spec.lt is not None and not v < spec.lt):
            raise fail("is out of range")


def _flatten(v: Any) -> Iterator[Any]:
    for x in v:
        if isinstance(x, (tuple, list)):
            yield from _flatten(x)
        else:
            yield x


def check_fields(obj: Any) -> None:
    """Check ``obj``'s own declared fields (not nested sections): for a ``__post_init__``.

    The error names the field; :func:`override` / :func:`from_dict` put the section path in front.
    """
    for name, spec, default in _declared(type(obj)):
        check_value(name, getattr(obj, name), spec, default)


@functools.cache
def _declared(cls: type) -> tuple[tuple[str, Param, Any], ...]:
    """(name, spec, default) of every field of ``cls`` declared with :func:`param` (cached)."""
    return tuple((f.name, spec_of(f), _default(f)) for f in dataclasses.fields(cls) if spec_of(f) is not None)


def validate(cfg: Any, prefix: str = "") -> Any:
    """Check every declared field of ``cfg`` and its nested sections, then every declared
    relation between them (:func:`check_relations`); returns ``cfg``.

    Raises :class:`ConfigError` (a ValueError) naming the dotted key, the value and what is valid,
    or :class:`RelationError` naming every field of the broken relation and its value.
    """
    _validate_fields(cfg, prefix)
    check_relations(cfg, prefix)
    return cfg


def _validate_fields(cfg: Any, prefix: str = "") -> None:
    try:
        check_fields(cfg)
    except ConfigError as e:
        raise e.under(prefix) from None
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            _validate_fields(v, f"{prefix}.{f.name}" if prefix else f.name)


def _default(f: dataclasses.Field) -> Any:
    if f.default is not dataclasses.MISSING:
        return f.default
    if f.default_factory is not dataclasses.MISSING:  # type: ignore[misc]
        return f.default_factory()  # type: ignore[misc]
    return None


@dataclasses.dataclass(frozen=True)
class FieldInfo:
    """One settable key of a config (``terrabench config SYSTEM``)."""

    key: str
    default: Any
    type: str
    spec: Param | None

    @property
    def valid(self) -> str:
        return self.spec.describe(self.default) if self.spec is not None else ""

    @property
    def doc(self) -> str:
        return self.spec.doc if self.spec is not None else ""

    @property
    def unit(self) -> str:
        return self.spec.unit if self.spec is not None else ""


def fields_info(cfg: Any, prefix: str = "") -> list[FieldInfo]:
    """Every leaf key of the config instance ``cfg`` (dotted), its current value, type and spec."""
    out: list[FieldInfo] = []
    try:
        hints = typing.get_type_hints(type(cfg))
    except NameError:  # a class defined inside a function: fall back to the annotation text
        hints = {}
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            out.extend(fields_info(v, f"{prefix}{f.name}."))
            continue
        hint = hints.get(f.name, f.type if isinstance(f.type, str) else type(v))
        tname = hint if isinstance(hint, str) else getattr(hint, "__name__", None) or str(hint)
        if typing.get_origin(hint) is not None:
            tname = str(hint).replace("typing.", "")
        out.append(FieldInfo(prefix + f.name, v, tname, spec_of(f)))
    return out


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
    """Rebuild ``cls`` from :func:`to_dict` output and :func:`validate` it.

    Unknown keys raise ValueError naming the valid ones; missing keys take their defaults.
    """
    return validate(_build(cls, data, ""))


def _build(cls: type[T], data: Mapping[str, Any], prefix: str) -> T:
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = set(data) - names
    if unknown:
        where = f" in section {prefix[:-1]!r}" if prefix else ""
        raise ValueError(f"unknown {cls.__name__} field(s) {sorted(unknown)}{where}; valid: {sorted(names)}")
    kwargs = {}
    for name, value in data.items():
        hint = hints[name]
        if dataclasses.is_dataclass(hint) and isinstance(value, Mapping):
            value = _build(hint, value, f"{prefix}{name}.")
        elif isinstance(value, list):
            value = tuple(tuple(v) if isinstance(v, list) else v for v in value)
        kwargs[name] = value
    try:
        return cls(**kwargs)
    except ConfigError as exc:  # a __post_init__ check_fields(): put the section path in front
        raise exc.under(prefix[:-1]) from None
    except (TypeError, ArithmeticError) as exc:
        where = f"config section {prefix[:-1]!r}" if prefix else f"config {cls.__name__}"
        raise ValueError(f"{where} is invalid: {exc}") from None


def override(cfg: T, changes: Mapping[str, Any]) -> T:
    """Apply ``{"a.b.c": value}`` changes and :func:`validate` the result.

    An unknown path raises ValueError naming the valid keys; a value outside its declared range
    raises :class:`ConfigError` naming the dotted key, the value and what is valid.
    """
    for path, value in changes.items():
        cfg = _set(cfg, path.split("."), value, path)
    return validate(cfg)


def _set(obj: Any, parts: list[str], value: Any, full: str) -> Any:
    fields = {f.name: f for f in dataclasses.fields(obj)}
    head = parts[0]
    if head not in fields:
        raise ValueError(f"unknown config key {full!r} (at {head!r}); valid here: {', '.join(fields)}")
    current = getattr(obj, head)
    if len(parts) == 1:
        if dataclasses.is_dataclass(current):
            sub = ", ".join(f"{full}.{f.name}" for f in dataclasses.fields(current))
            raise ValueError(f"config key {full!r} is a section; set one of its fields: {sub}")
        value = _coerce(current, value, full)
        spec = spec_of(fields[head])
        if spec is not None:
            check_value(full, value, spec, _default(fields[head]))
        try:
            return dataclasses.replace(obj, **{head: value})
        except ConfigError as exc:  # another field of this section, checked in __post_init__
            raise exc.under(full.rsplit(".", 1)[0] if "." in full else "") from None
        except (TypeError, ArithmeticError, ValueError) as exc:
            raise ValueError(f"config key {full!r} = {_show(value)} is invalid: {exc}") from None
    if not dataclasses.is_dataclass(current):
        raise ValueError(f"config key {full!r}: {head!r} is a value, not a section")
    try:
        return dataclasses.replace(obj, **{head: _set(current, parts[1:], value, full)})
    except ConfigError:
        raise
    except (TypeError, ArithmeticError, ValueError) as exc:  # a cross-section check of obj
        if str(exc).startswith(("config key", "unknown config key")):
            raise
        raise ValueError(f"config key {full!r} = {_show(value)} is invalid: {exc}") from None


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
        out[key.strip()] = _yaml_value(raw, f"bad override {item!r}: the value {raw!r}",
                                       "a number, true/false, a string or a list like [1, 2]")
    return out


def _yaml_value(text: str, what: str, valid: str) -> Any:
    """``text`` parsed as YAML; a parse error is one line, ``what`` ... (the problem); valid: ``valid``
    (e.g. an unclosed list), not the parser's report."""
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise ValueError(f"{what} does not parse ({problem}); valid: {valid}") from None


def parse_variations(items: list[str]) -> dict[str, list[Any]]:
    """``["robot.roller_damping=0.02,5", "clm.pace=[0.1, 0.2]"]`` -> ``{key: [value, ...]}``.

    A key's values are written ``V1,V2,...`` or as a YAML list ``[V1, V2, ...]`` (a list-valued
    setting is one item in brackets: ``robot.arm_kp=[[800, 2500, 1500], [800, 2000, 1500]]``).
    A key given twice, a value given twice or fewer than two values is bad input (one line naming
    it); each value is checked against the field's range later, like ``--set``.
    """
    out: dict[str, list[Any]] = {}
    for item in items:
        key, sep, raw = item.partition("=")
        key = key.strip()
        if not sep or not key or not raw.strip():
            raise ValueError(f"bad variation {item!r}; expected KEY=V1,V2,..., e.g. robot.roller_damping=0.02,5")
        text = raw.strip()
        values = _yaml_value(text if text.startswith("[") else f"[{text}]", f"bad variation {item!r}: {raw!r}",
                             "values separated by commas (0.02,5) or a list ([0.02, 5])")
        if not isinstance(values, list):
            raise ValueError(f"bad variation {item!r}: expected a list of values, got {values!r}")
        if key in out:
            raise ValueError(f"variation key {key!r} given twice; give its values once: {key}=V1,V2,...")
        seen: list[str] = []
        for v in values:
            text_v = yaml.safe_dump(v, default_flow_style=True).strip()
            if text_v in seen:
                raise ValueError(f"variation {key!r} lists the value {v!r} twice")
            seen.append(text_v)
        if len(values) < 2:
            raise ValueError(f"variation {key!r} has {len(values)} value(s); a variation needs at least two "
                             f"(one value is --set {key}=VALUE)")
        out[key] = values
    return out
