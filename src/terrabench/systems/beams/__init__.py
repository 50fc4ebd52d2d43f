"""Beam traversal with environmental force sensing (Xuan, Wang & Li).

A cockroach-inspired ellipsoid robot meets two grass-like beams, estimates their stiffness from
noisy contact forces, chooses the cheaper mode on a potential-energy landscape and tracks the
plan by feedback linearization. ``SYSTEM`` plugs into the terrabench runner; ``register`` adds
the system, scenario and method ids to a registry. See ``docs/beams.md``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from terrabench.benchmark.trial import TrialResult, TrialSpec
from terrabench.systems.base import MethodInfo, System

from . import scenarios as _sc
from .config import TrialConfig

__all__ = ["SYSTEM", "BeamsSystem", "register"]


class BeamsSystem(System):
    """The beams system on the hallway contract (its trials run the paper's own integrator)."""

    id = _sc.SYSTEM_ID
    status_notes = {"success": "passed the beams", "fell": "the body rolled or pitched past 90 deg",
                    "stuck": "the plan ended without passing"}
    summary = ("Xuan, Wang, Li: an ellipsoid robot senses beam stiffness by touch and plans on a potential-energy "
               "landscape (pitch over or roll through)")
    status = "model, estimation, planning, control, MuJoCo cross-check, report; no env (the paper's analytic dynamics)"
    config_cls = TrialConfig
    groups = {g: g for g in _sc.GROUPS}
    timeout_key = "protocol.timeout"
    headline_metrics = ()
    smoke = {"methods": ["open-loop"], "instances": ["flimsy-f0.1"]}
    golden = ({"methods": ["estimate-3"], "instances": ["sigma20-ts100"]},
              {"methods": ["interact"], "instances": ["flimsy"]},
              {"methods": ["mujoco"], "instances": ["roll0-pitch20"]})

    def methods(self) -> dict[str, MethodInfo]:
        return {m: MethodInfo(m, text, ("beams",) + _sc.METHOD_GROUP[m]) for m, text in _sc.METHODS.items()}

    def instances(self, group: str | None) -> list[str]:
        """Instance ids of ``group`` (None or ``"all"``: every group's, in group order)."""
        if group in (None, "all"):
            return [i for g in _sc.GROUPS for i in _sc.INSTANCES[g]]
        if group not in _sc.INSTANCES:
            raise ValueError(f"unknown beams group {group!r}; valid: {', '.join(_sc.GROUPS)}, all")
        return list(_sc.INSTANCES[group])

    def applies(self, method: str, instance: str) -> bool:
        """A method runs on the instances of its groups (:data:`scenarios.METHOD_GROUP`)."""
        return any(instance in _sc.INSTANCES[g] for g in _sc.METHOD_GROUP.get(method, ()))

    def plan(self, *, methods: Sequence[str] | None = None, instances: Sequence[str] | None = None,
             group: str | None = None, seeds: int = 1, overrides: dict[str, Any] | None = None) -> list[TrialSpec]:
        """Trial specs for ``group`` (estimation, traversal, open-loop, delay, experiment,
        contact-check, barriers or all); raises ValueError on unknown ids."""
        return _sc.plan_specs(methods=methods, instances=instances, group=group, seeds=seeds,
                              overrides=overrides or {})

    def run_trial(self, spec: TrialSpec, *, on_step=None) -> TrialResult:
        """Run one trial (deterministic in spec.config and spec.seed)."""
        from .trials import run_trial
        return run_trial(spec)

    def summarize(self, rows: list[dict[str, Any]]) -> Any:
        """A rich table of stored rows beside the paper's numbers."""
        from .report import summarize
        return summarize(rows)

    def report(self, store: Any, out_dir: Path) -> Path:
        """Write ``out_dir/index.html`` with figures and CSVs; return its path."""
        from .report import write_report
        return write_report(store, Path(out_dir), system=self)


SYSTEM = BeamsSystem()


def register(registry) -> None:
    """Register the beams system, its scenarios and its methods in ``registry``."""
    from terrabench.registry import Record

    registry.register(Record("system", _sc.SYSTEM_ID, BeamsSystem.summary,
                             "terrabench.systems.beams:SYSTEM", _sc.SYSTEM_ID, ("beams", "force-sensing")))
    summaries = {
        "estimation": "Tables 1-4: fit 4/3/2 beam unknowns from noisy forces vs noise and sensing time",
        "traversal": "Sec. III-C/D: interact (landscape plan) vs avoid (roll through the gap), energy eq. 11",
        "open-loop": "Sec. III-A: constant propulsion 0.1 N / 1 N into stiff and flimsy beams",
        "delay": "Sec. III-E: energy cost vs sensory delay (100, 300, 600 ms)",
        "experiment": "Sec. IV: estimate (k, tau0) with beam mass and preload (eq. 12) on simulated data",
        "contact-check": "Analytic contact model vs MuJoCo quasi-static pushes",
        "barriers": "Sec. II-G on the landscape: pitch vs roll barrier and crossover stiffness vs the gap",
    }
    for g, sid in _sc.SCENARIOS.items():
        registry.register(Record("scenario", sid, summaries[g], "terrabench.systems.beams.scenarios:plan_specs",
                                 _sc.SYSTEM_ID, ("beams", g)))
    for m, text in _sc.METHODS.items():
        registry.register(Record("method", m, text, "terrabench.systems.beams.trials:run_trial",
                                 _sc.SYSTEM_ID, ("beams",) + _sc.METHOD_GROUP[m]))
