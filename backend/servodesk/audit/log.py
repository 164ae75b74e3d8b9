"""The audit log service: an entry around each write, the acting user from the request, the
entries back by filter, CSV export (docs/security.md, "Audit log")."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from pathlib import Path

from servodesk.access.actor import SYSTEM, acting, current_actor
from servodesk.audit.entry import AuditValue, Outcome, Pending, enter, leave
from servodesk.audit.errors import AuditUnavailableError, unavailable
from servodesk.audit.store import AuditFilter, AuditRow, AuditStore, csv_header

log = logging.getLogger(__name__)

# How long a stop's answer waits for its result row: the stop went out already; a slow disk
# must not hold the answer (the row is still written, later).
URGENT_WAIT_S = 0.5

Describe = Callable[[BaseException], Outcome]


class AuditLog:
    def __init__(self, data_dir: Path, *, describe: Describe = Outcome.of_error) -> None:
        self._data_dir = data_dir
        self._store = AuditStore(data_dir)
        self._describe = describe  # an error's kind and words, as the API gives them

    async def open(self) -> None:
        """Open the log; one that cannot be opened (disk full) leaves the server running: its
        stops go out, other writes are refused until a write finds the log writable again."""
        try:
            orphans = await asyncio.wrap_future(self._store.submit_open())
        except AuditUnavailableError as error:
            log.error(
                "audit log cannot be opened (%s) in %s: writes are refused until it can, stops "
                "still go out",
                error.cause,
                error.data_dir,
            )
            return
        if orphans:
            log.warning("%d audit entries had no result (the server stopped mid-write)", orphans)

    async def close(self) -> None:
        await asyncio.to_thread(self._store.close)

    async def begin(
        self,
        action: str,
        node: int | None,
        what: str,
        *,
        new: AuditValue = None,
        undo_of: int | None = None,
        wait: bool = True,
    ) -> Pending:
        """Append the entry's begin row; with `wait`, return once it is on disk. A stop passes
        wait=False: it must never wait for the log (its row is queued ahead of its result)."""
        entry = Pending(
            actor=current_actor(),
            action=action,
            node=node,
            what=what,
            new=new,
            undo_of=undo_of,
        )
        entry.row = self._store.submit_begin(entry)
        if wait:
            await asyncio.wrap_future(entry.row)
        return entry

    async def settle(
        self, entry: Pending, outcome: Outcome, *, wait: float | None = None
    ) -> AuditUnavailableError | None:
        """Append the result of a write that happened (or was tried) whatever the log's state:
        never raises; returns why the entry is not recorded, for the answer to say so. With
        `wait`, gives up waiting after that many seconds (the row is still queued)."""
        done = asyncio.wrap_future(self._store.submit_finish(entry, outcome))
        try:
            await asyncio.wait_for(asyncio.shield(done), wait)
        except TimeoutError:
            log.warning("audit log: the result of %s is not written yet (slow disk)", entry.what)
            return None
        except Exception as error:
            failure = unavailable(error, self._data_dir).after(entry.what)
            log.error("audit log in %s cannot be written: %s", self._data_dir, failure)
            return failure
        return None

    @asynccontextmanager
    async def entry(
        self,
        action: str,
        node: int | None,
        what: str,
        describe: Describe,
        *,
        new: AuditValue = None,
        undo_of: int | None = None,
        wait: bool = True,
    ) -> AsyncIterator[Pending]:
        """One audited write: begin row, the write (the SDO path fills in object and old value
        through `current_entry()`), result row — also when the write fails or is cancelled.

        With `wait` (the default) a log that cannot be written refuses the write before it is
        sent (AuditUnavailableError). A stop passes wait=False: it goes out whatever the log's
        state; when its entry could not be written, AuditUnavailableError is raised after it
        went out, naming what was sent (the caller answers it beside the stop)."""
        entry = await self.begin(action, node, what, new=new, undo_of=undo_of, wait=wait)
        token = enter(entry)
        try:
            yield entry
        except BaseException as error:
            await self.settle(entry, describe(error), wait=None if wait else URGENT_WAIT_S)
            raise
        finally:
            leave(token)
        failure = await self.settle(
            entry, entry.verdict or Outcome.ok(), wait=None if wait else URGENT_WAIT_S
        )
        if failure is not None:
            raise failure

    @asynccontextmanager
    async def by_tool(
        self, action: str, node: int | None, what: str
    ) -> AsyncIterator[Pending | None]:
        """A write the tool makes by itself, not for a request (a jog stopped because its
        keep-alives stopped, the heartbeat consumer set again after a reboot): its entry is by
        "servodesk", whoever's request armed the timer. These are mostly stops, so the log
        never holds one back: the begin row is queued, not awaited, and a log that cannot
        write (closed, disk full) is logged while the write goes ahead."""
        try:
            with acting(SYSTEM):
                entry = await self.begin(action, node, what, wait=False)
        except Exception:
            log.exception("audit log unavailable; %s goes ahead unrecorded", what)
            yield None
            return
        token = enter(entry)
        outcome = Outcome.ok()
        try:
            yield entry
        except BaseException as error:
            outcome = self._describe(error)
            raise
        finally:
            leave(token)
            await self.settle(entry, outcome, wait=URGENT_WAIT_S)  # logs a failure

    async def entries(self, filters: AuditFilter) -> list[AuditRow]:
        return await asyncio.wrap_future(self._store.submit_query(filters))

    async def get(self, entry_id: int) -> AuditRow | None:
        return await asyncio.wrap_future(self._store.submit_get(entry_id))

    async def csv(self, filters: AuditFilter) -> AsyncIterator[str]:
        """Every matching entry, oldest first, streamed in chunks (`limit` is ignored)."""
        yield csv_header()
        after = 0
        while True:
            text, last = await asyncio.wrap_future(self._store.submit_csv_chunk(filters, after))
            if last is None:
                return
            yield text
            after = last
