"""Commissioning records in the app's SQLite database (`<data_dir>/servodesk.sqlite`, table
`commissioning`, storage/migrations.py version 4). A record is small and changes a step at a
time, so each change rewrites its JSON in one statement; one worker thread does every query,
never the event loop."""

from __future__ import annotations

import asyncio
import sqlite3
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import TypeVar

from servodesk.models.commissioning import CommissioningRecord
from servodesk.storage.migrations import migrate
from servodesk.storage.store import FILENAME

T = TypeVar("T")
LIST_LIMIT = 1000  # records a list answers with, newest first


class RecordStore:
    def __init__(self, data_dir: Path) -> None:
        self.path = data_dir / FILENAME
        self._thread = ThreadPoolExecutor(max_workers=1, thread_name_prefix="commissioning")
        self._db: sqlite3.Connection | None = None

    async def _call(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        return await asyncio.wrap_future(self._thread.submit(lambda: fn(self._conn())))

    def _conn(self) -> sqlite3.Connection:
        # opened on first use: the timeline store has migrated the file by then (Services.open)
        if self._db is None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            db = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
            db.execute("PRAGMA journal_mode = WAL")
            db.execute("PRAGMA synchronous = FULL")  # a signed step is on disk when answered
            db.execute("PRAGMA busy_timeout = 5000")
            migrate(db)  # a no-op when the timeline store did it; not when it could not open
            self._db = db
        return self._db

    async def add(self, record: CommissioningRecord) -> CommissioningRecord:
        """Insert `record` (its id is ignored) and return it with the id it was given."""

        def insert(db: sqlite3.Connection) -> int:
            cursor = db.execute(
                "INSERT INTO commissioning (node, created, record) VALUES (?, ?, '{}')",
                (record.node, record.created),
            )
            if cursor.lastrowid is None:
                raise RuntimeError("SQLite gave the commissioning record no id")
            return cursor.lastrowid

        new_id = await self._call(insert)
        saved = record.model_copy(update={"id": new_id})
        await self.save(saved)
        return saved

    async def save(self, record: CommissioningRecord) -> None:
        text = record.model_dump_json()
        await self._call(
            lambda db: db.execute(
                "UPDATE commissioning SET record = ? WHERE id = ?", (text, record.id)
            )
        )

    async def get(self, record_id: int) -> CommissioningRecord | None:
        def one(db: sqlite3.Connection) -> str | None:
            row = db.execute("SELECT record FROM commissioning WHERE id = ?", (record_id,))
            found = row.fetchone()
            return None if found is None else str(found[0])

        text = await self._call(one)
        return None if text is None else CommissioningRecord.model_validate_json(text)

    async def list(self, node: int | None = None) -> list[CommissioningRecord]:
        def rows(db: sqlite3.Connection) -> list[str]:
            where, args = ("WHERE node = ? ", [node]) if node is not None else ("", [])
            sql = f"SELECT record FROM commissioning {where}ORDER BY id DESC LIMIT ?"
            return [str(r[0]) for r in db.execute(sql, [*args, LIST_LIMIT])]

        return [CommissioningRecord.model_validate_json(t) for t in await self._call(rows)]

    def close(self) -> None:
        def shut() -> None:
            if self._db is not None:
                self._db.close()
                self._db = None

        self._thread.submit(shut).result()
        self._thread.shutdown(wait=True)
