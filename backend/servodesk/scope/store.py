"""Where captures live: an SQLite index (`<root>/captures.sqlite`, WAL) of the Capture records
and one directory per capture (`<root>/<id>/`: capture.rrd, samples.parquet, exports).

Each row holds the Capture as JSON (the API's own model), so the index never drifts from what
the API shows; the schema is versioned like servodesk.storage.migrations. Every method blocks:
the scope service calls them through asyncio.to_thread. One connection, one lock.
"""

from __future__ import annotations

import builtins
import logging
import os
import shutil
import sqlite3
import threading
import time
from collections.abc import Callable
from pathlib import Path

from pydantic import ValidationError

from servodesk.errors import CaptureNotFoundError
from servodesk.models.scope import ACTIVE_STATES, Capture
from servodesk.scope.samples import is_complete

log = logging.getLogger(__name__)

FILENAME = "captures.sqlite"
RRD_NAME = "capture.rrd"
SAMPLES_NAME = "samples.parquet"
INTERRUPTED = "ServoDesk stopped during the capture; what was recorded until then is kept"
UNREADABLE_SAMPLES = (
    "the samples table was not finished (no CSV, Parquet or MF4 export); the .rrd recording "
    "has what was recorded"
)

# (version, SQL): each runs once, in order, in its own transaction; never edit one that shipped
MIGRATIONS: tuple[tuple[int, str], ...] = (
    (
        1,
        """
        CREATE TABLE captures (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            created REAL NOT NULL,
            data TEXT NOT NULL
        );
        """,
    ),
)


def migrate(db: sqlite3.Connection) -> int:
    """Bring `db` to the latest schema; returns the version it had before."""
    db.execute("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)")
    row = db.execute("SELECT MAX(version) FROM schema_version").fetchone()
    before = int(row[0]) if row and row[0] is not None else 0
    for version, sql in MIGRATIONS:
        if version > before:
            db.executescript(
                f"BEGIN; {sql}; INSERT INTO schema_version (version) VALUES ({version}); COMMIT;"
            )
    return before


