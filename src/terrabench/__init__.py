"""terrabench: robots that cross unknown rough terrain by touching it.

The small public API::

    from terrabench import REGISTRY, get_system, TrialSpec, TrialResult, ResultsStore, run_trials
"""

from __future__ import annotations

from terrabench._version import __version__  # noqa: E402
from terrabench.benchmark.trial import TrialResult, TrialSpec  # noqa: E402
from terrabench.registry import REGISTRY  # noqa: E402


def get_system(name: str):
    """The system object registered under ``name`` (e.g. ``"mrs-cwc"``)."""
    from terrabench.catalog import system

    return system(name)


def __getattr__(name: str):
    if name == "ResultsStore":
        from terrabench.benchmark.store import ResultsStore

        return ResultsStore
    if name == "run_trials":
        from terrabench.benchmark.runner import run_trials

        return run_trials
    raise AttributeError(name)


__all__ = ["REGISTRY", "TrialSpec", "TrialResult", "ResultsStore", "run_trials", "get_system", "__version__"]
