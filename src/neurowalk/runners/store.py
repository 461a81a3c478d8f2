"""The result store of a sweep: one SQLite file (``DIR/results.sqlite``), one row per run, keyed by its spec.

.. code-block:: text

    runs(key TEXT,               -- spec_key(spec): SHA-256 of the canonical spec
         code TEXT,              -- the fingerprint of the code that made the run (neurowalk.fingerprint.code)
         spec TEXT,              -- the normalised spec, JSON
         status TEXT,            -- 'ok' | 'error'
         result TEXT,            -- the run's summary, JSON (NULL on error)
         error TEXT,             -- one line (NULL when ok)
         wall_time_s REAL,       -- seconds the run took on its worker (machine-dependent, so not in `result`)
         finished_at TEXT,       -- ISO 8601, UTC
         PRIMARY KEY (key, code))
    meta(name TEXT PRIMARY KEY, value TEXT)   -- schema_version, created_at, neurowalk_version

A store is opened for one ``code`` (:func:`neurowalk.fingerprint.code` by default): it reads and writes the rows of
that code only, so a run made by other code (an edited learning rule, metric or keep term; another library version)
is never taken as done, and two checkouts sharing one store keep their runs side by side. A store of schema 1
(before fingerprints) is brought to schema 2 as it opens, its rows under the code ``""``: none is taken as done.

Only the driver process writes; each finished run is its own transaction, so a sweep killed at any moment
(even ``kill -9``) leaves every finished run in a readable store (write-ahead log, replayed on the next open).
"""

from __future__ import annotations

import csv
import datetime
import json
import sqlite3
from collections.abc import Collection
from pathlib import Path
from typing import IO, Any

import neurowalk
from neurowalk import fingerprint, profiling
from neurowalk.fileio import atomic_write, exclusive_lock, to_jsonable
from neurowalk.runners.specs import DEFAULTS, FIELDS

