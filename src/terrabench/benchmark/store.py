"""The results store: one DuckDB file, one row per trial, time series beside it.

Tables:
    ``meta(name, value)``: ``schema_version`` and the writer's package version.
    ``trials``: one row per finished trial keyed by :attr:`TrialSpec.key`, with status,
        metrics, info and the fully resolved config as JSON.
    ``series(key, name, t_index, values)``: each stored time-series column as a DOUBLE[] list.

Opening a store reads it whole first (read-only): a truncated file, a damaged block or a file
that is not DuckDB is one :class:`StoreError` naming the file and what failed, and the file is
left exactly as it was. A trial's series and its row are written in one transaction, row last, so an interrupted
run leaves either the whole trial or nothing; re-running skips the keys already present,
except rows with status ``error`` (a fault, not a physics outcome), which it runs again.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
from pathlib import Path
from typing import Any, Callable, Iterable

import duckdb
import numpy as np

from terrabench.benchmark.trial import TrialResult, TrialSpec, canonical_json

SCHEMA_VERSION = 1

_DDL = [
    "CREATE TABLE IF NOT EXISTS meta (name VARCHAR PRIMARY KEY, value VARCHAR)",
    """CREATE TABLE IF NOT EXISTS trials (
        key VARCHAR PRIMARY KEY,
        system VARCHAR, scenario VARCHAR, method VARCHAR, instance VARCHAR, seed BIGINT,
        config_hash VARCHAR, status VARCHAR, wall_time DOUBLE,
        metrics JSON, info JSON, config JSON, finished_at TIMESTAMP, version VARCHAR)""",
    """CREATE TABLE IF NOT EXISTS series (
        key VARCHAR, name VARCHAR, position INTEGER, values DOUBLE[])""",
]


class StoreError(ValueError):
    """A results file that cannot be used (wrong version, locked, not a DuckDB file, damaged:
    truncated or with a block whose checksum fails). Raised on opening, with the file untouched."""


def _clean(obj: Any) -> Any:
    """JSON-safe: NaN/inf become null, numpy scalars become Python numbers."""
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _first_line(exc: BaseException) -> str:
    return (str(exc).splitlines() or [type(exc).__name__])[0]


def _metrics_back(d: dict[str, Any]) -> dict[str, float]:
    return {k: (float("nan") if v is None else v) for k, v in d.items()}


class ResultsStore:
    """A DuckDB results file. Use as a context manager or call :meth:`close`."""

    def __init__(self, path: str | Path, *, read_only: bool = False):
        from terrabench._version import __version__

        self.path = Path(path)
        if read_only and not self.path.exists():
            raise StoreError(f"results file not found: {str(self.path)!r} (run `terrabench run ...` first)")
        if not read_only and self.path.exists() and self.path.stat().st_size > 0:
            # read the whole file first, read-only, so a damaged store is refused untouched:
            # nothing is ever written into a file that could not be read back whole
            ResultsStore(self.path, read_only=True).close()
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.con = self._connect(read_only)
        try:
            self._check_or_init(read_only, __version__)
            if read_only:
                self._read_whole()
        except BaseException:
            self.con.close()
            raise

    def _connect(self, read_only: bool) -> duckdb.DuckDBPyConnection:
        try:
            con = duckdb.connect(str(self.path), read_only=read_only)
        except duckdb.IOException as exc:
            raise StoreError(f"cannot open results file {str(self.path)!r}: {_first_line(exc)} "
                             "(the file was left as it was)") from None
        except duckdb.Error as exc:
            raise StoreError(f"{str(self.path)!r} is not a usable DuckDB results file: {_first_line(exc)} "
                             "(the file was left as it was)") from None
        con.execute("SET enable_progress_bar = false")
        return con

    def _read_whole(self) -> None:
        """Read every stored value once (a hash over every column of every table), so a truncated
        file or a damaged block is found here, as one :class:`StoreError`, not by a later query."""
        tables = {r[0]: [c[0] for c in self.con.execute(
                     "SELECT column_name FROM information_schema.columns WHERE table_name = ?", [r[0]]).fetchall()]
                  for r in self.con.execute("SELECT table_name FROM information_schema.tables").fetchall()}
        try:
            for table, columns in sorted(tables.items()):
                cols = ", ".join(f'"{c}"' for c in columns)
                self.con.execute(f'SELECT count(*), bit_xor(hash({cols})) FROM "{table}"').fetchall()
        except duckdb.Error as exc:
            raise StoreError(f"results file {str(self.path)!r} is damaged (reading table {table!r}: "
                             f"{_first_line(exc)}); it was left as it was: copy it aside, and run into a new "
                             "--store") from None

    def _check_or_init(self, read_only: bool, version: str) -> None:
        tables = {r[0] for r in self.con.execute("SELECT table_name FROM information_schema.tables").fetchall()}
        if "meta" in tables:
            row = self.con.execute("SELECT value FROM meta WHERE name = 'schema_version'").fetchone()
            found = row[0] if row else "missing"
            if found != str(SCHEMA_VERSION):
                raise StoreError(
                    f"results file {str(self.path)!r} has schema version {found}; this terrabench reads "
                    f"version {SCHEMA_VERSION}. Use a new --store path (nothing was changed)."
                )
            return
        if tables:
            raise StoreError(
                f"{str(self.path)!r} is a DuckDB file but not a terrabench results store (tables: {sorted(tables)})"
            )
        if read_only:
            raise StoreError(f"results file {str(self.path)!r} is empty")
        for ddl in _DDL:
            self.con.execute(ddl)
        self.con.execute("INSERT INTO meta VALUES ('schema_version', ?), ('created_by', ?)",
                         [str(SCHEMA_VERSION), version])

    # ---------------------------------------------------------------- writing
    def write(self, spec: TrialSpec, result: TrialResult) -> None:
        """Store one finished trial atomically (replacing an earlier row with the same key)."""
        from terrabench._version import __version__

        key = spec.key
        con = self.con
        con.execute("BEGIN TRANSACTION")
        try:
            con.execute("DELETE FROM series WHERE key = ?", [key])
            con.execute("DELETE FROM trials WHERE key = ?", [key])
            if result.timeseries:
                con.executemany(
                    "INSERT INTO series VALUES (?, ?, ?, ?)",
                    [
                        [key, name, i, np.asarray(col, float).tolist()]
                        for i, (name, col) in enumerate(result.timeseries.items())
                    ],
                )
            con.execute(
                "INSERT INTO trials VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                [
                    key, spec.system, spec.scenario, spec.method, spec.instance, int(spec.seed),
                    spec.config_hash, result.status, float(result.wall_time),
                    json.dumps(_clean(result.metrics)), json.dumps(_clean(result.info)),
                    canonical_json(_clean(dict(spec.config))),
                    _dt.datetime.now(_dt.timezone.utc).replace(tzinfo=None), __version__,
                ],
            )
            con.execute("COMMIT")
        except BaseException:
            con.execute("ROLLBACK")
            raise

    def rekey(self, system: str, canonical: Callable[[TrialSpec], TrialSpec | None]) -> int:
        """Re-derive the keys of ``system``'s stored trials after a change in what a spec holds.

        ``canonical(spec)`` returns the spec the current code would plan for the stored one
        (e.g. with the config cut down to the sections its method reads), or ``None`` to
        leave the row alone. Rows whose key changes get the new key, config and hash, and
        their series follow; a row whose new key is already stored is left as it was.
        Results are never touched. Returns the number of rows rekeyed.
        """
        cols = "key, system, scenario, method, instance, seed, config"
        rows = self.con.execute(f"SELECT {cols} FROM trials WHERE system = ?", [system]).fetchall()
        taken = self.done_keys()
        moved = 0
        self.con.execute("BEGIN TRANSACTION")
        try:
            for key, sys_, scen, meth, inst, seed, cfg in rows:
                new = canonical(TrialSpec(sys_, scen, meth, inst, int(seed), json.loads(cfg)))
                if new is None or new.key == key or new.key in taken:
                    continue
                self.con.execute(
                    "UPDATE trials SET key = ?, config_hash = ?, config = ? WHERE key = ?",
                    [new.key, new.config_hash, canonical_json(_clean(dict(new.config))), key],
                )
                self.con.execute("UPDATE series SET key = ? WHERE key = ?", [new.key, key])
                taken.add(new.key)
                moved += 1
            self.con.execute("COMMIT")
        except BaseException:
            self.con.execute("ROLLBACK")
            raise
        return moved

    # ---------------------------------------------------------------- reading
    def done_keys(self, keys: Iterable[str] | None = None, *, retry_errors: bool = False) -> set[str]:
        """Keys of the stored trials (restricted to ``keys`` if given).

        With ``retry_errors=True`` the rows with status ``error`` are left out: an error is a
        fault of the run (a worker that died or hung, an exception), not a physics outcome,
        so the runner runs those trials again. ``timeout``, ``fell``, ``diverged`` and the
        other outcomes are final. The default (every stored row) is what "is this key
        taken?" needs (e.g. :meth:`rekey`).
        """
        sql = "SELECT key FROM trials" + (" WHERE status <> 'error'" if retry_errors else "")
        done = {r[0] for r in self.con.execute(sql).fetchall()}
        return done if keys is None else done & set(keys)

    def code_of(self, keys: Iterable[str]) -> dict[str, str | None]:
        """The code fingerprint each stored row of ``keys`` was made by (``info.host.code``,
        :func:`terrabench.benchmark.worker.code_fingerprint`; ``None`` for rows stored before it
        was recorded, or an ``error`` row without a host)."""
        rows = self.con.execute("SELECT key, json_extract_string(info, '$.host.code') FROM trials "
                                "WHERE list_contains(?, key)", [sorted(set(keys))]).fetchall()
        return dict(rows)

    def error_keys(self, keys: Iterable[str] | None = None) -> set[str]:
        """Keys of the stored rows with status ``error`` (restricted to ``keys`` if given)."""
        found = {r[0] for r in self.con.execute("SELECT key FROM trials WHERE status = 'error'").fetchall()}
        return found if keys is None else found & set(keys)

    def rows(
        self,
        system: str | None = None,
        scenario: str | None = None,
        method: str | None = None,
        keys: Iterable[str] | None = None,
    ) -> list[dict[str, Any]]:
        """Trial rows as dicts with parsed ``metrics``, ``info`` and ``config``."""
        where, args = [], []
        for col, val in (("system", system), ("scenario", scenario), ("method", method)):
            if val is not None:
                where.append(f"{col} = ?")
                args.append(val)
        sql = ("SELECT key, system, scenario, method, instance, seed, config_hash, status, wall_time, metrics, info, "
               "config, finished_at FROM trials")
        if where:
            sql += " WHERE " + " AND ".join(where)
        sql += " ORDER BY system, scenario, method, instance, seed"
        cols = ["key", "system", "scenario", "method", "instance", "seed", "config_hash", "status", "wall_time",
                "metrics", "info", "config", "finished_at"]
        out = []
        wanted = set(keys) if keys is not None else None
        for r in self.con.execute(sql, args).fetchall():
            d = dict(zip(cols, r))
            if wanted is not None and d["key"] not in wanted:
                continue
            d["metrics"] = _metrics_back(json.loads(d["metrics"]))
            d["info"] = json.loads(d["info"])
            d["config"] = json.loads(d["config"])
            out.append(d)
        return out

    def timeseries(self, key: str) -> dict[str, np.ndarray]:
        rows = self.con.execute("SELECT name, values FROM series WHERE key = ? ORDER BY position", [key]).fetchall()
        return {name: np.array([np.nan if v is None else v for v in vals], float) for name, vals in rows}

    def query(self, sql: str, params: list[Any] | None = None) -> list[tuple]:
        """Run SQL against the store (tables ``trials``, ``series``, ``meta``)."""
        return self.con.execute(sql, params or []).fetchall()

    def close(self) -> None:
        self.con.close()

    def trial_count(self) -> int:
        """How many trial rows the store holds."""
        row = self.con.execute("SELECT count(*) FROM trials").fetchone()
        assert row is not None  # count(*) always returns one row
        return int(row[0])

    def __enter__(self) -> "ResultsStore":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
