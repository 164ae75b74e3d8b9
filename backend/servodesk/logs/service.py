"""What the log routes use: an uploaded log decoded in a worker process (a bounded number at a
time, decode_worker.py), paged, exported; the stored results are LogStore's (store.py)."""

from __future__ import annotations

import asyncio
import dataclasses
import json
import logging
import os
import re
import tempfile
from collections.abc import Callable, Collection
from pathlib import Path
from typing import ParamSpec, TypeVar

from servodesk.errors import InvalidValueError, NotFoundError
from servodesk.logs.context import parse_profiles
from servodesk.logs.decode_worker import DecodePool, LogReadError, LogRefusedError
from servodesk.logs.events import Event
from servodesk.logs.export import ExportFormat, ParquetWriter, text_writer
from servodesk.logs.reader import SUFFIXES
from servodesk.logs.store import MAX_PAGE, KeptLog, LogNotFoundError, LogResult, LogStore
from servodesk.storage.quota import Kept, describe_bytes, over_quota

log = logging.getLogger(__name__)
P = ParamSpec("P")
T = TypeVar("T")

_SAFE = re.compile(r"[^A-Za-z0-9._-]+")
EXPORT_TYPES = {
    ExportFormat.CSV: "text/csv",
    ExportFormat.JSON: "application/x-ndjson",
    ExportFormat.PARQUET: "application/vnd.apache.parquet",
}


def _safe_name(name: str, fallback: str) -> str:
    """The upload's own name, reduced to a harmless file name (its suffix picks the reader)."""
    cleaned = _SAFE.sub("_", Path(name).name).strip("._") or fallback
    return cleaned[-100:]


