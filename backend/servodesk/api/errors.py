"""The one place where errors become HTTP answers (docs/api.md, "Errors").

Every error the API returns has the one documented shape, `ErrorBody` {error, message, …}: the
domain errors of servodesk.errors, request validation (FastAPI's own 422 would say {"detail"}),
Starlette's HTTP errors (400 unparsable body, 404, 405 with the route's real methods in `Allow`)
and anything unexpected (500, with the traceback in the server log only).
"""

from __future__ import annotations

import errno
import logging
from collections.abc import Sequence
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException

from servodesk.api.schema import allowed_methods
from servodesk.audit.errors import AuditUnavailableError
from servodesk.errors import (
    BusNotConnectedError,
    BusOpenError,
    CommTimeoutError,
    ConfirmationRequiredError,
    ForbiddenError,
    IdentityMismatchError,
    InvalidValueError,
    NodeNotFoundError,
    NodeStoppedError,
    NotFoundError,
    PdoApplyError,
    PdoInvalidError,
    RequestInterruptedError,
    SdoAbortError,
    SdoProtocolError,
    ServodeskError,
    StateConflictError,
)
from servodesk.models.common import ErrorBody
from servodesk.models.motion import DriveState, EnableReason
from servodesk.models.pdo import PdoProblem
from servodesk.models.safety import ControllerHolder, JogInfo
from servodesk.motion.clients import ClientIdTakenError
from servodesk.motion.errors import EnableBlockedError, LimitError, MotionBusyError
from servodesk.motion.ip_timing import SyncUnsafeError
from servodesk.motion.jog import JogNotFoundError, JogStoppedError, NotJogOwnerError
from servodesk.motion.lease import HeldByOtherError
from servodesk.sdo.jobs import JobNotFoundError


class MotionErrorBody(ErrorBody):
    """ErrorBody with what the motion routes add: who holds the drive (held_by_other), why it
    does not enable (enable_blocked: reasons and the drive state), a stopped jog."""

    holder: ControllerHolder | None = None
    reasons: list[EnableReason] | None = None
    state: DriveState | None = None
    jog: JogInfo | None = None


log = logging.getLogger(__name__)

HTTP_ERRORS = {
    400: "bad_request",
    404: "not_found",
    405: "method_not_allowed",
    413: "too_large",
    415: "unsupported_media_type",
}


def error_response(error: ServodeskError) -> JSONResponse:
    status, body = describe(error)
    message_id, params = error.said()
    if message_id is not None and body.message == str(error):  # the words it said by id
        body.message_id, body.params = message_id, params
    # pdo_apply_failed always names its abort code, null when the step failed otherwise
    keep = ("abort_code",) if isinstance(error, PdoApplyError) else ()
    return body_response(status, body, keep=keep)


def body_response(
    status: int,
    body: ErrorBody,
    headers: dict[str, str] | None = None,
    *,
    keep: tuple[str, ...] = (),
) -> JSONResponse:
    if isinstance(body, MotionErrorBody):
        # nested models (the drive state) keep their nulls: their schema requires the fields
        content = {k: v for k, v in body.model_dump(mode="json").items() if v is not None}
    else:
        content = body.model_dump(exclude_none=True)
    for name in keep:
        content.setdefault(name, None)
    return JSONResponse(status_code=status, content=content, headers=headers)