class CaptureStore:
    def __init__(self, root: Path) -> None:
        self.root = root
        self.path = root / FILENAME
        self._db: sqlite3.Connection | None = None
        self._lock = threading.Lock()

    # ------------------------------------------------------------------ lifecycle

    def open(self) -> list[int]:
        """Create the directory and database; captures a previous run left armed or running
        are marked failed (their files are kept). Returns the ids so marked."""
        with self._lock:
            if self._db is not None:
                return []
            self.root.mkdir(parents=True, exist_ok=True)
            db = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
            try:
                db.execute("PRAGMA journal_mode = WAL")
                db.execute("PRAGMA synchronous = NORMAL")  # WAL: durable at checkpoints
                db.execute("PRAGMA busy_timeout = 5000")
                migrate(db)
            except BaseException:
                db.close()
                raise
            self._db = db
            rows = db.execute("SELECT id, data FROM captures ORDER BY id").fetchall()
        failed: list[int] = []
        for capture_id, data in rows:
            capture = _parse(capture_id, data)
            if capture is not None and capture.state in ACTIVE_STATES:
                self.save(self._interrupted(capture))
                failed.append(capture.id)
        return failed

    def close(self) -> None:
        with self._lock:
            db, self._db = self._db, None
            if db is not None:
                db.close()

    def _connection(self) -> sqlite3.Connection:
        if self._db is None:
            raise RuntimeError("the capture store is not open")
        return self._db

    def _interrupted(self, capture: Capture) -> Capture:
        files = self._stats(capture.id)
        notes = list(capture.notes)
        samples = self.root / str(capture.id) / SAMPLES_NAME
        if not is_complete(samples):
            notes.append(UNREADABLE_SAMPLES)
        # the newest file tells when recording stopped, near enough
        last_write = max((f.st_mtime for f in files), default=None)
        return capture.model_copy(
            update={
                "state": "failed",
                "error": INTERRUPTED,
                "ended": capture.ended or last_write or capture.started or capture.created,
                "size_bytes": sum(f.st_size for f in files),
                "notes": notes,
            }
        )

    # ------------------------------------------------------------------ records

    def create(self, build: Callable[[int], Capture]) -> Capture:
        """Reserve the next id, build the capture with it and store it, in one transaction (an
        id is never given twice, even after deletes: AUTOINCREMENT)."""
        with self._lock:
            db = self._connection()
            db.execute("BEGIN IMMEDIATE")
            try:
                cursor = db.execute(
                    "INSERT INTO captures (created, data) VALUES (?, '{}')", (time.time(),)
                )
                capture_id = cursor.lastrowid
                assert capture_id is not None  # an INSERT always has one
                capture = build(capture_id)
                if capture.id != capture_id:
                    raise ValueError(f"built capture {capture.id} for id {capture_id}")
                db.execute(
                    "UPDATE captures SET created = ?, data = ? WHERE id = ?",
                    (capture.created, capture.model_dump_json(), capture_id),
                )
                db.execute("COMMIT")
            except BaseException:
                db.execute("ROLLBACK")
                raise
        return capture

    def save(self, capture: Capture) -> None:
        """Store the capture's current record (it must exist: `create` made it)."""
        with self._lock:
            cursor = self._connection().execute(
                "UPDATE captures SET created = ?, data = ? WHERE id = ?",
                (capture.created, capture.model_dump_json(), capture.id),
            )
        if cursor.rowcount == 0:
            raise CaptureNotFoundError(capture.id)

    def get(self, capture_id: int) -> Capture:
        with self._lock:
            row = (
                self._connection()
                .execute("SELECT data FROM captures WHERE id = ?", (capture_id,))
                .fetchone()
            )
        capture = _parse(capture_id, row[0]) if row is not None else None
        if capture is None:
            raise CaptureNotFoundError(capture_id)
        return capture

    def list(self) -> builtins.list[Capture]:
        """Every capture, newest first (unreadable records are logged and left out)."""
        with self._lock:
            rows = self._connection().execute("SELECT id, data FROM captures ORDER BY id DESC")
            found = rows.fetchall()
        return [c for c in (_parse(i, data) for i, data in found) if c is not None]

    def delete(self, capture_id: int) -> None:
        """Remove the record and the capture's directory."""
        with self._lock:
            cursor = self._connection().execute("DELETE FROM captures WHERE id = ?", (capture_id,))
        if cursor.rowcount == 0:
            raise CaptureNotFoundError(capture_id)
        try:
            shutil.rmtree(self.root / str(capture_id))
        except FileNotFoundError:
            pass  # never had files
        except OSError:
            # the record is gone already; leftover files only cost space
            log.warning("capture %d: could not remove all its files", capture_id, exc_info=True)

    # ------------------------------------------------------------------ files

    def directory(self, capture_id: int) -> Path:
        """`<root>/<id>`, created when first asked for."""
        path = self.root / str(capture_id)
        path.mkdir(parents=True, exist_ok=True)
        return path

    def rrd_path(self, capture_id: int) -> Path:
        return self.directory(capture_id) / RRD_NAME

    def samples_path(self, capture_id: int) -> Path:
        return self.directory(capture_id) / SAMPLES_NAME

    def size_bytes(self, capture_id: int) -> int:
        """The bytes of every file in the capture's directory (0 when it has none)."""
        return sum(f.st_size for f in self._stats(capture_id))

    def _stats(self, capture_id: int) -> builtins.list[os.stat_result]:
        stats: builtins.list[os.stat_result] = []
        for directory, _dirs, files in os.walk(self.root / str(capture_id)):
            for name in files:
                try:
                    stats.append(os.stat(os.path.join(directory, name)))
                except FileNotFoundError:  # an export's temporary file, gone meanwhile
                    continue
        return stats


def _parse(capture_id: int, data: str) -> Capture | None:
    try:
        return Capture.model_validate_json(data)
    except ValidationError:
        log.warning("capture %d: the stored record is not readable; left out", capture_id)
        return None
