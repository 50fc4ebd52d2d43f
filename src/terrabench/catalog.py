"""Fills :data:`terrabench.registry.REGISTRY` with every system, scenario and method.

Systems register lazily ("module:attr" targets), so ``terrabench list`` never builds a model.
"""

from __future__ import annotations

import functools
import importlib
import os

from terrabench.registry import REGISTRY, Record, Registry

#: system id -> module that defines ``register(registry)`` and ``SYSTEM``
SYSTEM_MODULES = {
    "mrs-cwc": "terrabench.systems.mrs_cwc",
    "beams": "terrabench.systems.beams",
    "octopus": "terrabench.systems.octopus",
    "soil": "terrabench.systems.soil",
}


@functools.cache
def populate(registry: Registry = REGISTRY) -> Registry:
    # user modules that register methods of their own (imported in every worker too)
    for plugin in filter(None, os.environ.get("TERRABENCH_PLUGINS", "").split(",")):
        try:
            importlib.import_module(plugin.strip())
        except ImportError as exc:
            raise ValueError(f"TERRABENCH_PLUGINS names {plugin!r}, which cannot be imported: {exc}") from None
    for sid, module in SYSTEM_MODULES.items():
        try:
            mod = importlib.import_module(module)
        except ImportError:  # a system still being built is simply absent
            continue
        if hasattr(mod, "register"):
            mod.register(registry)
    return registry


def system(name: str):
    """The ``SYSTEM`` object of a system id; ValueError listing valid ids otherwise."""
    record: Record = populate().get("system", name)
    return record.load()
