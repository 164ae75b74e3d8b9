"""Loopback-only serving: Host checks against DNS rebinding, Origin checks against cross-site
requests (DESIGN: Security).

Serving beyond loopback needs a token and roles, which the tool does not have yet, so the
server refuses to bind elsewhere (cli.py) and refuses requests naming another host. Browsers
send form, multipart and text/plain posts to any site without asking first (no CORS preflight),
so every state-changing request must come from one of our own pages: `SameOriginGuard` checks
that in one place for all routes, and the WebSocket uses the same rule.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from urllib.parse import urlsplit

from starlette.types import ASGIApp, Receive, Scope, Send

LOOPBACK_HOSTS = frozenset({"127.0.0.1", "localhost", "::1", "[::1]"})
CHANGES_STATE = frozenset({"POST", "PUT", "PATCH", "DELETE"})
TEST_HOST = "testserver"  # Starlette's TestClient


def _is_loopback(hostname: str) -> bool:
    return hostname in LOOPBACK_HOSTS or f"[{hostname}]" in LOOPBACK_HOSTS


def _authority(host: str, default_port: int) -> tuple[str, int] | None:
    """("127.0.0.1", 8000) from a Host header or URL netloc; None if unparsable."""
    try:
        parts = urlsplit(f"//{host}")
        return (parts.hostname or "", parts.port or default_port)
    except ValueError:
        return None


def origin_allowed(origin: str | None, host_header: str | None) -> bool:
    """No Origin (scripts, curl) is fine. A browser Origin must be a loopback host, and, when
    the Host header is known, the very host and port the request was sent to."""
    if origin is None:
        return True
    try:
        parts = urlsplit(origin)
        port = parts.port
    except ValueError:
        return False
    hostname = parts.hostname or ""
    if parts.scheme not in ("http", "https") or not _is_loopback(hostname):
        return False  # also "null" (sandboxed frames, file: pages)
    if host_header is None:
        return True
    served = _authority(host_header, 80)
    if served is None:
        return False
    served_host, served_port = served
    if served_host == TEST_HOST:
        return True
    default = 443 if parts.scheme == "https" else 80
    return _is_loopback(served_host) and (port or default) == served_port


def refusal(headers: dict[str, str]) -> str | None:
    """Why a state-changing request must be refused as cross-site, or None if it may pass.

    Origin decides when present; without it (older browsers on same-origin requests), the
    browser's Sec-Fetch-Site, then the Referer; with none of the three it is not a browser
    request from a web page (curl, scripts) and passes."""
    host = headers.get("host")
    origin = headers.get("origin")
    if origin is not None:
        return None if origin_allowed(origin, host) else origin
    site = headers.get("sec-fetch-site")
    if site is not None:
        return None if site in ("same-origin", "none") else f"a {site} page"
    referer = headers.get("referer")
    if referer is not None:
        parts = urlsplit(referer)
        source = f"{parts.scheme}://{parts.netloc}" if parts.scheme else referer
        return None if origin_allowed(source, host) else source
    return None


class HostGuard:
    """Pure ASGI middleware: only requests naming a loopback host are served (a DNS rebinding
    page names its own host), refused with 400 in the API's error shape."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] in ("http", "websocket"):
            host = _headers(scope["headers"]).get("host", "")
            served = _authority(host, 80)
            if served is None or not (_is_loopback(served[0]) or served[0] == TEST_HOST):
                if scope["type"] == "websocket":
                    await send({"type": "websocket.close", "code": 1008})
                    return
                message = (
                    f"refused a request for host {host!r}: ServoDesk answers only to "
                    "127.0.0.1, localhost and [::1]"
                )
                await _send_error(send, 400, "bad_host", message)
                return
        await self.app(scope, receive, send)


class SameOriginGuard:
    """Pure ASGI middleware (bodies stream through untouched): refuses state-changing HTTP
    requests from other sites with 403 in the API's error shape."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and scope["method"] in CHANGES_STATE:
            source = refusal(_headers(scope["headers"]))
            if source is not None:
                await _forbid(send, source)
                return
        await self.app(scope, receive, send)


def _headers(raw: Iterable[tuple[bytes, bytes]]) -> dict[str, str]:
    return {name.decode("latin-1").lower(): value.decode("latin-1") for name, value in raw}


async def _forbid(send: Send, source: str) -> None:
    message = f"refused a request from {source}: ServoDesk accepts changes only from its own pages"
    await _send_error(send, 403, "cross_origin", message)


async def _send_error(send: Send, status: int, error: str, message: str) -> None:
    body = json.dumps({"error": error, "message": message}).encode()
    await send(
        {
            "type": "http.response.start",
            "status": status,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(body)).encode()),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
