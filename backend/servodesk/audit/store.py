"""The audit log on disk: SQLite (`<data_dir>/audit.sqlite`, WAL, synchronous FULL), append-only.

An entry is two rows: its begin row, written before the write is sent, and its result row,
written after. Neither is ever changed or deleted: triggers refuse UPDATE and DELETE, and a
result row's primary key is its entry, so no entry gets a second result. An entry whose result
row is missing at start-up (the server died mid-write) gets the result "unknown".

Blocking SQLite calls run on this store's one thread, in the order they were submitted; a
stop submits its begin row without waiting for it (`begin(..., wait=False)`). A row that
cannot be written (disk full, read-only, I/O error) fails its future with AuditUnavailableError.
"""

from __future__ import annotations

import contextlib
import json
import sqlite3
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from servodesk.audit.csv_cells import csv_rows
from servodesk.audit.entry import AuditValue, Outcome, Pending
from servodesk.audit.errors import AlreadyUndoneError, unavailable
from servodesk.bounded import TEXT_LIMIT, is_shortened, shorten

FILENAME = "audit.sqlite"
CRASHED = "the server stopped before this write completed: check the drive's value"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS entries (
    id INTEGER PRIMARY KEY,
    time REAL NOT NULL,
    user TEXT NOT NULL,
    role TEXT NOT NULL,
    client TEXT,
    node INTEGER,
    action TEXT NOT NULL,
    what TEXT NOT NULL,
    new TEXT,
    undo_of INTEGER
);
CREATE TABLE IF NOT EXISTS results (
    entry INTEGER PRIMARY KEY REFERENCES entries(id),
    time REAL NOT NULL,
    result TEXT NOT NULL,
    what TEXT NOT NULL,
    obj_index INTEGER,
    obj_subindex INTEGER,
    old TEXT,
    new TEXT,
    abort_code TEXT,
    error TEXT,
    message TEXT,
    undoable INTEGER NOT NULL
);
CREATE INDEX IF NOT EXISTS entries_node ON entries(node, id);
CREATE INDEX IF NOT EXISTS entries_time ON entries(time);
CREATE INDEX IF NOT EXISTS entries_undo_of ON entries(undo_of) WHERE undo_of IS NOT NULL;
CREATE TRIGGER IF NOT EXISTS entries_append_only_u BEFORE UPDATE ON entries
    BEGIN SELECT RAISE(ABORT, 'the audit log is append-only'); END;
CREATE TRIGGER IF NOT EXISTS entries_append_only_d BEFORE DELETE ON entries
    BEGIN SELECT RAISE(ABORT, 'the audit log is append-only'); END;
CREATE TRIGGER IF NOT EXISTS results_append_only_u BEFORE UPDATE ON results
    BEGIN SELECT RAISE(ABORT, 'the audit log is append-only'); END;
CREATE TRIGGER IF NOT EXISTS results_append_only_d BEFORE DELETE ON results
    BEGIN SELECT RAISE(ABORT, 'the audit log is append-only'); END;
"""

_SELECT = """
SELECT e.id, e.time, r.time, e.user, e.role, e.client, e.node, e.action,
       COALESCE(r.what, e.what), r.obj_index, r.obj_subindex, r.old, COALESCE(r.new, e.new),
       COALESCE(r.result, 'pending'), r.abort_code, r.error, r.message, e.undo_of,
       COALESCE(r.undoable, 0),
       (SELECT MIN(u.id) FROM entries u LEFT JOIN results ur ON ur.entry = u.id
        WHERE u.undo_of = e.id AND COALESCE(ur.result, 'pending') IN ('ok', 'pending'))
