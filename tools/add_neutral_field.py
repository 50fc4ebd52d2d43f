"""Carry a results store across a config field added with a neutral default, or removed.

Every trial is keyed by its whole resolved config, so a new field (even one whose default
leaves the physics as it was) gives every trial of its system a new key: the stored rows
would no longer be found and would all re-run. When the default is *neutral* (the trials it
applies to give the same bits with and without it: check it, below), a stored row that lacks
the field ran with that default, so its config can state it and its key can follow.

This script adds ``--field PATH=VALUE`` (a dotted config path, VALUE as JSON) to every stored
row of ``--system`` that lacks it (``--method-prefix`` restricts the rows, e.g. ``srwmr.`` for
the rover's rows of the mobility map, whose robot config sits under ``robot``; ``--under
robot`` then prefixes the path) and re-derives the keys (:meth:`ResultsStore.rekey`); metrics
and series are not touched. A backup of the file is written first.

``--drop PATH`` does the opposite for a field the code no longer has: it removes PATH from every
stored row that holds it. A field removed because nothing read it (tests/test_config_docs.py,
``test_every_config_field_is_read_by_the_package``) is neutral by construction; rows that differed
only in it collide on one key, and :meth:`ResultsStore.rekey` keeps the first and leaves the
others under their old keys.

Check the neutrality before trusting the result: re-run a sample of the rekeyed trials into a
fresh store with the current code and compare, e.g.
``python tools/compare_stores.py OLD.duckdb NEW.duckdb --by trial`` (0 differ).

Usage: python tools/add_neutral_field.py STORE --system srwmr --field soil.buried=0.0
       python tools/add_neutral_field.py STORE --system srwmr --drop scales.wb_min
       python tools/add_neutral_field.py STORE --system zoo --method-prefix srwmr. \
           --under robot --field soil.buried=0.0
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialSpec


def parse_field(text: str) -> tuple[list[str], object]:
    path, sep, value = text.partition("=")
    if not sep or not path:
        raise SystemExit(f"--field must be PATH=VALUE (VALUE as JSON), got {text!r}")
    return path.split("."), json.loads(value)


def _section(config: dict, path: list[str]) -> tuple[dict, dict] | None:
    """(a deep copy of ``config``, the copy's section holding ``path``'s last part), or None if a
    section on the way is absent."""
    out = json.loads(json.dumps(config))
    node = out
    for part in path[:-1]:
        node = node.get(part) if isinstance(node, dict) else None
        if not isinstance(node, dict):
            return None
    return out, node


def with_field(config: dict, path: list[str], value: object) -> dict | None:
    """``config`` with ``path`` set to ``value`` if it lacks it; None if it has it or its section is absent."""
    found = _section(config, path)
    if found is None or path[-1] in found[1]:
        return None
    found[1][path[-1]] = value
    return found[0]


def without_field(config: dict, path: list[str]) -> dict | None:
    """``config`` without ``path`` if it holds it; None if it does not."""
    found = _section(config, path)
    if found is None or path[-1] not in found[1]:
        return None
    del found[1][path[-1]]
    return found[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("store", type=Path)
    ap.add_argument("--system", required=True)
    ap.add_argument("--field", action="append", default=[], help="dotted path=JSON value to add (repeatable)")
    ap.add_argument("--drop", action="append", default=[], help="dotted path to remove (repeatable)")
    ap.add_argument("--method-prefix", default="")
    ap.add_argument("--under", default="", help="section the path sits in (e.g. robot for zoo rows)")
    args = ap.parse_args()
    if not args.field and not args.drop:
        raise SystemExit("give at least one --field PATH=VALUE or --drop PATH")

    def under(path: list[str]) -> list[str]:
        return [*args.under.split("."), *path] if args.under else path

    fields = []
    for text in args.field:
        path, value = parse_field(text)
        fields.append((under(path), value))
    drops = [under(text.split(".")) for text in args.drop]

    def canonical(spec: TrialSpec) -> TrialSpec | None:
        if not spec.method.startswith(args.method_prefix):
            return None
        cfg, changed = dict(spec.config), False
        for path, value in fields:
            new = with_field(cfg, path, value)
            if new is not None:
                cfg, changed = new, True
        for path in drops:
            new = without_field(cfg, path)
            if new is not None:
                cfg, changed = new, True
        if not changed:
            return None
        return TrialSpec(spec.system, spec.scenario, spec.method, spec.instance, spec.seed, cfg)

    backup = args.store.with_suffix(".pre-field.duckdb")
    with ResultsStore(args.store) as st:
        st.con.execute("CHECKPOINT")
    shutil.copy2(args.store, backup)
    with ResultsStore(args.store) as st:
        moved = st.rekey(args.system, canonical)
    print(f"rekeyed {moved} rows of {args.system}{' ' + args.method_prefix if args.method_prefix else ''}; "
          f"backup: {backup}")


if __name__ == "__main__":
    main()
