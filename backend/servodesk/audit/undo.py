"""Undoing a parameter or OD write: the old value written back through the same audited write
path, as an entry of its own that names the one it undoes."""

from __future__ import annotations

from collections.abc import Awaitable, Callable

from servodesk.audit.entry import Outcome
from servodesk.audit.errors import AlreadyUndoneError
from servodesk.audit.log import AuditLog
from servodesk.audit.store import AuditRow
from servodesk.errors import NotFoundError, StateConflictError
from servodesk.models.sdo import SdoValue

Read = Callable[[int, int, int], Awaitable[SdoValue]]
Write = Callable[[int, int, int, int | float | str], Awaitable[SdoValue]]


def why_not(row: AuditRow) -> str | None:
    """Why an entry cannot be undone, in words; None when it can."""
    if row.result != "ok":
        return f"entry {row.id} did not complete ({row.result}): there is nothing to undo"
    if not row.undoable or row.node is None or row.index is None or row.subindex is None:
        return (
            f"entry {row.id} ({row.action}) is not a single parameter or OD write with a known "
            "old value: only those can be undone"
        )
    if row.old is None:
        return f"entry {row.id} has no old value to write back"
    return None


async def undo(
    audit: AuditLog,
    entry_id: int,
    *,
    read: Read,
    write: Write,
    describe: Callable[[BaseException], Outcome],
    force: bool,
) -> int:
    """Write entry `entry_id`'s old value back; the id of the undo's own entry."""
    row = await audit.get(entry_id)
    if row is None:
        raise NotFoundError("not_found", f"there is no audit entry {entry_id}")
    reason = why_not(row)
    node, index, subindex, old = row.node, row.index, row.subindex, row.old
    if reason is not None or node is None or index is None or subindex is None or old is None:
        raise StateConflictError("not_undoable", reason or f"entry {entry_id} cannot be undone")
    if row.undone_by is not None:  # said before the drive is read; the claim below decides
        await _refuse_undone(audit, entry_id, row.undone_by)
    place = f"{row.index:04X}h:{row.subindex:02X}h"
    if not force:
        now = await read(node, index, subindex)
        if now.value != row.new:
            raise StateConflictError(
                "changed_since",
                f"node {node} {place} is {now.text} now, not {row.new} as entry {entry_id} "
                "left it: undo with force to write the old value anyway",
            )
    # the undo's begin row claims the entry: of concurrent undos one is entered, the others
    # get AlreadyUndoneError before anything is sent
    what = f"undo entry {entry_id}: write node {node} {place} = {old} (back from {row.new})"
    async with audit.entry("undo", node, what, describe, new=old, undo_of=entry_id) as pending:
        await write(node, index, subindex, old)
    return pending.row.result()


async def _refuse_undone(audit: AuditLog, entry_id: int, undo_id: int) -> None:
    undo_row = await audit.get(undo_id)
    user = undo_row.user if undo_row is not None else "?"
    result = undo_row.result if undo_row is not None else "ok"
    raise AlreadyUndoneError(entry_id, undo_id, user, result)