def describe(error: ServodeskError) -> tuple[int, ErrorBody]:
    motion = _describe_motion(error)
    if motion is not None:
        return motion
    if isinstance(error, AuditUnavailableError):
        # 507 Insufficient Storage when the disk is full; another cause is 503
        return (507 if error.full else 503), ErrorBody(
            error="audit_unavailable", message=str(error)
        )
    if isinstance(error, SdoAbortError):
        return 409, ErrorBody(
            error="sdo_abort",
            message=error.meaning,
            abort_code=error.code_hex,
            node=error.node_id,
            index=error.index,
            subindex=error.subindex,
        )
    if isinstance(error, PdoApplyError):
        return 409, ErrorBody(
            error="pdo_apply_failed",
            message=str(error),
            abort_code=error.code_hex,
            node=error.node_id,
            step=error.step,
            restored=error.restored,
        )
    if isinstance(error, NodeStoppedError):
        return 409, ErrorBody(error="node_stopped", message=str(error), node=error.node_id)
    if isinstance(error, SdoProtocolError):  # before its base class, CommTimeoutError
        return 502, ErrorBody(error="sdo_protocol", message=str(error), node=error.node_id)
    if isinstance(error, CommTimeoutError):
        return 504, ErrorBody(error="timeout", message=str(error), node=error.node_id)
    if isinstance(error, RequestInterruptedError):
        return 503, ErrorBody(error="interrupted", message=str(error), node=error.node_id)
    if isinstance(error, JobNotFoundError):
        return 404, ErrorBody(error="job_not_found", message=str(error))
    if isinstance(error, ForbiddenError):
        return 403, ErrorBody(
            error="forbidden", message=str(error), role=error.role, required=error.required
        )
    if isinstance(error, NotFoundError):  # log_not_found
        return 404, ErrorBody(error=error.kind, message=str(error))
    if isinstance(error, StateConflictError):  # recording_not_running
        return 409, ErrorBody(error=error.kind, message=str(error))
    if isinstance(error, NodeNotFoundError):
        return 404, ErrorBody(error="node_not_found", message=str(error), node=error.node_id)
    if isinstance(error, BusNotConnectedError):
        return 503, ErrorBody(error="bus_not_connected", message=str(error))
    if isinstance(error, BusOpenError):
        return 422, ErrorBody(error="bus_open_failed", message=str(error))
    if isinstance(error, PdoInvalidError):
        problems = [PdoProblem.model_validate(p, from_attributes=True) for p in error.problems]
        return 422, ErrorBody(error="invalid_value", message=str(error), problems=problems)
    if isinstance(error, InvalidValueError):
        return 422, ErrorBody(error="invalid_value", message=str(error))
    if isinstance(error, IdentityMismatchError):
        return 428, ErrorBody(error="identity_mismatch", message=str(error))
    if isinstance(error, ConfirmationRequiredError):
        return 428, ErrorBody(error="confirmation_required", message=str(error))
    return 500, ErrorBody(error="error", message=str(error))


def _describe_motion(error: ServodeskError) -> tuple[int, ErrorBody] | None:
    if isinstance(error, EnableBlockedError):
        return 409, MotionErrorBody(
            error="enable_blocked",
            message=str(error),
            node=error.node,
            reasons=error.reasons,
            state=error.state,
        )
    if isinstance(error, HeldByOtherError):
        return 409, MotionErrorBody(
            error="held_by_other", message=str(error), node=error.node, holder=error.holder
        )
    if isinstance(error, MotionBusyError):
        return 409, MotionErrorBody(error="motion_busy", message=str(error), node=error.node)
    if isinstance(error, JogStoppedError):
        return 409, MotionErrorBody(
            error="jog_stopped", message=str(error), node=error.info.node, jog=error.info
        )
    if isinstance(error, JogNotFoundError):
        return 404, ErrorBody(error="jog_not_found", message=str(error))
    if isinstance(error, NotJogOwnerError):
        return 403, MotionErrorBody(
            error="not_jog_owner", message=str(error), node=error.info.node, jog=error.info
        )
    if isinstance(error, ClientIdTakenError):
        return 403, ErrorBody(error="client_id_taken", message=str(error))
    if isinstance(error, LimitError):
        return 422, ErrorBody(error="invalid_value", message=str(error), node=error.node)
    if isinstance(error, SyncUnsafeError):
        return 409, MotionErrorBody(error="sync_unsafe", message=str(error), node=error.node)
    return None


def validation_message(errors: Sequence[Any]) -> str:
    """FastAPI's validation errors as one line: "body.value: Field required; path.node: …"."""
    parts: list[str] = []
    for item in errors:
        where = ".".join(str(part) for part in item.get("loc", ()) if part != "body") or "request"
        parts.append(f"{where}: {item.get('msg', 'invalid')}")
    return "; ".join(parts) or "invalid request"


def install_error_handlers(app: FastAPI) -> None:
    async def domain(_request: Request, error: Exception) -> JSONResponse:
        if not isinstance(error, ServodeskError):  # registered for ServodeskError only
            raise error
        return error_response(error)

    async def validation(_request: Request, error: Exception) -> JSONResponse:
        if not isinstance(error, RequestValidationError):
            raise error
        body = ErrorBody(error="invalid_request", message=validation_message(error.errors()))
        return body_response(422, body)

    async def http(request: Request, error: Exception) -> JSONResponse:
        if not isinstance(error, HTTPException):
            raise error
        headers = dict(error.headers or {})
        if error.status_code == 405:
            methods = allowed_methods(request.app, request.url.path)
            if methods:
                headers["Allow"] = ", ".join(methods)
        kind = HTTP_ERRORS.get(error.status_code, "error")
        body = ErrorBody(error=kind, message=str(error.detail))
        return body_response(error.status_code, body, headers or None)

    async def unexpected(request: Request, error: Exception) -> JSONResponse:
        storage = storage_failure(error)
        if storage is not None:  # not a bug: the disk under the data directory said no
            log.warning("%s %s: %s", request.method, request.url.path, storage[1].message)
            return body_response(*storage)
        # A bug of ours: the user gets one line in the documented shape, the log the traceback.
        log.error("%s %s failed", request.method, request.url.path, exc_info=error)
        body = ErrorBody(
            error="internal", message=f"internal error ({type(error).__name__}); see the log"
        )
        return body_response(500, body)

    app.add_exception_handler(ServodeskError, domain)
    app.add_exception_handler(RequestValidationError, validation)
    app.add_exception_handler(HTTPException, http)
    app.add_exception_handler(Exception, unexpected)


