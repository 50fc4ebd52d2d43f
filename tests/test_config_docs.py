"""Each config field is documented once, where it is declared: ``param(..., doc="...")``.

For every registered system, every leaf field of its config tree (the root ``config_cls`` and
every nested dataclass section) carries a non-empty ``doc``, and no config dataclass repeats
its fields in an ``Attributes:`` block of its docstring (the copy that drifts from the code;
``terrabench config SYSTEM`` shows the ``doc`` text).
"""

from __future__ import annotations

import dataclasses
import functools
import re
import typing

import pytest

from terrabench.catalog import populate, system
from terrabench.config import param, spec_of

SYSTEMS = [r.id for r in populate().entries("system")]
ATTRIBUTES = re.compile(r"^\s*Attributes:\s*$", re.MULTILINE)


def _name(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def _sections(hint: typing.Any, value: typing.Any) -> list[type]:
    """The dataclass types a field holds: from its default value and from its annotation."""
    found = []
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        found.append(type(value))
    stack = [hint]
    while stack:
        h = stack.pop()
        if isinstance(h, type) and dataclasses.is_dataclass(h):
            found.append(h)
        stack.extend(typing.get_args(h))
    return list(dict.fromkeys(found))


def config_tree(root: type, instance: typing.Any = None) -> list[type]:
    """``root`` and every dataclass section below it, each once, in the order met."""
    out: dict[type, None] = {}

    def walk(cls: type, obj: typing.Any) -> None:
        if cls in out:
            return
        out[cls] = None
        hints = typing.get_type_hints(cls)
        for f in dataclasses.fields(cls):
            value = getattr(obj, f.name, None) if obj is not None else _default(f)
            for sub in _sections(hints.get(f.name), value):
                walk(sub, value if isinstance(value, sub) else None)

    walk(root, instance)
    return list(out)


def _default(f: dataclasses.Field) -> typing.Any:
    if f.default is not dataclasses.MISSING:
        return f.default
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    return None


def _is_section(cls: type, f: dataclasses.Field, value: typing.Any) -> bool:
    return bool(_sections(typing.get_type_hints(cls).get(f.name), value))


def problems_of(root: type, instance: typing.Any = None) -> list[str]:
    """One line per config class of the tree with an ``Attributes:`` block and per leaf field
    without a ``param(doc=...)``, each naming the class and the field."""
    problems = []
    for cls in config_tree(root, instance):
        if ATTRIBUTES.search(cls.__doc__ or ""):
            problems.append(f"{_name(cls)}: its docstring has an 'Attributes:' block; move what it says into "
                            "each field's param(doc=...) and delete the block")
        for f in dataclasses.fields(cls):
            if _is_section(cls, f, _default(f)):
                continue  # a nested section: its own fields are checked
            spec = spec_of(f)
            if spec is None:
                problems.append(f"{_name(cls)}.{f.name}: not declared with param(); declare it with "
                                "param(..., doc='what it means')")
            elif not spec.doc.strip():
                problems.append(f"{_name(cls)}.{f.name}: param() has no doc; give doc='what it means'")
    return problems


@pytest.mark.parametrize("sid", SYSTEMS)
def test_every_config_field_has_a_doc_and_no_docstring_repeats_them(sid):
    sysobj = system(sid)
    tree = config_tree(sysobj.config_cls, sysobj.base_config())
    assert tree and tree[0] is sysobj.config_cls
    problems = problems_of(sysobj.config_cls, sysobj.base_config())
    assert not problems, f"{sid}: config fields without their one documentation:\n" + "\n".join(problems)


@dataclasses.dataclass(frozen=True)
class _Leaf:
    x: float = param(1.0, doc="x")


@dataclasses.dataclass(frozen=True)
class _Other:
    """A section repeating its fields.

    Attributes:
        y: what y means.
    """

    y: float = param(2.0)
    z: float = 3.0


@dataclasses.dataclass(frozen=True)
class _Root:
    leaf: _Leaf = dataclasses.field(default_factory=_Leaf)
    other: _Other | None = None
    w: int = param(1, doc="w")


def test_the_walk_finds_every_section_and_names_class_and_field():
    """A section given by its default value, one only behind an optional annotation; the
    problems name the class and the field."""
    assert config_tree(_Root) == [_Root, _Leaf, _Other]
    problems = problems_of(_Root)
    name = f"{__name__}._Other"
    assert len(problems) == 3, problems
    assert problems[0].startswith(f"{name}: its docstring has an 'Attributes:' block")
    assert problems[1].startswith(f"{name}.y: param() has no doc")
    assert problems[2].startswith(f"{name}.z: not declared with param()")


@functools.lru_cache(maxsize=1)
def _package_sources() -> tuple[str, ...]:
    """Every module's text, read once for all the systems' runs."""
    import pathlib

    import terrabench

    root = pathlib.Path(terrabench.__file__).parent
    return tuple(p.read_text() for p in sorted(root.rglob("*.py")))


def unread_fields(root: type, instance: typing.Any, sources: typing.Sequence[str]) -> list[str]:
    """Leaf fields of the tree whose name the package never reads: no attribute access
    ``.name`` and no string literal ``"name"`` (a getattr, a ``--set`` key built from parts)
    anywhere but a declaration ``name: ... = param(``. By name, so a field sharing its name with a
    read one of another section passes; what it catches is a knob nothing reads at all."""
    out = []
    for cls in config_tree(root, instance):
        for f in dataclasses.fields(cls):
            if _is_section(cls, f, _default(f)):
                continue
            read = re.compile(rf"\.{f.name}\b|[\"']{f.name}[\"']")
            if not any(read.search(src) for src in sources):
                out.append(f"{_name(cls)}.{f.name}")
    return out


@pytest.mark.parametrize("sid", SYSTEMS)
def test_every_config_field_is_read_by_the_package(sid):
    """A field a user can ``--set`` must reach something: three were declared and read by nothing
    (srwmr ``scales.wb_min``, octopus ``robot.d3``, the map's ``protocol.success_share``)."""
    sysobj = system(sid)
    unread = unread_fields(sysobj.config_cls, sysobj.base_config(), _package_sources())
    assert not unread, f"{sid}: config fields nothing reads (remove them or use them): {unread}"


def test_an_unread_field_is_found():
    @dataclasses.dataclass(frozen=True)
    class _Unread:
        zz_never_read_anywhere: float = param(1.0, doc="nothing reads it")

    assert unread_fields(_Unread, None, ["x = cfg.other\n"]) == [f"{_name(_Unread)}.zz_never_read_anywhere"]
    assert unread_fields(_Unread, None, ["x = cfg.zz_never_read_anywhere\n"]) == []
