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
from servodesk.audit.store import AuditFilter, AuditRow, AuditStore, csv_header

log = logging.getLogger(__name__)

Describe = Callable[[BaseException], Outcome]


class AuditLog:
    def __init__(self, data_dir: Path, *, describe: Describe = Outcome.of_error) -> None:
        self._store = AuditStore(data_dir)
        self._describe = describe  # an error's kind and words, as the API gives them

    async def open(self) -> None:
        orphans = await asyncio.wrap_future(self._store.submit_open())
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

    async def finish(self, entry: Pending, outcome: Outcome) -> None:
        await asyncio.wrap_future(self._store.submit_finish(entry, outcome))

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
        through `current_entry()`), result row — also when the write fails or is cancelled."""
        entry = await self.begin(action, node, what, new=new, undo_of=undo_of, wait=wait)
        token = enter(entry)
        try:
            yield entry
        except BaseException as error:
            await asyncio.shield(self.finish(entry, describe(error)))
            raise
        finally:
            leave(token)
        await self.finish(entry, Outcome.ok())

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
            try:
                await asyncio.shield(self.finish(entry, outcome))
            except Exception:
                log.exception("audit log: the result of %s could not be written", what)

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
