"""The audit log's API models (GET /api/audit, POST /api/audit/{id}/undo)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, StrictBool

from servodesk.models.base import RequestBody, Value


class AuditEntry(BaseModel):
    id: int
    time: float  # unix s: when the entry was written, before the write was sent
    finished: float | None  # when its result was written; null while pending
    user: str
    role: str
    client: str | None  # the client's address and port
    node: int | None
    action: str  # "sdo-write", "param", "pdo-apply", "dcf-load", "nmt", "drive-enable", …
    what: str  # the write in words
    index: int | None
    subindex: int | None
    old: Value
    new: Value
    result: Literal["pending", "ok", "failed", "unknown"]
    abort_code: str | None  # "0x06010002" when the drive refused
    error: str | None  # the API's error code ("sdo_abort", "timeout" …)
    message: str | None  # the abort code's meaning or the error in words
    undo_of: int | None  # the entry this one undid
    undone_by: int | None  # the undo that took this entry back (or is doing so): undone once
    # a single parameter/OD write that succeeded with a known old value, not undone yet
    # (built from the store's row by servodesk.api.audit: the models import nothing above them)
    undoable: bool


class UndoRequest(RequestBody):
    # write the old value back even though the entry's value was changed since
    force: StrictBool = False
