"""The contract between a system and the shared runner, store, reports and CLI."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Protocol, Sequence

from terrabench.benchmark.trial import TrialResult, TrialSpec


class System(Protocol):
    """What the hallway needs from a system.

    ``run_trial`` must be importable by reference (a module-level function or a method of a
    module-level object) because the runner ships specs to worker processes or Ray tasks.
    """

    name: str

    def plan(
        self,
        *,
        methods: Sequence[str] | None,
        instances: Sequence[str] | None,
        group: str | None,
        seeds: int,
        overrides: dict[str, Any],
    ) -> list[TrialSpec]:
        """Expand a user's request into trial specs (raises ValueError on bad ids)."""

    def run_trial(self, spec: TrialSpec) -> TrialResult:
        """Run one trial; never raises for physics trouble (returns a status instead)."""

    def summarize(self, rows: list[dict[str, Any]]) -> Any:
        """A rich renderable (table) of stored rows, beside the paper's numbers."""

    def report(self, store: Any, out_dir: Path) -> Path:
        """Write the system's report (HTML + PNG/CSV); return the HTML path."""