class LogService:
    def __init__(
        self, data_dir: Path, *, max_concurrent: int, keep_bytes: int | None = None
    ) -> None:
        self.store = LogStore(data_dir)
        self.keep_bytes = keep_bytes  # decoded logs beyond this go, oldest first (None: all kept)
        self._data_dir = data_dir
        self._spool = data_dir / "uploads"
        self._max = max_concurrent
        self._slots: asyncio.Semaphore | None = None
        self._workers = DecodePool(max_concurrent)

    def close(self) -> None:
        self._workers.close()

    async def decode(
        self,
        name: str,
        data: bytes,
        dcf: tuple[str, bytes] | None = None,
        profiles: str | None = None,
    ) -> LogResult:
        """Decode an uploaded log (its suffix names the format) off the event loop; at most
        `max_concurrent` decodes run at once, the others wait their turn. `profiles` names
        nodes' drives: "1=mdi-s1c, 2=kinco"."""
        try:
            named = parse_profiles(profiles)
        except ValueError as error:
            raise InvalidValueError(f"profiles: {error}") from None
        name = _safe_name(name, "upload.log")
        if not name.lower().endswith(SUFFIXES):
            raise InvalidValueError(
                f"{name}: not a CAN log this tool reads (it reads {', '.join(SUFFIXES)})"
            )
        if self._slots is None:
            self._slots = asyncio.Semaphore(self._max)
        async with self._slots:
            tmp, path, dcf_path = await asyncio.to_thread(self._spool_files, name, data, dcf)
            try:
                result = await self._workers.decode(self._data_dir, path, dcf_path, named)
            except LogRefusedError as error:
                log.warning("refused %s: %s", name, error)
                raise InvalidValueError(f"{name}: {error}") from None
            except LogReadError as error:
                log.info("decoding %s failed: %s", name, error)
                raise InvalidValueError(
                    f"{name}: could not be read as a CAN log: {error}"
                ) from None
            finally:
                await asyncio.to_thread(tmp.cleanup)
        removed = await self.prune(protect={result.id})
        if removed:  # said with the result, so the user learns why an older one is gone
            note = pruned_note(removed, self.keep_bytes or 0)
            result = dataclasses.replace(result, summary=[*result.summary, note])
        return result

    async def open(self) -> None:
        """Start-up: decoded logs beyond the quota go (it may have been lowered)."""
        await self.prune()

    async def kept(self) -> list[KeptLog]:
        return await asyncio.to_thread(self.store.kept)

    async def delete(self, log_id: str) -> None:
        await asyncio.to_thread(self._guard, self.store.delete, log_id)

    async def prune(self, protect: Collection[str] = ()) -> list[Kept]:
        """Delete the oldest decoded logs until the rest fit the quota (`protect`: stays)."""
        keep = self.keep_bytes
        if keep is None:
            return []
        return await asyncio.to_thread(self._prune, keep, protect)

    def _prune(self, keep: int, protect: Collection[str]) -> list[Kept]:
        kept = {i: Kept(i, size, made) for i, size, made in self.store.sizes()}
        removed: list[Kept] = []
        for log_id in over_quota(list(kept.values()), keep, protect):
            item = kept[log_id]
            try:
                self.store.delete(item.id)
            except (OSError, LogNotFoundError):
                continue  # gone already, or cannot go: the next prune tries again
            removed.append(item)
        if removed:
            log.info("logs: %s", pruned_note(removed, keep))
        return removed

    def _spool_files(
        self, name: str, data: bytes, dcf: tuple[str, bytes] | None
    ) -> tuple[tempfile.TemporaryDirectory[str], Path, Path | None]:
        """The upload (and its DCF) as files for the worker process."""
        self._spool.mkdir(parents=True, exist_ok=True)
        tmp = tempfile.TemporaryDirectory(dir=self._spool)
        path = Path(tmp.name) / name
        path.write_bytes(data)
        dcf_path: Path | None = None
        if dcf is not None:
            dcf_path = Path(tmp.name) / ("dcf-" + _safe_name(dcf[0], "upload.dcf"))
            dcf_path.write_bytes(dcf[1])
        return tmp, path, dcf_path

    async def result(self, log_id: str) -> LogResult:
        return await asyncio.to_thread(self._guard, self.store.result, log_id)

    async def events(
        self, log_id: str, since: int, limit: int, *, hide_polling: bool = False
    ) -> list[Event]:
        return await asyncio.to_thread(
            self._guard, self.store.events, log_id, since, limit, hide_polling=hide_polling
        )

    async def export(self, log_id: str, fmt: ExportFormat) -> Path:
        """Every event of the log in a temporary file (the caller deletes it)."""
        return await asyncio.to_thread(self._guard, self._export, log_id, fmt)

    def _export(self, log_id: str, fmt: ExportFormat) -> Path:
        self.store.result(log_id)  # LogNotFoundError before a file is made
        self._spool.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(dir=self._spool, suffix=f".{fmt.value}")
        os.close(fd)
        path = Path(name)
        try:
            if fmt is ExportFormat.PARQUET:
                writer = ParquetWriter(path)
                self._write_pages(log_id, writer.write)
                writer.close()
            else:
                with path.open("w", encoding="utf-8", newline="") as out:
                    text = text_writer(fmt, out)
                    self._write_pages(log_id, text.write)
                    text.close()
        except BaseException:
            path.unlink(missing_ok=True)
            raise
        return path

    def _write_pages(self, log_id: str, write: Callable[[Event], None]) -> None:
        since = 0
        while True:
            page = self.store.events(log_id, since, MAX_PAGE)
            for item in page:
                write(item)
            if len(page) < MAX_PAGE:
                return
            since = page[-1].seq + 1

    @staticmethod
    def _guard(fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        try:
            return fn(*args, **kwargs)
        except LogNotFoundError:
            raise NotFoundError("log_not_found", "no decoded log with this id") from None


def pruned_note(removed: list[Kept], keep_bytes: int) -> str:
    """'removed 2 older decoded logs (150.0 MB) to keep decoded logs within 2.0 GB'."""
    size = describe_bytes(sum(k.size for k in removed))
    what = "an older decoded log" if len(removed) == 1 else f"{len(removed)} older decoded logs"
    return f"removed {what} ({size}) to keep decoded logs within {describe_bytes(keep_bytes)}"


def event_data(item: Event) -> object:
    """The event's JSON detail as JSON (a fault record, PDO values) or its text as is."""
    if item.data is None:
        return None
    try:
        return json.loads(item.data)
    except ValueError:
        return item.data
