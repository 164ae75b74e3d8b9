"""The service the log routes will use: decode a log file once, keep its events for paging.

Each result is one SQLite file under `<data_dir>/logs/<id>.sqlite` holding the summary, the
totals and every event; `events(id, since, limit)` pages by the event sequence number. Events
are inserted in batches while the log streams past, so memory stays flat for any log size.
"""

from __future__ import annotations

import json
import re
import sqlite3
import uuid
from collections.abc import Callable, Iterator, Mapping
from contextlib import closing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from servodesk.logs.analysis import LogAnalysis
from servodesk.logs.events import COLUMNS, Event

INSERT_BATCH = 10_000
MAX_PAGE = 10_000
_ID = re.compile(r"^[0-9a-f]{32}$")
_SCHEMA = """
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE events (
    seq INTEGER PRIMARY KEY, time REAL NOT NULL, frame INTEGER NOT NULL, kind TEXT NOT NULL,
    node INTEGER, text TEXT NOT NULL, "index" INTEGER, subindex INTEGER, code INTEGER, data TEXT,
    polling INTEGER NOT NULL DEFAULT 0
);
"""
_INSERT = f"INSERT INTO events VALUES ({', '.join('?' * len(COLUMNS))})"


class LogNotFoundError(KeyError):
    """No decoded log with this id."""


@dataclass(frozen=True)
class LogResult:
    id: str
    name: str  # the file's name
    summary: list[str]
    stats: dict[str, Any]


@dataclass(frozen=True)
class KeptLog:
    """A decoded log on disk: what the Logs page lists (and the quota counts)."""

    id: str
    name: str  # the uploaded file's name
    size_bytes: int
    created: float  # when its decode finished (epoch s)


class LogStore:
    def __init__(self, data_dir: Path) -> None:
        self.root = data_dir / "logs"

    def decode_file(
        self,
        path: Path,
        *,
        dcf: Path | None = None,
        bitrate: int | None = None,
        progress: Callable[[int], None] | None = None,
        profiles: Mapping[int, str] | None = None,
    ) -> LogResult:
        """Decode `path` (any python-can log format) and store its events; blocking, run it
        off the event loop."""
        self.root.mkdir(parents=True, exist_ok=True)
        log_id = uuid.uuid4().hex
        target = self._path(log_id)
        partial = target.with_suffix(".partial")
        analysis = LogAnalysis(path, dcf=dcf, bitrate=bitrate, profiles=profiles)
        try:
            with closing(sqlite3.connect(partial)) as db:
                db.executescript("PRAGMA journal_mode = OFF; PRAGMA synchronous = OFF;" + _SCHEMA)
                batch: list[tuple[Any, ...]] = []
                for event in analysis.events(progress):
                    batch.append(tuple(getattr(event, c) for c in COLUMNS))
                    if len(batch) >= INSERT_BATCH:
                        db.executemany(_INSERT, batch)
                        batch.clear()
                db.executemany(_INSERT, batch)
                result = LogResult(log_id, path.name, analysis.summary(), analysis.stats())
                meta = {"name": result.name, "summary": result.summary, "stats": result.stats}
                db.executemany(
                    "INSERT INTO meta VALUES (?, ?)",
                    [(k, json.dumps(v, ensure_ascii=False)) for k, v in meta.items()],
                )
                db.commit()
            partial.rename(target)  # only a finished decode is ever visible
        finally:
            partial.unlink(missing_ok=True)
        return result

    def result(self, log_id: str) -> LogResult:
        with closing(self._open(log_id)) as db:
            meta = {k: json.loads(v) for k, v in db.execute("SELECT key, value FROM meta")}
        return LogResult(log_id, meta["name"], meta["summary"], meta["stats"])

    def events(
        self, log_id: str, since: int = 0, limit: int = 500, *, hide_polling: bool = False
    ) -> list[Event]:
        """Events with seq >= `since`, at most `limit` (≤ MAX_PAGE) of them, in order;
        without the SDO polling reads when `hide_polling`."""
        limit = max(0, min(limit, MAX_PAGE))
        with closing(self._open(log_id)) as db:
            # a log decoded before the polling column has no polling events
            known = "polling" in {row[1] for row in db.execute("PRAGMA table_info(events)")}
            where = "seq >= ? AND polling = 0" if hide_polling and known else "seq >= ?"
            rows = db.execute(
                f"SELECT * FROM events WHERE {where} ORDER BY seq LIMIT ?", (since, limit)
            ).fetchall()
        return [_event(row) for row in rows]

    def ids(self) -> Iterator[str]:
        if self.root.is_dir():
            for path in sorted(self.root.glob("*.sqlite")):
                if _ID.match(path.stem):  # a stray file in logs/ is not a decoded log
                    yield path.stem

    def kept(self) -> list[KeptLog]:
        """Every decoded log, newest first; one that vanishes meanwhile is left out."""
        found: list[KeptLog] = []
        for log_id in self.ids():
            try:
                stat = self._path(log_id).stat()
                name = self.result(log_id).name
            except (OSError, LogNotFoundError, sqlite3.Error, KeyError, ValueError):
                continue  # deleted meanwhile, or not a readable result: the quota still sees it
            found.append(KeptLog(log_id, name, stat.st_size, stat.st_mtime))
        return sorted(found, key=lambda k: (k.created, k.id), reverse=True)

    def sizes(self) -> list[tuple[str, int, float]]:
        """(id, bytes, mtime) of every result file, readable or not (what the quota counts)."""
        found: list[tuple[str, int, float]] = []
        for log_id in self.ids():
            try:
                stat = self._path(log_id).stat()
            except OSError:
                continue
            found.append((log_id, stat.st_size, stat.st_mtime))
        return found

    def delete(self, log_id: str) -> None:
        path = self._path(log_id)
        if not path.is_file():
            raise LogNotFoundError(log_id)
        path.unlink()

    def _path(self, log_id: str) -> Path:
        if not _ID.match(log_id):  # ids come from URLs: never a path of their own
            raise LogNotFoundError(log_id)
        return self.root / f"{log_id}.sqlite"

    def _open(self, log_id: str) -> sqlite3.Connection:
        path = self._path(log_id)
        if not path.is_file():
            raise LogNotFoundError(log_id)
        return sqlite3.connect(f"file:{path}?mode=ro", uri=True)


def _event(row: tuple[Any, ...]) -> Event:
    """An event from its row (SQLite stores the polling flag as 0/1)."""
    values = dict(zip(COLUMNS, row, strict=False))
    values["polling"] = bool(values.get("polling", 0))
    return Event(**values)