DISK_FULL = frozenset({errno.ENOSPC, errno.EDQUOT})


def storage_failure(error: BaseException) -> tuple[int, ErrorBody] | None:
    """A file system that is full or read-only, wherever the request met it (a log spooled
    for decoding, a capture, a recording): 507 or 503 in words instead of an internal error."""
    seen: set[int] = set()
    cause: BaseException | None = error
    while cause is not None and id(cause) not in seen:
        seen.add(id(cause))
        if isinstance(cause, OSError) and cause.errno in DISK_FULL:
            return 507, ErrorBody(
                error="storage_full",
                message="no space left on the disk of ServoDesk's data directory: free space "
                "there and try again (stops and disables still work)",
            )
        if isinstance(cause, OSError) and cause.errno == errno.EROFS:
            return 503, ErrorBody(
                error="storage_read_only",
                message="ServoDesk's data directory is on a read-only disk: give it a writable "
                "one (SERVODESK_DATA_DIR) and restart it",
            )
        cause = cause.__cause__ or cause.__context__
    return None


def _error(description: str) -> dict[str, object]:
    return {"model": ErrorBody, "description": description}


# What routes can answer besides success, for the OpenAPI schema (and so the generated client).
# 400 (unparsable body), 403 (cross-site) and 422 (invalid request) are added to every
# operation by servodesk.api.openapi.
NODE_ERRORS: dict[int | str, dict[str, object]] = {
    404: _error("Unknown node"),
    409: _error("SDO abort (abort_code and its meaning), or the node is Stopped (node_stopped)"),
    502: _error(
        "sdo_protocol: the node answered, but not as the SDO transfer expects (a segment's "
        "toggle bit, another command); the transfer was aborted"
    ),
    503: _error("Bus not connected, or the connection was renewed during the request"),
    504: _error("Node did not answer"),
}
PDO_APPLY_ERRORS: dict[int | str, dict[str, object]] = {
    409: _error(
        "pdo_apply_failed: the device refused a step (step, abort_code, restored); the previous "
        "PDOs were restored. Also an SDO abort while reading, or the node is Stopped"
    ),
}
CONFIRM_ERRORS: dict[int | str, dict[str, object]] = {
    428: _error("Needs confirmation: send again with confirm=true"),
}


def _motion_error(description: str) -> dict[str, object]:
    return {"model": MotionErrorBody, "description": description}


# Motion routes: a 409 may carry the holder, the enable reasons and the drive state.
MOTION_ERRORS: dict[int | str, dict[str, object]] = {
    **NODE_ERRORS,
    403: _error(
        "Refused: the caller's role may not, another site's page, or client_id_taken (another "
        "login uses this X-Client-Id)"
    ),
    409: _motion_error(
        "held_by_other (holder): another client controls the drive, take over first; "
        "enable_blocked (reasons, state); motion_busy; sync_unsafe (an IP stream refused: "
        "this host does not keep the SYNC deadlines); or an SDO abort / node_stopped"
    ),
}
JOG_ERRORS: dict[int | str, dict[str, object]] = {
    403: _motion_error(
        "Refused: the caller's role may not, another site's page, or not_jog_owner (jog): only "
        "the jog's owner keeps it moving"
    ),
    404: _error("No such jog (jog_not_found)"),
    409: _motion_error("jog_stopped (jog): the jog was stopped; start a new one to move again"),
}
BUS_ERRORS: dict[int | str, dict[str, object]] = {
    503: _error("Bus not connected"),
}
CONNECT_ERRORS: dict[int | str, dict[str, object]] = {
    422: _error(
        "Not a bus configuration, or the bus asked for could not be opened (the "
        "connected bus stays)"
    ),
}
