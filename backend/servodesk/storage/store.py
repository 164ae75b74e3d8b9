"""The timeline and fault history in SQLite (`<data_dir>/servodesk.sqlite`, WAL).

One writer task takes everything queued since its last batch and writes it with executemany in
one transaction, in a worker thread (never on the event loop); it also prunes to the retention
(settings `events_max_rows`, `events_max_days`, `faults_max_rows`). Reads use a second
connection, also in a worker thread, so a read never waits for a batch being written (WAL).
`flush()` waits for what was queued before the call: routes call it so an answer includes every
event published before the request (read-your-writes).

An event's id is given when it is queued (one more than the last, never reused), so the live
channel can push it with the id the timeline routes will show (`id_of`), and a page that sees a
gap in the ids knows it missed some and fetches them with `since`.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import sqlite3
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from servodesk.bounded import TEXT_LIMIT, bounded_json, shorten
from servodesk.events.bus import BusEvent
from servodesk.storage.migrations import migrate

log = logging.getLogger(__name__)

FILENAME = "servodesk.sqlite"
PENDING_LIMIT = 1_000_000  # rows waiting for the writer; beyond that they are counted and lost
AGE_PRUNE_EVERY = 60.0  # s between pruning by age
FAULT_COLUMNS = (
    "time",
    "node",
    "code",
    "code_hex",
    "source",
    "name_en",
    "name_zh",
    "name_zh_source",
    "check",
    "check_zh",
    "error_register",
    "manufacturer_hex",
    "raw_hex",
    "state_before",
    "state_after",
)
_QUOTED = ", ".join(f'"{c}"' for c in FAULT_COLUMNS)  # "check" is an SQL keyword
_FAULT_INSERT = (
    f"INSERT INTO faults ({_QUOTED}, bus) VALUES ({', '.join('?' * (len(FAULT_COLUMNS) + 1))})"
)
_EVENT_INSERT = (
    "INSERT INTO events (id, time, kind, node, message, data, bus, message_id, params)"
    " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)"
)
_EVENT_INSERT_NEW_ID = (
    "INSERT INTO events (time, kind, node, message, data, bus, message_id, params)"
    " VALUES (?, ?, ?, ?, ?, ?, ?, ?)"
)


@dataclass(frozen=True)
class Retention:
    max_events: int = 200_000
    max_days: float = 30.0
    max_faults: int = 50_000


def _params(stored: str | None) -> dict[str, str | int]:
    loaded = json.loads(stored) if stored else {}
    return loaded if isinstance(loaded, dict) else {}


def _params_json(item: BusEvent) -> str | None:
    """An event's message parameters as stored: short values (ids, numbers, object
    addresses); a long one is cut like the message."""
    if item.message_id is None:
        return None
    params = {
        key: shorten(value, TEXT_LIMIT) if isinstance(value, str) else value
        for key, value in item.params.items()
    }
    return json.dumps(params, ensure_ascii=False)


@dataclass(frozen=True)
class StoredEvent:
    id: int
    time: float
    kind: str
    node: int | None
    message: str
    data: dict[str, Any]
    bus: str | None = None  # the bus it came from (None: stored before buses were recorded)
    message_id: str | None = None  # the words by id (events/texts.py); None: English only
    params: dict[str, str | int] = field(default_factory=dict)


def _connect(path: Path) -> sqlite3.Connection:
    db = sqlite3.connect(path, check_same_thread=False, isolation_level=None)
    db.execute("PRAGMA journal_mode = WAL")
    db.execute("PRAGMA synchronous = NORMAL")  # WAL: durable at checkpoints, never corrupt
    db.execute("PRAGMA busy_timeout = 5000")
    return db


class Storage:
    def __init__(
        self,
        data_dir: Path,
        retention: Retention | None = None,
        *,
        bus_of: Callable[[], str | None] | None = None,
    ) -> None:
        self.path = data_dir / FILENAME
        self.retention = retention or Retention()
        # names the bus each event is stored with ("socketcan can0"): another server may share
        # this data directory, and each shows its own bus's timeline
        self._bus_of = bus_of or (lambda: None)
        self._writer: sqlite3.Connection | None = None
        self._reader: sqlite3.Connection | None = None
        self._read_lock = threading.Lock()  # one read at a time on the read connection
        self._events: list[tuple[Any, ...]] = []
        self._faults: list[tuple[Any, ...]] = []
        self._queued = 0  # rows queued since start
        self._written = 0  # rows written (or dropped by a failed batch)
        self._progress: asyncio.Condition | None = None
        self._wake: asyncio.Event | None = None
        self._task: asyncio.Task[None] | None = None
        self._pruned_at = 0.0
        self.dropped = 0
        self._next_id: int | None = None  # known once the database is open
        self._last: tuple[BusEvent, int] | None = None  # the event queued last and its id
        self._taken_to = 0  # the highest id another server sharing the database wrote

    # ------------------------------------------------------------------ lifecycle

    async def start(self) -> None:
        try:
            next_id = await asyncio.to_thread(self._open)
        except (sqlite3.Error, OSError) as error:
            # a full disk must not keep the server (and its stops) from starting: the timeline
            # is live only (the WebSocket) until a restart finds the database writable
            log.error("the timeline cannot be opened in %s (%s): events are not stored",
                      self.path.parent, error)  # fmt: skip
            await asyncio.to_thread(self._close_connections)
            next_id = 1
        # events queued before the database was open get their ids now, in order
        for i, row in enumerate(self._events):
            self._events[i] = (next_id, *row[1:])
            next_id += 1
        self._next_id = next_id
        self._progress = asyncio.Condition()
        self._wake = asyncio.Event()
        self._task = asyncio.get_running_loop().create_task(self._run(), name="storage-writer")

    def _open(self) -> int:
        """Open both connections; returns the id the next event gets."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._writer = _connect(self.path)
        migrate(self._writer)
        self._reader = _connect(self.path)
        # AUTOINCREMENT's counter: ids of pruned events are never given again
        row = self._writer.execute(
            "SELECT MAX(n) FROM (SELECT seq AS n FROM sqlite_sequence WHERE name = 'events'"
            " UNION ALL SELECT MAX(id) FROM events)"
        ).fetchone()
        return int(row[0] or 0) + 1

    async def close(self) -> None:
        task, self._task = self._task, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
            await self._write_pending()  # what was queued last is not lost at shutdown
        await asyncio.to_thread(self._close_connections)

    def _close_connections(self) -> None:
        for db in (self._writer, self._reader):
            if db is not None:
                db.close()
        self._writer = self._reader = None

    # ------------------------------------------------------------------ writing (on the loop)

    def add_event(self, item: BusEvent) -> None:
        """Queue an event for the timeline (a bus subscriber: no I/O here) and give it its id
        (`id_of`). Its words and detail are stored bounded, whatever a client sent."""
        data = bounded_json(item.data)
        event_id = self._next_id
        if event_id is not None and event_id <= self._taken_to:
            event_id = self._taken_to + 1  # another server wrote up to there
        if event_id is not None:
            self._next_id = event_id + 1
            self._last = (item, event_id)
        self._queue(
            self._events,
            (event_id, item.time, item.kind.value, item.node, shorten(item.message, TEXT_LIMIT),
             data, self._bus_of(), item.message_id, _params_json(item)),
        )  # fmt: skip

    def bus(self) -> str | None:
        """The bus new events and faults are stored with (None: none configured yet)."""
        return self._bus_of()

    def id_of(self, item: BusEvent) -> int | None:
        """The id `add_event` gave `item`, asked by a later subscriber of the same publish (the
        live channel); None before the database is open."""
        last = self._last
        return last[1] if last is not None and last[0] is item else None

    def add_fault(self, fault: dict[str, Any]) -> None:
        """Queue a fault record (the API's Fault fields plus state_before/state_after), stored
        with the bus it came from."""
        self._queue(self._faults, (*(fault.get(c) for c in FAULT_COLUMNS), self._bus_of()))

    def _queue(self, rows: list[tuple[Any, ...]], row: tuple[Any, ...]) -> None:
        if len(self._events) + len(self._faults) >= PENDING_LIMIT:
            self.dropped += 1
            return
        rows.append(row)
        self._queued += 1
        if self._wake is not None:
            self._wake.set()

    async def flush(self) -> None:
        """Wait until everything queued before this call is written."""
        target, progress = self._queued, self._progress
        if progress is None or self._task is None:
            return
        async with progress:
            await progress.wait_for(lambda: self._written >= target or self._task is None)

    async def _run(self) -> None:
        assert self._wake is not None
        while True:
            await self._wake.wait()
            self._wake.clear()
            await self._write_pending()

    async def _write_pending(self) -> None:
        events, self._events = self._events, []
        faults, self._faults = self._faults, []
        if events or faults:
            try:
                await asyncio.to_thread(self._write, events, faults)
            except sqlite3.Error:
                log.exception("writing %d events, %d faults failed", len(events), len(faults))
            self._written += len(events) + len(faults)
        if self._progress is not None:
            async with self._progress:
                self._progress.notify_all()

    def _write(self, events: list[tuple[Any, ...]], faults: list[tuple[Any, ...]]) -> None:
        db = self._writer
        if db is None:
            return
        db.execute("BEGIN")
        try:
            if events:
                self._insert_events(db, events)
            if faults:
                db.executemany(_FAULT_INSERT, faults)
            self._prune(db)
            db.execute("COMMIT")
        except BaseException:
            if db.in_transaction:  # SQLite already rolled back a full disk's transaction
                db.execute("ROLLBACK")
            raise

    def _insert_events(self, db: sqlite3.Connection, events: list[tuple[Any, ...]]) -> None:
        """Store the events under the ids they were given; where another server sharing this
        database took an id meanwhile, under a new one (the next ids given follow it)."""
        db.execute("SAVEPOINT events")
        try:
            db.executemany(_EVENT_INSERT, events)
        except sqlite3.IntegrityError:
            db.execute("ROLLBACK TO events")
            for row in events:
                taken = db.execute("SELECT 1 FROM events WHERE id = ?", (row[0],)).fetchone()
                db.execute(*((_EVENT_INSERT_NEW_ID, row[1:]) if taken else (_EVENT_INSERT, row)))
            newest = db.execute("SELECT MAX(id) FROM events").fetchone()[0]
            self._taken_to = int(newest)  # read on the loop by add_event
        db.execute("RELEASE events")

    def _prune(self, db: sqlite3.Connection) -> None:
        keep = self.retention
        for table, limit in (("events", keep.max_events), ("faults", keep.max_faults)):
            # ids grow by one per row: everything below (newest id - limit) is beyond the bound
            db.execute(
                f"DELETE FROM {table} WHERE id <= (SELECT MAX(id) FROM {table}) - ?", (limit,)
            )
        now = time.time()
        if now - self._pruned_at >= AGE_PRUNE_EVERY:
            self._pruned_at = now
            oldest = now - keep.max_days * 86400
            db.execute("DELETE FROM events WHERE time < ?", (oldest,))
            db.execute("DELETE FROM faults WHERE time < ?", (oldest,))

    # ------------------------------------------------------------------ reading (off the loop)

    async def events(
        self,
        *,
        node: int | None = None,
        kind: str | None = None,
        since: int | None = None,
        before: int | None = None,
        limit: int = 100,
        bus: str | None = None,
    ) -> list[StoredEvent]:
        """With `since`: events with id > since, oldest first. Otherwise the newest first,
        below `before` when given. `bus`: only that bus's events (None: every bus's)."""
        where: list[str] = []
        args: list[Any] = []
        for clause, value in (
            ("node = ?", node),
            ("kind = ?", kind),
            ("bus = ?", bus),
            ("id > ?", since),
            ("id < ?", before),
        ):
            if value is not None:
                where.append(clause)
                args.append(value)
        order = "ASC" if since is not None else "DESC"
        sql = "SELECT id, time, kind, node, message, data, bus, message_id, params FROM events"
        if where:
            sql += " WHERE " + " AND ".join(where)
        sql += f" ORDER BY id {order} LIMIT ?"
        rows = await self._read(sql, (*args, limit))
        return [
            StoredEvent(r[0], r[1], r[2], r[3], r[4], json.loads(r[5]), r[6], r[7], _params(r[8]))
            for r in rows
        ]

    async def faults(
        self, node: int | None, limit: int, *, bus: str | None = None
    ) -> tuple[list[dict[str, Any]], int]:
        """The newest `limit` faults (of `node`, or all), newest first, and how many exist.
        `bus`: only that bus's faults (None: every bus's)."""
        cols = f"{_QUOTED}, bus"
        clauses = [(c, v) for c, v in (("node = ?", node), ("bus = ?", bus)) if v is not None]
        where = " WHERE " + " AND ".join(c for c, _ in clauses) if clauses else ""
        args = tuple(v for _, v in clauses)
        # one snapshot: an EMCY stored between the two reads would make `total` disagree
        # with the rows (2000 counted, 1995 listed during a storm)
        rows, total = await self._read_together(
            (f"SELECT {cols} FROM faults{where} ORDER BY id DESC LIMIT ?", (*args, limit)),
            (f"SELECT COUNT(*) FROM faults{where}", args),
        )
        count = int(total[0][0]) if total else 0
        return [dict(zip((*FAULT_COLUMNS, "bus"), row, strict=True)) for row in rows], count

    async def _read_together(
        self, *queries: tuple[str, tuple[Any, ...]]
    ) -> list[list[tuple[Any, ...]]]:
        """Several reads from one snapshot of the database (one read transaction)."""

        def run() -> list[list[tuple[Any, ...]]]:
            db = self._reader
            if db is None:
                return [[] for _ in queries]  # not open (a full disk at start-up): nothing kept
            with self._read_lock:
                db.execute("BEGIN")
                try:
                    return [db.execute(sql, args).fetchall() for sql, args in queries]
                finally:
                    db.execute("COMMIT")

        return await asyncio.to_thread(run)

    async def _read(self, sql: str, args: tuple[Any, ...]) -> list[tuple[Any, ...]]:
        def run() -> list[tuple[Any, ...]]:
            db = self._reader
            if db is None:
                return []
            with self._read_lock:
                return db.execute(sql, args).fetchall()

        return await asyncio.to_thread(run)