FROM entries e LEFT JOIN results r ON r.entry = e.id
"""
# The undo that took (or is taking) an entry back: one that succeeded or is still running. A
# failed or interrupted ("unknown") undo leaves the entry to be undone again.
_UNDONE_BY = """
SELECT e.id, e.user, COALESCE(r.result, 'pending') FROM entries e
LEFT JOIN results r ON r.entry = e.id
WHERE e.undo_of = ? AND COALESCE(r.result, 'pending') IN ('ok', 'pending')
ORDER BY e.id LIMIT 1
"""
CSV_COLUMNS = (
    "id",
    "time",
    "finished",
    "user",
    "role",
    "client",
    "node",
    "action",
    "what",
    "index",
    "subindex",
    "old",
    "new",
    "result",
    "abort_code",
    "error",
    "message",
    "undo_of",
)


@dataclass(frozen=True)
class AuditRow:
    id: int
    time: float
    finished: float | None
    user: str
    role: str
    client: str | None
    node: int | None
    action: str
    what: str
    index: int | None
    subindex: int | None
    old: AuditValue
    new: AuditValue
    result: str
    abort_code: str | None
    error: str | None
    message: str | None
    undo_of: int | None
    undoable: bool
    undone_by: int | None = None  # the undo entry that took this one back (or is doing so)


@dataclass(frozen=True)
class AuditFilter:
    node: int | None = None
    since: float | None = None  # unix time, inclusive
    until: float | None = None
    user: str | None = None
    action: str | None = None
    before: int | None = None  # ids below this one (paging back)
    limit: int = 100

    def where(self) -> tuple[str, list[Any]]:
        terms: list[str] = []
        args: list[Any] = []
        for column, value in (
            ("e.node = ?", self.node),
            ("e.time >= ?", self.since),
            ("e.time <= ?", self.until),
            ("e.user = ?", self.user),
            ("e.action = ?", self.action),
            ("e.id < ?", self.before),
        ):
            if value is not None:
                terms.append(column)
                args.append(value)
        return (" WHERE " + " AND ".join(terms)) if terms else "", args


def _dump(value: AuditValue) -> str | None:
    """A value as stored: a long text shortened, its length noted (bounded.py)."""
    if value is None:
        return None
    return json.dumps(shorten(value) if isinstance(value, str) else value)


def _text(words: str | None) -> str | None:
    return None if words is None else shorten(words, TEXT_LIMIT)


def _undoable(entry: Pending) -> bool:
    # an old text kept shortened is not the value it replaced: writing it back would be wrong
    old = entry.old
    return entry.undoable and not (isinstance(old, str) and is_shortened(old))


def _load(text: str | None) -> AuditValue:
    if text is None:
        return None
    value = json.loads(text)
    return value if isinstance(value, int | float | str) else str(value)


def _row(raw: tuple[Any, ...]) -> AuditRow:
    (id_, begun, finished, user, role, client, node, action, what, index, subindex, old, new,
     result, abort_code, error, message, undo_of, undoable, undone_by) = raw  # fmt: skip
    return AuditRow(
        id_, begun, finished, user, role, client, node, action, what, index, subindex,
        _load(old), _load(new), result, abort_code, error, message, undo_of, bool(undoable),
        undone_by,
    )  # fmt: skip


class AuditStore:
    def __init__(self, data_dir: Path) -> None:
        self.path = data_dir / FILENAME
        self._thread = ThreadPoolExecutor(max_workers=1, thread_name_prefix="audit")
        self._db: sqlite3.Connection | None = None
        self._opening_failed = False

    # --- on the store's thread -------------------------------------------------------------

    def _open(self) -> int:
        try:
            return self._connect()
        except (sqlite3.Error, OSError) as error:
            self._opening_failed = True  # the next write tries again (space may be freed)
            raise unavailable(error, self.path.parent) from error

    def _connect(self) -> int:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        db = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
        try:
            db.execute("PRAGMA journal_mode = WAL")
            db.execute("PRAGMA synchronous = FULL")  # an entry is on disk before it is sent
            db.executescript(_SCHEMA)
            orphans = db.execute(
                "SELECT e.id, e.what, e.new FROM entries e LEFT JOIN results r "
                "ON r.entry = e.id WHERE r.entry IS NULL"
            ).fetchall()
            now = time.time()
            db.executemany(
                "INSERT INTO results (entry, time, result, what, new, message, undoable) "
                "VALUES (?, ?, 'unknown', ?, ?, ?, 0)",
                [(id_, now, what, new, CRASHED) for id_, what, new in orphans],
            )
        except BaseException:
            db.close()
            raise
        self._db = db
        return len(orphans)

    def _conn(self) -> sqlite3.Connection:
        if self._db is None and self._opening_failed:
            self._open()  # it could not open at start-up (disk full): try again
        if self._db is None:
            raise RuntimeError("the audit log is not open")  # a bug of ours, not the user's
        return self._db

    def _begin(self, entry: Pending, when: float) -> int:
        try:
            return self._insert_begin(entry, when)
        except (sqlite3.Error, OSError) as error:
            raise unavailable(error, self.path.parent) from error

    def _insert_begin(self, entry: Pending, when: float) -> int:
        db = self._conn()
        if entry.undo_of is None:
            return self._insert_entry(db, entry, when)
        # An undo claims its entry: the check and the insert in one write transaction, so of
        # several undos of one entry (this process's or another's) exactly one is entered.
        db.execute("BEGIN IMMEDIATE")
        try:
            taken = db.execute(_UNDONE_BY, (entry.undo_of,)).fetchone()
            if taken is not None:
                raise AlreadyUndoneError(entry.undo_of, *taken)
            row = self._insert_entry(db, entry, when)
        except BaseException:
            with contextlib.suppress(sqlite3.Error):  # the error that got here says more
                db.execute("ROLLBACK")
            raise
        db.execute("COMMIT")
        return row

    @staticmethod
    def _insert_entry(db: sqlite3.Connection, entry: Pending, when: float) -> int:
        actor = entry.actor
        cursor = db.execute(
            "INSERT INTO entries (time, user, role, client, node, action, what, new, undo_of) "
            "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (when, _text(actor.user), actor.role.label, _text(actor.client), entry.node,
             _text(entry.action), _text(entry.what), _dump(entry.new), entry.undo_of),
        )  # fmt: skip
        if cursor.lastrowid is None:
            raise RuntimeError("SQLite gave the audit entry no id")
        return cursor.lastrowid

    def _finish(self, entry: Pending, outcome: Outcome, when: float) -> None:
        row = entry.row.result()  # a begin row that failed fails its result the same way
        try:
            self._insert_result(row, entry, outcome, when)
        except (sqlite3.Error, OSError) as error:
            raise unavailable(error, self.path.parent) from error

    def _insert_result(self, row: int, entry: Pending, outcome: Outcome, when: float) -> None:
        self._conn().execute(
            "INSERT INTO results (entry, time, result, what, obj_index, obj_subindex, old, new, "
            "abort_code, error, message, undoable) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (row, when, outcome.result, _text(entry.what), entry.index, entry.subindex,
             _dump(entry.old), _dump(entry.new), outcome.abort_code, _text(outcome.error),
             _text(outcome.message), int(outcome.result == "ok" and _undoable(entry))),
        )  # fmt: skip

    def _query(self, filters: AuditFilter) -> list[AuditRow]:
        where, args = filters.where()
        sql = f"{_SELECT}{where} ORDER BY e.id DESC LIMIT ?"
        return [_row(r) for r in self._conn().execute(sql, [*args, filters.limit])]

    def _get(self, entry_id: int) -> AuditRow | None:
        raw = self._conn().execute(f"{_SELECT} WHERE e.id = ?", (entry_id,)).fetchone()
        return None if raw is None else _row(raw)

    def _csv_chunk(self, filters: AuditFilter, after: int) -> tuple[str, int | None]:
        """Up to 1000 rows (oldest first) past id `after`, as CSV text; the last id or None."""
        where, args = filters.where()
        joiner = " AND " if where else " WHERE "
        sql = f"{_SELECT}{where}{joiner}e.id > ? ORDER BY e.id LIMIT 1000"
        rows = [_row(r) for r in self._conn().execute(sql, [*args, after])]
        text = csv_rows(
            [row.id, _iso(row.time), _iso(row.finished), row.user, row.role, row.client,
             row.node, row.action, row.what, _hex(row.index, 4), _hex(row.subindex, 2),
             row.old, row.new, row.result, row.abort_code, row.error, row.message,
             row.undo_of]
            for row in rows
        )  # fmt: skip
        return text, rows[-1].id if rows else None

    # --- the async side --------------------------------------------------------------------

    def submit_open(self) -> Future[int]:
        return self._thread.submit(self._open)

    def submit_begin(self, entry: Pending) -> Future[int]:
        return self._thread.submit(self._begin, entry, time.time())

    def submit_finish(self, entry: Pending, outcome: Outcome) -> Future[None]:
        return self._thread.submit(self._finish, entry, outcome, time.time())

    def submit_query(self, filters: AuditFilter) -> Future[list[AuditRow]]:
        return self._thread.submit(self._query, filters)

    def submit_get(self, entry_id: int) -> Future[AuditRow | None]:
        return self._thread.submit(self._get, entry_id)

    def submit_csv_chunk(self, filters: AuditFilter, after: int) -> Future[tuple[str, int | None]]:
        return self._thread.submit(self._csv_chunk, filters, after)

    def close(self) -> None:
        """After everything submitted so far (the last results) is written."""

        def shut() -> None:
            if self._db is not None:
                self._db.close()
                self._db = None

        self._thread.submit(shut)
        self._thread.shutdown(wait=True)


def csv_header() -> str:
    return csv_rows([CSV_COLUMNS])


def _iso(when: float | None) -> str:
    if when is None:
        return ""
    return time.strftime("%Y-%m-%dT%H:%M:%S", time.gmtime(when)) + f".{int(when % 1 * 1000):03d}Z"


def _hex(value: int | None, digits: int) -> str:
    return "" if value is None else f"{value:0{digits}X}"
