"""One registry for systems, scenarios and methods.

Each entry is a :class:`Record` with an id, a one-line summary, tags and a lazy
``"module:attr"`` target, so listing entries never imports MuJoCo models. Unknown ids raise
a :class:`ValueError` naming the valid ones (the CLI turns that into one clear line).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any

KINDS = ("system", "scenario", "method")


@dataclass(frozen=True)
class Record:
    """One registry entry.

    Attributes:
        kind: ``"system"``, ``"scenario"`` or ``"method"``.
        id: the id a user types (methods are unique within their system).
        summary: one line for ``terrabench list``.
        target: ``"module:attr"`` resolved on first use.
        system: the owning system id (the system's own id for systems).
        tags: free-form labels, e.g. ``("linked", "map")``.
    """

    kind: str
    id: str
    summary: str
    target: str = ""
    system: str = ""
    tags: tuple[str, ...] = field(default_factory=tuple)

    def load(self) -> Any:
        module, _, attr = self.target.partition(":")
        obj = importlib.import_module(module)
        return getattr(obj, attr) if attr else obj


class Registry:
    def __init__(self) -> None:
        self._records: dict[tuple[str, str, str], Record] = {}

    def register(self, record: Record) -> Record:
        if record.kind not in KINDS:
            raise ValueError(f"unknown record kind {record.kind!r}; valid: {', '.join(KINDS)}")
        key = (record.kind, record.system, record.id)
        if key in self._records:
            raise ValueError(f"duplicate {record.kind} id {record.id!r} in system {record.system!r}")
        self._records[key] = record
        return record

    def entries(self, kind: str | None = None, system: str | None = None) -> list[Record]:
        return [
            r
            for (k, s, _), r in self._records.items()
            if (kind is None or k == kind) and (system is None or s == system)
        ]

    def ids(self, kind: str, system: str | None = None) -> list[str]:
        return [r.id for r in self.entries(kind, system)]

    def get(self, kind: str, id: str, system: str | None = None) -> Record:
        matches = [r for r in self.entries(kind, system) if r.id == id]
        if not matches:
            valid = ", ".join(self.ids(kind, system)) or "(none)"
            where = f" of system {system!r}" if system else ""
            raise ValueError(f"unknown {kind} {id!r}{where}; valid: {valid}")
        return matches[0]


#: The process-wide registry. Systems register themselves in :mod:`terrabench.catalog`.
REGISTRY = Registry()
