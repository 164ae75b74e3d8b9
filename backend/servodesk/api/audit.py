"""The audit log: every write to a drive with who, when, old → new and the result; CSV export;
undo of a parameter or OD write (docs/security.md, "Audit log")."""

from __future__ import annotations

import functools
from dataclasses import replace
from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Path, Query
from fastapi.responses import StreamingResponse

from servodesk.api.audited import AuditedRoute, outcome_of
from servodesk.api.deps import ServicesDep
from servodesk.api.errors import NODE_ERRORS
from servodesk.audit import AuditFilter, AuditRow
from servodesk.audit.undo import undo as undo_entry
from servodesk.models.audit import AuditEntry, UndoRequest
from servodesk.models.common import ErrorBody

router = APIRouter(prefix="/audit", tags=["audit"], route_class=AuditedRoute)


def _entry(row: AuditRow) -> AuditEntry:
    """The store's row as the API sends it: undoable only while no undo took it back."""
    entry = AuditEntry.model_validate(row, from_attributes=True)
    entry.undoable = row.undoable and row.undone_by is None
    return entry


UNDO_ERRORS: dict[int | str, dict[str, object]] = {
    **NODE_ERRORS,
    404: {"model": ErrorBody, "description": "No such entry, or its node is not on the bus"},
    409: {
        "model": ErrorBody,
        "description": "not_undoable (why), already_undone (another undo of the entry took it "
        "back or is doing so: an entry is undone once, forced or not), changed_since (the value "
        "changed: use force), or the drive refused the write (sdo_abort with its code)",
    },
}


def _filters(
    node: Annotated[int | None, Query(ge=1, le=127)] = None,
    since: Annotated[float | None, Query(ge=0, le=1e11, description="unix time (s)")] = None,
    until: Annotated[float | None, Query(ge=0, le=1e11, description="unix time (s)")] = None,
    user: Annotated[str | None, Query(max_length=100)] = None,
    action: Annotated[str | None, Query(max_length=40)] = None,
) -> AuditFilter:
    return AuditFilter(node, since, until, user, action)


Filters = Annotated[AuditFilter, Depends(_filters)]


@router.get("")
async def audit_entries(
    services: ServicesDep,
    filters: Filters,
    before: Annotated[
        int | None, Query(ge=1, le=2**62, description="entries older than this id")
    ] = None,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
) -> list[AuditEntry]:
    """The entries, newest first."""
    rows = await services.audit.entries(replace(filters, before=before, limit=limit))
    return [_entry(row) for row in rows]


@router.get(
    "/export",
    response_class=StreamingResponse,
    responses={200: {"content": {"text/csv": {}}, "description": "every matching entry"}},
)
async def export_audit(
    services: ServicesDep,
    filters: Filters,
    format: Literal["csv"] = "csv",  # the query parameter's name
) -> StreamingResponse:
    """Every matching entry as CSV, oldest first."""
    return StreamingResponse(
        services.audit.csv(filters),
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": 'attachment; filename="servodesk-audit.csv"'},
    )


@router.post("/{entry_id}/undo", responses=UNDO_ERRORS)
async def undo(
    entry_id: Annotated[int, Path(ge=1, le=2**62)],
    services: ServicesDep,
    body: UndoRequest | None = None,
) -> AuditEntry:
    """Write the entry's old value back (itself audited, naming this entry in `undo_of`)."""
    new_id = await undo_entry(
        services.audit,
        entry_id,
        read=services.sdo.read,
        # the value the drive held before (a heartbeat time too): the undo is the confirmation
        write=functools.partial(services.sdo.write, confirm=True),
        describe=outcome_of,
        force=body.force if body is not None else False,
    )
    row = await services.audit.get(new_id)
    if row is None:  # written just now: only a broken disk would lose it
        raise RuntimeError(f"audit entry {new_id} vanished")
    return _entry(row)