SCHEMA_VERSION = 2
RUN_COLUMNS = ("key", "code", "spec", "status", "result", "error", "wall_time_s", "finished_at")
#: Columns of an export before the spec fields and the summary keys.
EXPORT_META = ("key", "code", "status", "error", "wall_time_s", "finished_at")
#: The code of the rows a schema-1 store held (made before fingerprints: never taken as done).
NO_CODE = ""

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (name TEXT PRIMARY KEY, value TEXT);
CREATE TABLE IF NOT EXISTS runs (
    key TEXT NOT NULL,
    code TEXT NOT NULL,
    spec TEXT NOT NULL,
    status TEXT NOT NULL CHECK (status IN ('ok', 'error')),
    result TEXT,
    error TEXT,
    wall_time_s REAL,
    finished_at TEXT NOT NULL,
    PRIMARY KEY (key, code)
);
"""


class StoreError(Exception):
    """The store file cannot be used (not SQLite, corrupt, another schema); the message names the path."""


class ResultStore:
    """SQLite result store at ``path`` (created if missing), read and written for the runs of ``code`` (default
    :func:`neurowalk.fingerprint.code`: the package and its libraries). Use as a context manager, or call
    :meth:`close`."""

    def __init__(self, path: Path | str, code: str | None = None) -> None:
        self.path = Path(path)
        self.code = fingerprint.code() if code is None else code
        self._lock = _lock(self.path)
        try:
            self._db = sqlite3.connect(self.path, timeout=30.0, isolation_level=None)  # autocommit; explicit txns
        except sqlite3.Error as e:
            self._lock.close()
            raise StoreError(f"cannot open result store {str(self.path)!r}: {e}") from None
        try:
            self._open()
        except sqlite3.Error as e:
            self.close()
            raise StoreError(f"{str(self.path)!r} is not a readable result store ({e})") from None
        except StoreError:
            self.close()
            raise

    def _open(self) -> None:
        db = self._db
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        if tables and "meta" not in tables:
            raise StoreError(f"{str(self.path)!r} is an SQLite file but not a neurowalk result store")
        db.execute("PRAGMA journal_mode = WAL")
        db.execute("PRAGMA synchronous = NORMAL")  # WAL + NORMAL: a killed process loses no committed run
        if not tables:
            meta = {
                "schema_version": str(SCHEMA_VERSION),
                "created_at": _now(),
                "neurowalk_version": neurowalk.__version__,
            }
            with self._txn():
                for statement in _SCHEMA.split(";"):
                    if statement.strip():
                        db.execute(statement)
                db.executemany("INSERT INTO meta VALUES (?, ?)", meta.items())
        row = db.execute("SELECT value FROM meta WHERE name = 'schema_version'").fetchone()
        if row is not None and row[0] == "1":
            self._upgrade()
            row = ("2",)
        if row is None or row[0] != str(SCHEMA_VERSION):
            found = "none" if row is None else row[0]
            raise StoreError(f"result store {str(self.path)!r} has schema version {found}, expected {SCHEMA_VERSION}")
        cols = tuple(r[1] for r in db.execute("PRAGMA table_info(runs)"))
        if cols != RUN_COLUMNS:
            raise StoreError(f"result store {str(self.path)!r}: table runs has columns {cols}, expected {RUN_COLUMNS}")
        db.execute("SELECT count(*) FROM runs").fetchone()

    def _upgrade(self) -> None:
        """Schema 1 to 2: every row kept, under the code :data:`NO_CODE` (made before fingerprints)."""
        db = self._db
        with self._txn():
            db.execute("ALTER TABLE runs RENAME TO runs_1")
            db.execute(_SCHEMA.split(";")[1])
            db.execute(
                "INSERT INTO runs SELECT key, ?, spec, status, result, error, wall_time_s, finished_at FROM runs_1",
                (NO_CODE,),
            )
            db.execute("DROP TABLE runs_1")
            db.execute("UPDATE meta SET value = ? WHERE name = 'schema_version'", (str(SCHEMA_VERSION),))

    def _txn(self) -> _Txn:
        return _Txn(self._db)

    # -- writing (driver only) --------------------------------------------------------------------------------
    def put(
        self,
        key: str,
        spec: dict[str, Any],
        *,
        result: dict[str, Any] | None = None,
        error: str | None = None,
        wall_time_s: float | None = None,
    ) -> str:
        """Store one finished run (replacing an earlier row of the same key); returns its ``finished_at``.

        Exactly one of ``result`` (status 'ok') and ``error`` (status 'error', one line) is given.
        """
        with profiling.part("store"):
            return self._put(key, spec, result=result, error=error, wall_time_s=wall_time_s)

    def _put(
        self,
        key: str,
        spec: dict[str, Any],
        *,
        result: dict[str, Any] | None,
        error: str | None,
        wall_time_s: float | None,
    ) -> str:
        """:meth:`put`, untimed."""
        if (result is None) == (error is None):
            raise ValueError("give either a result or an error")
        status = "ok" if error is None else "error"
        res = None if result is None else _dumps(result)
        finished = _now()
        with self._txn():
            self._db.execute(
                "INSERT OR REPLACE INTO runs VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (key, self.code, _dumps(spec), status, res, error, wall_time_s, finished),
            )
        return finished

    # -- reading ----------------------------------------------------------------------------------------------
    def done_keys(self) -> set[str]:
        """Keys of the runs of this code that finished without error (a sweep skips them)."""
        sql = "SELECT key FROM runs WHERE status = 'ok' AND code = ?"
        return {r[0] for r in self._db.execute(sql, (self.code,))}

    def other_code(self, keys: Collection[str]) -> int:
        """How many of ``keys`` the store holds finished only by other code (or before fingerprints): runs that
        run again."""
        sql = "SELECT DISTINCT key FROM runs WHERE status = 'ok' AND code != ?"
        wanted = set(keys)
        return len(({r[0] for r in self._db.execute(sql, (self.code,))} & wanted) - self.done_keys())

    def other_code_line(self, keys: Collection[str], desc: str) -> str | None:
        """The line a command prints where runs of ``keys`` were kept by other code (None: none were)."""
        n = self.other_code(keys)
        if not n:
            return None
        runs = "run" if n == 1 else "runs"
        return (
            f"{desc}: {n:,} stored {runs} in {self.path} made by other code (another fingerprint than this code's "
            f"{self.code}, or none: an older neurowalk) run again"
        )

    def counts(self) -> dict[str, int]:
        """Rows of this code per status, e.g. ``{"ok": 10, "error": 1}``."""
        out = {"ok": 0, "error": 0}
        sql = "SELECT status, count(*) FROM runs WHERE code = ? GROUP BY status"
        out.update(dict(self._db.execute(sql, (self.code,)).fetchall()))
        return out

    def __len__(self) -> int:
        return int(self._db.execute("SELECT count(*) FROM runs WHERE code = ?", (self.code,)).fetchone()[0])

    def rows(self, status: str | None = None, keys: Collection[str] | None = None) -> list[dict[str, Any]]:
        """Every row of this code (or those of one status, or those of ``keys``) ordered by key, with ``spec`` and
        ``result`` parsed from JSON."""
        where = " WHERE code = ?" + (" AND status = ?" if status else "")
        args: tuple[str, ...] = (self.code, status) if status else (self.code,)
        if keys is None:
            found = list(self._db.execute(f"SELECT * FROM runs{where} ORDER BY key", args))
        else:
            found, wanted = [], sorted(set(keys))
            for i in range(0, len(wanted), 500):  # SQLite's limit on a statement's parameters
                chunk = wanted[i : i + 500]
                sql = f"SELECT * FROM runs{where} AND key IN ({','.join('?' * len(chunk))})"
                found += self._db.execute(sql, args + tuple(chunk)).fetchall()
            found.sort(key=lambda r: r[0])
        out = []
        for r in found:
            row = dict(zip(RUN_COLUMNS, r, strict=True))
            row["spec"] = json.loads(row["spec"])
            row["result"] = None if row["result"] is None else json.loads(row["result"])
            out.append(row)
        return out

    def results(self, status: str = "ok", keys: Collection[str] | None = None) -> dict[str, dict[str, Any]]:
        """``{key: result}`` of the runs with ``status`` (results of errored runs are None), of ``keys`` only where
        given (a shared store holds many studies' runs)."""
        return {r["key"]: r["result"] for r in self.rows(status, keys)}

    def meta(self) -> dict[str, str]:
        """The store's meta table (schema_version, created_at, neurowalk_version)."""
        return dict(self._db.execute("SELECT name, value FROM meta").fetchall())

    # -- export -----------------------------------------------------------------------------------------------
    def table(self) -> tuple[list[str], list[list[object]]]:
        """Flat table of every row of this code: meta columns, one column per spec field, one per summary key.

        Summary keys that repeat a spec field are left out (the spec column holds the value); a spec field the
        stored spec leaves out (a later switch at its default: variant, gait, engine, reflexes, ...) shows its
        default; nested values (dicts, lists) are JSON strings. Returns (column names, rows).
        """
        rows = self.rows()
        extra: dict[str, None] = {}
        for r in rows:
            for k in r["result"] or {}:
                if k not in FIELDS and k not in EXPORT_META:
                    extra[k] = None
        columns = [*EXPORT_META, *FIELDS, *extra]
        data = []
        for r in rows:
            res = r["result"] or {}
            line = [r[c] for c in EXPORT_META]
            line += [_flat(r["spec"].get(f, DEFAULTS[f])) for f in FIELDS]
            line += [_flat(res.get(k)) for k in extra]
            data.append(line)
        return columns, data

    def export(self, path: Path | str, fmt: str = "parquet") -> Path:
        """Write the flat :meth:`table` to ``path`` as 'parquet' or 'csv', atomically; return the path."""
        path = Path(path)
        columns, data = self.table()
        if fmt == "parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            arrays = [_arrow_column(pa, [row[i] for row in data]) for i in range(len(columns))]
            tab = pa.Table.from_arrays(arrays, names=columns)
            tab = tab.replace_schema_metadata({"neurowalk": json.dumps(self.meta())})
            atomic_write(path, lambda tmp: pq.write_table(tab, tmp))
        elif fmt == "csv":

            def w(tmp: str) -> None:
                with open(tmp, "w", newline="") as f:
                    out = csv.writer(f)
                    out.writerow(columns)
                    out.writerows(["" if v is None else v for v in row] for row in data)

            atomic_write(path, w)
        else:
            raise ValueError(f"unknown export format {fmt!r}; expected parquet or csv")
        return path

    def close(self) -> None:
        """Close the file (a clean close folds the write-ahead log back into it) and release the folder's lock."""
        self._db.close()
        self._lock.close()

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def count_finished(path: Path | str, keys: Collection[str] | None = None, code: str | None = None) -> int:
    """Runs of ``code`` (None: of any code, each key once) stored without error in the store at ``path``
    (only those whose key is in ``keys``, where given), read without taking its lock (0 if there is no readable store
    there): what an interrupted command reports as kept. Opened for reading and writing but only read, so that its
    close leaves no write-ahead-log files behind (a read-only connection cannot remove them)."""
    try:
        db = sqlite3.connect(f"file:{Path(path)}?mode=rw", uri=True)
    except sqlite3.Error:
        return 0
    try:
        if code is None:
            found = [k for (k,) in db.execute("SELECT DISTINCT key FROM runs WHERE status = 'ok'")]
        else:
            found = [k for (k,) in db.execute("SELECT key FROM runs WHERE status = 'ok' AND code = ?", (code,))]
        if keys is None:
            return len(found)
        wanted = set(keys)
        return sum(1 for k in found if k in wanted)
    except sqlite3.Error:
        return 0
    finally:
        db.close()


def _lock(path: Path) -> IO[bytes]:
    """Hold ``PATH.lock`` exclusively while the store is open: a second sweep or figure into the same store is refused.

    The lock is the operating system's (``flock``): it goes with the process, so a killed run leaves none behind.
    """
    try:
        f = exclusive_lock(path.with_name(path.name + ".lock"))
    except OSError as e:
        raise StoreError(f"cannot open result store {str(path)!r}: {e.strerror}") from None
    if f is None:
        raise StoreError(
            f"result store {str(path)!r} is in use by another sweep or figure; wait for it to finish "
            "or use another output folder"
        )
    return f


class _Txn:
    """``BEGIN IMMEDIATE`` … ``COMMIT`` (``ROLLBACK`` on error) on an autocommit connection."""

    def __init__(self, db: sqlite3.Connection) -> None:
        self.db = db

    def __enter__(self) -> None:
        self.db.execute("BEGIN IMMEDIATE")

    def __exit__(self, exc_type: object, *rest: object) -> None:
        self.db.execute("ROLLBACK" if exc_type else "COMMIT")


def _dumps(x: object) -> str:
    return json.dumps(to_jsonable(x), separators=(",", ":"))  # key order kept: export columns follow it


def _now() -> str:
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="microseconds")


def _flat(v: object) -> object:
    """A table cell: scalars as they are, nested values as JSON text."""
    return json.dumps(v, sort_keys=True) if isinstance(v, dict | list) else v


def _arrow_column(pa: Any, values: list[Any]) -> Any:
    """An Arrow array of ``values``; a column of mixed types becomes JSON text."""
    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError, TypeError, OverflowError):
        return pa.array([None if v is None else json.dumps(v) for v in values], type=pa.string())
