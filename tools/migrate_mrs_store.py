"""Bring an MRS-CWC results store written before per-method configs up to date.

Since terrabench 0.2 an MRS-CWC trial stores (and is keyed by) only the config sections its
method reads (``methods.Method.reads``). Older stores keyed every trial by the whole
config, so their rows would no longer be found and would re-run. This script re-derives
each row's key from its stored config, cut down the same way; metrics and series are not
touched. Rows whose stored config lacks a field the current code has (their settings
cannot be stated in the current schema) are reported, and with ``--drop-incomplete``
deleted, so they re-run under the current defaults.

Also upgrades configs across later schema changes (:func:`upgrade`): terrabench 0.3 dropped
``stiffness.control_period``, a copy of ``protocol.control_period`` (one value in one place);
rows where the two agreed lose the copy, rows where they differed cannot be stated in the
current schema and count as incomplete.

Usage: python tools/migrate_mrs_store.py results/terrabench.duckdb [--drop-incomplete]
A copy of the file is written beside it first (``*.pre-migration.duckdb``).
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

from terrabench.benchmark.store import ResultsStore
from terrabench.benchmark.trial import TrialSpec, canonical_json
from terrabench.config import from_dict, to_dict
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import METHODS, config_for

#: fields added in terrabench 0.3 (wheel_shape, bumper_touches_ground: 0.3.1) whose defaults reproduce 0.2's
#: trials bitwise (checked on 48 trials, 8 methods x 6 terrains, with tools/compare_stores.py --by trial): a row
#: that lacks them ran with those defaults
ADDED_WITH_NEUTRAL_DEFAULTS = {
    "chain": ("wheel_drive", "noslip_iterations", "wheel_solref", "wheel_solimp", "drive_solref",
              "drive_solimp", "drive_ref_armature", "wheel_shape",
              "bumper_touches_ground"),
    "protocol": ("stall_time", "stall_distance"),
}


def upgrade(config: dict) -> dict:
    """A stored config in the current schema, where that states the same trial."""
    cfg = {k: (dict(v) if isinstance(v, dict) else v) for k, v in config.items()}
    defaults = to_dict(MRSConfig())
    for section, names in ADDED_WITH_NEUTRAL_DEFAULTS.items():
        if isinstance(cfg.get(section), dict):
            for name in names:
                cfg[section].setdefault(name, defaults[section][name])
    stiff = cfg.get("stiffness")
    if isinstance(stiff, dict) and "control_period" in stiff:
        period = cfg.get("protocol", {}).get("control_period", MRSConfig().protocol.control_period)
        if stiff["control_period"] == period:
            del stiff["control_period"]
    return cfg


def complete(config: dict) -> bool:
    """True if the stored (possibly partial) config names every field of its sections."""
    try:
        rebuilt = to_dict(from_dict(MRSConfig, config))
    except ValueError:  # a field the current schema no longer has
        return False
    return all(canonical_json(rebuilt[k]) == canonical_json(v) for k, v in config.items())


def canonical(spec: TrialSpec) -> TrialSpec | None:
    method = METHODS.get(spec.method)
    if method is None:
        return None
    cfg = config_for(method, upgrade(dict(spec.config)))
    if not complete(cfg):
        return None
    return TrialSpec(spec.system, spec.scenario, spec.method, spec.instance, spec.seed, cfg)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("store", type=Path)
    ap.add_argument("--drop-incomplete", action="store_true")
    args = ap.parse_args()
    backup = args.store.with_suffix(".pre-migration.duckdb")
    with ResultsStore(args.store) as st:
        st.con.execute("CHECKPOINT")
    shutil.copy2(args.store, backup)
    with ResultsStore(args.store) as st:
        moved = st.rekey("mrs-cwc", canonical)
        rows = st.rows(system="mrs-cwc")
        stale = [r for r in rows if r["method"] in METHODS
                 and not complete(config_for(METHODS[r["method"]], upgrade(r["config"])))]
        print(f"rekeyed {moved} rows; {len(stale)} incomplete rows "
              f"({sorted({r['method'] for r in stale})}); backup: {backup}")
        if args.drop_incomplete and stale:
            keys = [r["key"] for r in stale]
            st.con.executemany("DELETE FROM series WHERE key = ?", [[k] for k in keys])
            st.con.executemany("DELETE FROM trials WHERE key = ?", [[k] for k in keys])
            print(f"deleted {len(keys)} incomplete rows (kept in the backup)")


if __name__ == "__main__":
    main()
