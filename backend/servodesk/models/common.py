"""The API models many routes share: the confirm body, a plain message, and the error body
every failed request answers with (docs/api.md)."""

from __future__ import annotations

from pydantic import BaseModel, StrictBool

from servodesk.models.base import RequestBody
from servodesk.models.pdo import PdoProblem


class Confirm(RequestBody):
    confirm: StrictBool = False


class MessageResult(BaseModel):
    message: str


class ErrorBody(BaseModel):
    error: str
    message: str
    # the message in the page's catalogue (`server.<message_id>` with `params`, docs/api.md
    # "Texts in the user's language"); absent: only the English message exists
    message_id: str | None = None
    params: dict[str, str | int] | None = None
    abort_code: str | None = None
    node: int | None = None
    index: int | None = None
    subindex: int | None = None
    step: str | None = None  # pdo_apply_failed: the write or read that failed
    restored: bool | None = None  # pdo_apply_failed: whether the previous PDOs are back
    problems: list[PdoProblem] | None = None  # invalid PDO configuration: every reason
    role: str | None = None  # forbidden: the caller's role
    required: str | None = None  # forbidden: the least role that may
    retry_after_s: int | None = None  # rate_limited: when to try again
