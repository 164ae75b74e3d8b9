"""How large a request body each API route takes, refused before it is parsed (docs/limits.md).

FastAPI's own `max_body_size` does the limiting (Starlette's RequestBodyLimitMiddleware): a
declared Content-Length over the limit is refused before a byte is read, a body without one
(chunked) stops being read at the limit. Starlette answers that 413 in plain text; `SaysLimit`
gives it the API's error shape with the limit and what to do instead.
"""

from __future__ import annotations

from dataclasses import dataclass

from fastapi import params
from fastapi.routing import APIRoute
from starlette.datastructures import Headers
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from servodesk.api import commissioning, logs, od, paramsets
from servodesk.api.errors import body_response
from servodesk.models.common import ErrorBody
from servodesk.settings import Settings

MIB = 1024 * 1024
# JSON bodies: the largest a user sends is a PDO set (16 PDOs × 8 mapped objects with their
# names, ~10 kB; the schema's own cap, 1024 PDOs × 8 named objects, ~0.9 MB) or a parameter
# write; 1 MiB holds each with room to spare and keeps a hostile one cheap to refuse.
JSON_BODY_MAX = 1 * MIB
# Multipart: boundaries, part headers and the small fields beside a file (confirm=true).
FORM_SLACK = 64 * 1024
# EDS/DCF/XDD uploads: each route's own file cap (read_limited) plus the form around it.
FILE_BODY_MAX = max(od.MAX_OD_FILE, paramsets.MAX_DCF_FILE) + FORM_SLACK


@dataclass(frozen=True)
class BodyLimit:
    size: int  # bytes
    advice: str  # what to do instead, for the 413's message


JSON_LIMIT = BodyLimit(JSON_BODY_MAX, "send a smaller request (limits: docs/limits.md)")
FILE_LIMIT = BodyLimit(FILE_BODY_MAX, "upload a smaller file (limits: docs/limits.md)")
# A commissioning bundle carries its captures (.rrd, Parquet) and the report's PDF; the upload
# is spooled to disk by the form parser, not held in memory.
BUNDLE_BODY_MAX = 512 * MIB
BUNDLE_LIMIT = BodyLimit(
    BUNDLE_BODY_MAX, "check against the record id instead, or leave big captures out"
)


def log_upload_limit(settings: Settings) -> BodyLimit:
    """A log of up to `log_upload_max_mb` and its optional DCF, in one form."""
    size = settings.log_upload_max_mb * MIB + logs.MAX_DCF + FORM_SLACK
    return BodyLimit(
        size,
        f"logs up to {settings.log_upload_max_mb} MiB are read: split the log, or raise "
        "SERVODESK_LOG_UPLOAD_MAX_MB",
    )


def route_body_limit(route: APIRoute, log_limit: BodyLimit) -> BodyLimit:
    """The route's limit; `log_limit` (log_upload_limit of the settings) for the log upload."""
    if route.endpoint is logs.decode_log:
        return log_limit
    if route.endpoint is commissioning.check_record:
        return BUNDLE_LIMIT
    if any(isinstance(param.field_info, params.File) for param in route.dependant.body_params):
        return FILE_LIMIT
    return JSON_LIMIT


def size_text(size: int) -> str:
    if size < MIB:
        return f"{size // 1024} kB"
    return f"{size / MIB:.1f}".removesuffix(".0") + " MiB"  # 1 MiB, 8.1 MiB, 264.1 MiB


def too_large_message(limit: BodyLimit) -> str:
    return (
        f"request body larger than this route takes ({size_text(limit.size)}); nothing was "
        f"read or stored: {limit.advice}"
    )


class SaysLimit:
    """Around a route limited by `max_body_size`: the limiter's 413 (plain text from Starlette,
    or the error handler's generic one) becomes the API's error body naming the limit. Only a
    413 of a body over the limit is rewritten; any other answer passes unchanged."""

    def __init__(self, app: ASGIApp, limit: BodyLimit) -> None:
        self.app = app
        self.limit = limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        declared = _content_length(scope)
        received = 0
        replaced = False

        async def counting_receive() -> Message:
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
            return message

        async def answering_send(message: Message) -> None:
            nonlocal replaced
            if replaced:
                return  # the limiter's own body: left out
            over = max(declared or 0, received) > self.limit.size
            if message["type"] == "http.response.start" and message["status"] == 413 and over:
                replaced = True
                body = ErrorBody(error="too_large", message=too_large_message(self.limit))
                await body_response(413, body)(scope, receive, send)
                return
            await send(message)

        await self.app(scope, counting_receive, answering_send)


def _content_length(scope: Scope) -> int | None:
    try:
        return int(Headers(scope=scope).get("content-length", ""))
    except ValueError:
        return None
