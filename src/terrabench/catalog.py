"""Fills :data:`terrabench.registry.REGISTRY` with every system, scenario and method.

Systems are found the way Gymnasium finds env plugins: through the ``terrabench.systems``
entry-point group. Each entry point names a ``register(registry)`` function; the built-in
systems are registered the same way in this package's own ``pyproject.toml``::

    [project.entry-points."terrabench.systems"]
    mrs-cwc = "terrabench.systems.mrs_cwc:register"

A third-party package adds its own line to its ``pyproject.toml`` and, once installed, its system
is listed, run, reported and wrapped as an env like the built-in ones. Systems register lazily
("module:attr" targets), so ``terrabench list`` never builds a model. A system whose module
fails to import is never silently skipped: asking for it is an error (:class:`SystemImportError`:
one line from the CLI, the traceback with ``terrabench --debug``), ``terrabench list`` ends with
that error, and every other command warns once on stderr, while the systems that load keep
working (as Gymnasium treats a broken env plugin: one broken package does not take the others
down).

``TERRABENCH_PLUGINS`` (comma-separated) names extra modules that add methods to existing systems;
each item is a module name importable from ``sys.path`` or a path to a ``.py`` file.
"""

from __future__ import annotations

import functools
import importlib
import importlib.util
import os
import sys
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path

from terrabench.registry import REGISTRY, Record, Registry

#: the entry-point group systems register under
ENTRY_POINT_GROUP = "terrabench.systems"


class SystemImportError(ValueError):
    """A registered system (or a plug-in module) could not be loaded; ``__cause__`` holds why."""


def system_entry_points() -> list[EntryPoint]:
    """The installed ``terrabench.systems`` entry points, one per name (the first found wins)."""
    seen: dict[str, EntryPoint] = {}
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        seen.setdefault(ep.name, ep)
    return list(seen.values())


def load_plugin(item: str) -> None:
    """Import one ``TERRABENCH_PLUGINS`` item: a module name, or a path to a ``.py`` file."""
    path = Path(item).expanduser()
    try:
        if item.endswith(".py") or os.sep in item:
            if not path.is_file():
                raise FileNotFoundError(f"no such file {str(path)!r}")
            spec = importlib.util.spec_from_file_location(path.stem, path)
            module = importlib.util.module_from_spec(spec)
            sys.modules[path.stem] = module
            spec.loader.exec_module(module)
        else:
            importlib.import_module(item)
    except Exception as exc:  # noqa: BLE001 - any failure of user code is reported the same way
        raise SystemImportError(
            f"TERRABENCH_PLUGINS names {item!r}, which cannot be imported ({type(exc).__name__}: {exc}); "
            "give a module on the Python path or a path to a .py file") from exc


#: registry -> {system name: the error its entry point raised}, filled by :func:`populate`
_FAILURES: dict[int, dict[str, SystemImportError]] = {}


@functools.cache
def populate(registry: Registry = REGISTRY) -> Registry:
    """Register every installed system (entry points) and the ``TERRABENCH_PLUGINS`` modules.

    A ``TERRABENCH_PLUGINS`` item that cannot be imported raises :class:`SystemImportError`; an
    installed system that fails to load is recorded (:func:`load_failures`) and raised by
    :func:`system` when it is asked for.
    """
    for plugin in filter(None, (p.strip() for p in os.environ.get("TERRABENCH_PLUGINS", "").split(","))):
        load_plugin(plugin)
    failures = _FAILURES.setdefault(id(registry), {})
    for ep in system_entry_points():
        try:
            register = ep.load()
            register(registry)
        except Exception as exc:  # noqa: BLE001 - an installed system that cannot load is reported, not fatal
            err = SystemImportError(f"system {ep.name!r} ({ep.value}) failed to load: "
                                    f"{type(exc).__name__}: {exc} (run with --debug for the traceback)")
            err.__cause__ = exc
            failures[ep.name] = err
    return registry


def load_failures(registry: Registry | None = None) -> dict[str, SystemImportError]:
    """System name -> why its entry point failed to load (empty when every system loaded)."""
    reg = populate() if registry is None else populate(registry)
    return dict(_FAILURES.get(id(reg), {}))


def system(name: str):
    """The ``SYSTEM`` object of a system id; ValueError listing valid ids otherwise, and the
    load error itself for a system that is installed but failed to load."""
    reg = populate()
    failed = _FAILURES.get(id(reg), {})
    if name in failed:
        raise failed[name]
    record: Record = reg.get("system", name)
    return record.load()
