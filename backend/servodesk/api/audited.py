"""The one write path's front door: every state-changing route of the API is an
`AuditedRoute`, which appends the audit entry before the route runs and its result after
(docs/security.md, "Audit log"). A route that changes nothing on a drive or in the tool's
configuration is listed in NOT_AUDITED; every other one is audited by default, so a new route
cannot forget it."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable, Coroutine
from typing import Any

from fastapi import Request, Response
from fastapi.exceptions import RequestValidationError
from fastapi.routing import APIRoute
from starlette.exceptions import HTTPException

from servodesk.api.errors import HTTP_ERRORS, describe, validation_message
from servodesk.api.no_body import problems, refuse_body
from servodesk.audit import AuditLog, Outcome
from servodesk.audit.entry import enter, leave
from servodesk.audit.log import URGENT_WAIT_S
from servodesk.errors import SdoAbortError, ServodeskError
from servodesk.models.common import ErrorBody

CHANGES_STATE = frozenset({"POST", "PUT", "PATCH", "DELETE"})
MAX_BODY = 16 * 1024  # bodies larger than this (uploads) are not copied into the entry

# Endpoints (by function name) that change nothing a user would audit: computations, reads,
# keep-alives, logging in. The undo route writes its own entry (audit/undo.py).
NOT_AUDITED = frozenset(
    {
        "keepalive",
        "validate_pdos",
        "plan_capture",
        "compare",
        "check_record",
        "check_od",
        "decode_log",
        "scan",
        "upload_all",
        "cancel_job",
        "start_live",
        "stop_live",
        "start_recording",
        "stop_recording",
        "login",
        "logout",
        "undo",
    }
)
# Stops and disables: their entry is queued, never waited for; they go out whatever the log's
# state, and an entry that cannot be written is reported beside the answer (AUDIT_HEADER).
URGENT = frozenset({"quick_stop", "quick_stop_all", "stop_jog", "disable"})
# On a stop sent with a body it does not take: the body was ignored, the stop went out.
BODY_IGNORED_HEADER = "X-Body-Ignored"
# POST …/drive/command: the controlword commands that take power from the motor are urgent too.
URGENT_COMMANDS = frozenset({"shutdown", "disable_operation", "disable_voltage", "quick_stop"})
# On an answer whose write went out but whose audit entry could not be written:
# "audit_unavailable; <what was sent and why it is not recorded>" (docs/api.md).
AUDIT_HEADER = "X-Audit-Error"
AUDIT_UNAVAILABLE: dict[str, Any] = {
    "model": ErrorBody,
    "description": "audit_unavailable: the audit log cannot be written (no space left); "
    "nothing was sent. Stops and disables answer with the X-Audit-Error header instead",
}
# The action an endpoint's entries carry, where it is not the endpoint's name in kebab-case.
ACTIONS = {
    "write_entry": "sdo-write",
    "set_param": "param",
    "apply_pdos": "pdo-apply",
    "load_dcf": "dcf-load",
    "nmt_broadcast": "nmt",
    "set_heartbeat": "heartbeat",
    "change_node_id": "node-id",
    "change_bitrate": "bitrate",
    "enable": "drive-enable",
    "disable": "drive-disable",
    "command": "drive-command",
    "quick_stop_all": "quick-stop",
    "set_limits": "limits",
    "take_control": "controller-take",
    "release_control": "controller-release",
    "start_jog": "jog",
    "clear_device_history": "clear-history",
    "upload_od": "od-load",
    "reset_od": "od-reset",
    "start_capture": "scope-capture",
    "stop_or_delete_capture": "scope-stop",
    "connect": "bus-connect",
    "disconnect": "bus-disconnect",
    "reconnect": "bus-reconnect",
    "set_sync": "sync",
}


def action_of(endpoint_name: str) -> str:
    return ACTIONS.get(endpoint_name, endpoint_name.replace("_", "-"))


def outcome_of(error: BaseException) -> Outcome:
    """What an error means for the entry: the API's own error code and words, and the SDO
    abort code where there is one."""
    if isinstance(error, SdoAbortError):
        return Outcome("failed", error.code_hex, "sdo_abort", error.meaning)
    if isinstance(error, ServodeskError):
        _, body = describe(error)
        return Outcome("failed", body.abort_code, body.error, body.message)
    if isinstance(error, RequestValidationError):
        return Outcome("failed", None, "invalid_request", validation_message(error.errors()))
    if isinstance(error, HTTPException):
        return Outcome("failed", None, HTTP_ERRORS.get(error.status_code, "error"), error.detail)
    if isinstance(error, asyncio.CancelledError | GeneratorExit):
        return Outcome("unknown", None, "interrupted", "the request was cancelled mid-write")
    return Outcome("failed", None, "internal", f"internal error ({type(error).__name__})")


def _response_outcome(response: Response) -> Outcome:
    if response.status_code < 400:
        return Outcome.ok()
    try:
        body = json.loads(bytes(response.body))
    except (ValueError, AttributeError):
        body = {}
    error = body.get("error") if isinstance(body, dict) else None
    message = body.get("message") if isinstance(body, dict) else None
    return Outcome("failed", None, str(error or response.status_code), message)


async def _body(request: Request) -> Any:
    """The JSON body, parsed; None when there is none (or it is too large to copy)."""
    if not request.headers.get("content-type", "").startswith("application/json"):
        return None
    try:
        if int(request.headers.get("content-length", "0")) > MAX_BODY:
            return None
    except ValueError:
        return None
    body = await request.body()  # Starlette caches it: the route reads the same bytes
    try:
        return json.loads(body)
    except ValueError:
        return None


def _summary(parsed: Any) -> tuple[str, Any]:
    """The request body as one short line, and its `value` when it names one."""
    if parsed is None:
        return "", None
    text = json.dumps(parsed, ensure_ascii=False, separators=(",", ":"))
    value = parsed.get("value") if isinstance(parsed, dict) else None
    if not isinstance(value, int | float | str) or isinstance(value, bool):
        value = None
    return (text if len(text) <= 300 else text[:297] + "…"), value


def _urgent(endpoint_name: str, parsed: Any) -> bool:
    if endpoint_name in URGENT:
        return True
    # the body is not validated yet: any JSON may stand where the command's name should
    command = parsed.get("command") if isinstance(parsed, dict) else None
    return endpoint_name == "command" and isinstance(command, str) and command in URGENT_COMMANDS


def _header_text(failure: BaseException) -> str:
    # header values are Latin-1: the data directory's path may not be
    text = f"audit_unavailable; {failure}"
    return text.encode("ascii", "replace").decode("ascii")


def _node(request: Request) -> int | None:
    text = request.path_params.get("node")
    try:
        node = int(text) if text is not None else None
    except ValueError:
        return None
    return node if node is not None and 1 <= node <= 127 else None


def _without_body(
    handler: Callable[[Request], Coroutine[Any, Any, Response]],
) -> Callable[[Request], Coroutine[Any, Any, Response]]:
    async def strict(request: Request) -> Response:
        await refuse_body(request)  # inside the entry: the refusal is audited as failed
        return await handler(request)

    return strict


def _body_ignored(
    handler: Callable[[Request], Coroutine[Any, Any, Response]],
) -> Callable[[Request], Coroutine[Any, Any, Response]]:
    """A stop never waits on its body: one with fields it does not know still stops (nothing
    of the body is kept: `_summary` is not asked), and the answer says the body was ignored."""

    async def stopping(request: Request) -> Response:
        found = problems(await request.body())
        response = await handler(request)
        if found:
            fields = ", ".join(str(p["loc"][-1]) for p in found)[:200]
            response.headers[BODY_IGNORED_HEADER] = f"this request takes no body: {fields}"
        return response

    return stopping


class AuditedRoute(APIRoute):
    def __init__(self, path: str, endpoint: Callable[..., Any], **kwargs: Any) -> None:
        methods = {m.upper() for m in kwargs.get("methods") or ()}
        self.audited = bool(methods & CHANGES_STATE) and endpoint.__name__ not in NOT_AUDITED
        if self.audited:
            # said in the schema too: API clients see which calls leave an audit entry
            kwargs["openapi_extra"] = {**(kwargs.get("openapi_extra") or {}), "x-audited": True}
            kwargs["responses"] = {507: AUDIT_UNAVAILABLE, **(kwargs.get("responses") or {})}
        super().__init__(path, endpoint, **kwargs)

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()
        name = self.endpoint.__name__
        bodiless = self.body_field is None and bool(set(self.methods or ()) & CHANGES_STATE)
        if bodiless:
            handler = _body_ignored(handler) if name in URGENT else _without_body(handler)
        if not self.audited:
            return handler
        action = action_of(name)

        async def audited(request: Request) -> Response:
            audit: AuditLog = request.app.state.services.audit
            # a stop's stray body is not the user's words about it: none of it is kept
            parsed = None if bodiless and name in URGENT else await _body(request)
            summary, value = _summary(parsed)
            urgent = _urgent(name, parsed)
            what = f"{request.method} {request.url.path}" + (f" {summary}" if summary else "")
            # a write that is not urgent is refused here when its entry cannot be written
            entry = await audit.begin(action, _node(request), what, new=value, wait=not urgent)
            wait = URGENT_WAIT_S if urgent else None
            token = enter(entry)
            try:
                response = await handler(request)
            except BaseException as error:
                await audit.settle(entry, outcome_of(error), wait=wait)
                raise
            finally:
                leave(token)
            # an error the route answered itself, or a success the route itself reported as a
            # failure (a stalled IP stream), counts as failed
            outcome = _response_outcome(response)
            if entry.verdict is not None and outcome.result == "ok":
                outcome = entry.verdict
            failure = await audit.settle(entry, outcome, wait=wait)
            if failure is not None:  # the write went out: say so, and that it is not recorded
                response.headers[AUDIT_HEADER] = _header_text(failure)
            return response

        return audited
