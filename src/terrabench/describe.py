"""What ``terrabench list SYSTEM``, ``terrabench list --statuses`` and ``terrabench config SYSTEM``
print: a system's methods, groups (with sizes), instance ids, every ``--set`` key with its
default, type, range and meaning, and what each trial status means.

Everything here is read from the system object and its config's :func:`terrabench.config.param`
declarations; nothing builds a model or runs a trial (planning is cheap and side-effect free).
"""

from __future__ import annotations

import re
from typing import Any

from terrabench.benchmark.trial import STATUSES
from terrabench.config import fields_info

#: what each trial status means for every system (one entry per
#: :data:`terrabench.benchmark.trial.STATUSES`); what it means for one system is that system's
#: ``System.status_notes`` (shown beside it by ``terrabench list --statuses``)
STATUS_MEANINGS = {
    "success": "the task's goal was reached",
    "timeout": "the simulated-time limit (--timeout) ran out first; the robot may still have been making progress",
    "fell": "the robot fell off or out of the world",
    "stuck": "no progress for the system's stall time, or a controller gave up",
    "turned_over": "the body tilted past the system's turned-over limit",
    "tipped_back": "the robot tipped over backwards: its COG passed behind its rearmost loaded ground contact with "
                   "the nose up and rising (a physical condition, not an angle)",
    "diverged": "the simulation blew up (non-finite state, a speed above physics.max_speed, or MuJoCo reset "
                "the state): a numerical failure, not an outcome of the method",
    "error": "the trial raised, its worker died or it ran past its wall-time budget: a fault of the run, "
             "not physics; running the same command again retries it",
    "done": "a trial without a pass/fail outcome finished (estimation fits, soil sweeps, contact checks, "
            "barriers): read its metrics",
}


def instances_of(sysobj: Any, group: str | None) -> list[str]:
    """The instance ids of ``group`` (None: all), from ``instances()`` or, failing that, a plan."""
    try:
        return list(sysobj.instances(group))
    except NotImplementedError:
        seen: dict[str, None] = {}
        for spec in sysobj.plan(methods=list(sysobj.methods()), group=group or "all", seeds=1):
            seen.setdefault(spec.instance, None)
        return list(seen)


def id_pattern(ids: list[str]) -> str:
    """The shapes of ``ids`` with digits shown as ``N`` (``A-01`` -> ``A-NN``), most common first."""
    shapes: dict[str, int] = {}
    for i in ids:
        s = re.sub(r"\d", "N", i)
        shapes[s] = shapes.get(s, 0) + 1
    return ", ".join(sorted(shapes, key=lambda s: -shapes[s])[:4]) + (" ..." if len(shapes) > 4 else "")


def examples(ids: list[str], n: int = 3) -> str:
    if len(ids) <= n + 1:
        return ", ".join(ids)
    return ", ".join(ids[:n]) + f" ... {ids[-1]}"


def methods_for(sysobj: Any, group: str | None = None, instances: list[str] | None = None) -> list[str]:
    """The methods that apply (:meth:`~terrabench.systems.base.System.applies`) to at least one
    instance of ``group`` (or of ``instances``; neither: the default group)."""
    ids = list(instances) if instances else instances_of(sysobj, group if group is not None else sysobj.default_group)
    return [m for m in sysobj.methods() if any(sysobj.applies(m, i) for i in ids)]


def system_tables(sysobj: Any) -> list[Any]:
    """Rich renderables for ``terrabench list SYSTEM``."""
    from rich.table import Table

    out: list[Any] = []
    t = Table(title=f"{sysobj.id}: methods (--methods; 'all' = every one)", title_justify="left")
    t.add_column("method")
    t.add_column("default")
    t.add_column("summary")
    defaults = set(sysobj.default_methods())
    for m in sysobj.methods().values():
        t.add_row(m.id, "yes" if m.id in defaults else "", m.summary)
    out.append(t)

    all_ids = instances_of(sysobj, None)
    all_methods = list(sysobj.methods())
    g = Table(title=f"{sysobj.id}: groups (--group; 'all' = every instance)", title_justify="left")
    for c in ("group", "instances", "examples", "methods", "meaning"):
        g.add_column(c)
    for gid, text in sysobj.groups.items():
        ids = instances_of(sysobj, gid)
        applicable = methods_for(sysobj, gid)
        shown = "all" if applicable == all_methods else ", ".join(applicable)
        default = " (default)" if gid == sysobj.default_group else ""
        g.add_row(gid + default, str(len(ids)), examples(ids), shown, text)
    g.add_row("all", str(len(all_ids)), "", "", "every instance")
    out.append(g)
    fmt = getattr(sysobj, "instance_format", "")
    out.append(f"instance ids (--terrains): {fmt}" if fmt else
               f"instance ids (--terrains): {id_pattern(all_ids)}; e.g. {examples(all_ids)}")
    extra = []
    if sysobj.timeout_key:
        extra.append(f"--timeout sets {sysobj.timeout_key}")
    if sysobj.threshold_key:
        extra.append(f"--threshold sets {sysobj.threshold_key}")
    if sysobj.env_ids:
        extra.append("environments: " + ", ".join(sysobj.env_ids))
    extra.append(f"every --set key: terrabench config {sysobj.id}")
    out.append("; ".join(extra))
    return out


def _show(v: Any) -> str:
    if isinstance(v, tuple):
        return "[" + ", ".join(_show(x) for x in v) + "]"
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def config_table(sysobj: Any) -> Any:
    """Rich table for ``terrabench config SYSTEM``: every ``--set`` key of the default config."""
    from rich.table import Table

    t = Table(title=f"{sysobj.id}: --set KEY=VALUE keys (defaults before any instance's own settings)",
              title_justify="left")
    for c, width in (("key", None), ("default", 24), ("type", 16), ("valid", 40), ("meaning", None)):
        t.add_column(c, overflow="fold", max_width=width)
    for info in fields_info(sysobj.base_config()):
        t.add_row(info.key, _show(info.default), info.type, info.valid, info.doc)
    return t


def statuses_table(systems: Any = ()) -> Any:
    """Every status, its meaning, and what it means in each of ``systems`` (their ``status_notes``)."""
    from rich.table import Table

    t = Table(title="trial statuses", title_justify="left")
    t.add_column("status")
    t.add_column("meaning")
    t.add_column("per system")
    for s in STATUSES:
        notes = "; ".join(f"{sy.id}: {sy.status_notes[s]}" for sy in systems if s in sy.status_notes)
        t.add_row(s, STATUS_MEANINGS[s], notes)
    return t
