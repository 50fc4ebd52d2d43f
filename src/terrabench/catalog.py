"""Fills :data:`terrabench.registry.REGISTRY` with every system, scenario and method.

Systems are found the way Gymnasium finds env plugins: through the ``terrabench.systems``
entry-point group. Each entry point names a ``register(registry)`` function; the built-in
systems are registered the same way in this package's own ``pyproject.toml``::

    [project.entry-points."terrabench.systems"]
    mrs-cwc = "terrabench.systems.mrs_cwc:register"

A third-party package adds its own line to its ``pyproject.toml`` and, once installed, its system
is listed, run, reported and wrapped as an env like the built-in ones. Systems register lazily
("module:attr" targets), so ``terrabench list`` never builds a model. A system whose module
fails to import is an error (:class:`SystemImportError`: one line from the CLI, the traceback
with ``terrabench --debug``), never silently skipped.

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


@functools.cache
def populate(registry: Registry = REGISTRY) -> Registry:
    """Register every installed system (entry points) and the ``TERRABENCH_PLUGINS`` modules."""
    for plugin in filter(None, (p.strip() for p in os.environ.get("TERRABENCH_PLUGINS", "").split(","))):
        load_plugin(plugin)
    for ep in system_entry_points():
        try:
            register = ep.load()
            register(registry)
        except Exception as exc:  # noqa: BLE001 - an installed system that cannot load is the user's error
            raise SystemImportError(f"system {ep.name!r} ({ep.value}) failed to load: "
                                    f"{type(exc).__name__}: {exc} (run with --debug for the traceback)") from exc
    return registry


def system(name: str):
    """The ``SYSTEM`` object of a system id; ValueError listing valid ids otherwise."""
    record: Record = populate().get("system", name)
    return record.load()
