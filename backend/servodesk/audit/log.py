"""The audit log service: an entry around each write, the acting user from the request, the
entries back by filter, CSV export (docs/security.md, "Audit log")."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from pathlib import Path

from servodesk.access.actor import current_actor
from servodesk.audit.entry import AuditValue, Outcome, Pending, enter, leave
from servodesk.audit.store import AuditFilter, AuditRow, AuditStore, csv_header

log = logging.getLogger(__name__)

Describe = Callable[[BaseException], Outcome]


class AuditLog:
    def __init__(self, data_dir: Path) -> None:
        self._store = AuditStore(data_dir)

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
