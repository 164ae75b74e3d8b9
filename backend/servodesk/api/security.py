"""Host checks against DNS rebinding, Origin checks against cross-site requests (DESIGN:
Security), both against the origins the app is served on (`ServedHosts`): loopback by default,
plus the bound address and the names given with `--allowed-host` when serving beyond loopback
(which needs access tokens: servodesk.access). Browsers
send form, multipart and text/plain posts to any site without asking first (no CORS preflight),
so every state-changing request must come from one of our own pages: `SameOriginGuard` checks
that in one place for all routes, and the WebSocket uses the same rule.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from urllib.parse import urlsplit

from starlette.types import ASGIApp, Message, Receive, Scope, Send

LOOPBACK_HOSTS = frozenset({"127.0.0.1", "localhost", "::1", "[::1]"})
CHANGES_STATE = frozenset({"POST", "PUT", "PATCH", "DELETE"})
# Headers these checks decide on: sent twice, a proxy and the app may each read another one
# (another site's Origin first, ours second), so such a request is refused outright.
SINGLE = ("host", "origin", "referer", "sec-fetch-site")
# Pages may be framed by nobody (clickjacking on Enable and jog), the rerun viewer only by our
# own Scope page.
FRAMED_BY_US = "/rerun"


def _is_loopback(hostname: str) -> bool:
    return hostname in LOOPBACK_HOSTS or f"[{hostname}]" in LOOPBACK_HOSTS


class ServedHosts:
    """The host names and addresses requests may name: loopback always, plus `extra` (the
    address the server is bound to, the names users reach it by)."""

    def __init__(self, extra: Iterable[str] = ()) -> None:
        names = (h.strip().lower().strip("[]") for h in extra)
        self.extra = frozenset(n for n in names if n and not _is_loopback(n))

    def allows(self, hostname: str) -> bool:
        name = hostname.lower().strip("[]")
        return _is_loopback(name) or name in self.extra

    def describe(self) -> str:
        names = ["127.0.0.1", "localhost", "[::1]", *sorted(self.extra)]
        return f"{', '.join(names[:-1])} and {names[-1]}"


LOOPBACK = ServedHosts()


def _authority(host: str, default_port: int) -> tuple[str, int] | None:
    """("127.0.0.1", 8000) from a Host header or URL netloc; None if unparsable."""
    try:
        parts = urlsplit(f"//{host}")
        return (parts.hostname or "", parts.port or default_port)
    except ValueError:
        return None


def origin_allowed(
    origin: str | None, host_header: str | None, hosts: ServedHosts = LOOPBACK
) -> bool:
    """No Origin (scripts, curl) is fine. A browser Origin must be a served host, and, when
    the Host header is known, the very host and port the request was sent to."""
    if origin is None:
        return True
    try:
        parts = urlsplit(origin)
        port = parts.port
    except ValueError:
        return False
    hostname = parts.hostname or ""
    if parts.scheme not in ("http", "https") or not hosts.allows(hostname):
        return False  # also "null" (sandboxed frames, file: pages)
    if host_header is None:
        return True
    served = _authority(host_header, 80)
    if served is None:
        return False
    served_host, served_port = served
    default = 443 if parts.scheme == "https" else 80
    same_host = served_host.lower().strip("[]") == hostname.lower().strip("[]") or (
        _is_loopback(served_host) and _is_loopback(hostname)
    )
    return hosts.allows(served_host) and same_host and (port or default) == served_port


def refusal(headers: dict[str, str], hosts: ServedHosts = LOOPBACK) -> str | None:
    """Why a state-changing request must be refused as cross-site, or None if it may pass.

    Origin decides when present; without it (older browsers on same-origin requests), the
    browser's Sec-Fetch-Site, then the Referer; with none of the three it is not a browser
    request from a web page (curl, scripts) and passes."""
    host = headers.get("host")
    origin = headers.get("origin")
    if origin is not None:
        return None if origin_allowed(origin, host, hosts) else origin
    site = headers.get("sec-fetch-site")
    if site is not None:
        return None if site in ("same-origin", "none") else f"a {site} page"
    referer = headers.get("referer")
    if referer is not None:
        parts = urlsplit(referer)
        source = f"{parts.scheme}://{parts.netloc}" if parts.scheme else referer
        return None if origin_allowed(source, host, hosts) else source
    return None


class HostGuard:
    """Pure ASGI middleware: only requests naming a served host are served (a DNS rebinding
    page names its own host), refused with 400 in the API's error shape."""

    def __init__(self, app: ASGIApp, hosts: ServedHosts = LOOPBACK) -> None:
        self.app = app
        self.hosts = hosts

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] in ("http", "websocket"):
            headers, repeated = _headers(scope["headers"])
            host = headers.get("host", "")
            served = _authority(host, 80)
            message = None
            if repeated:
                message = (
                    f"refused a request with more than one {repeated[0]} header: send each once"
                )
            elif served is None or not self.hosts.allows(served[0]):
                message = (
                    f"refused a request for host {host!r}: ServoDesk answers only to "
                    f"{self.hosts.describe()}"
                )
            if message is not None:
                if scope["type"] == "websocket":
                    await send({"type": "websocket.close", "code": 1008})
                    return
                await _send_error(send, 400, "bad_header" if repeated else "bad_host", message)
                return
        await self.app(scope, receive, send)


class SameOriginGuard:
    """Pure ASGI middleware (bodies stream through untouched): refuses state-changing HTTP
    requests from other sites with 403 in the API's error shape."""

    def __init__(self, app: ASGIApp, hosts: ServedHosts = LOOPBACK) -> None:
        self.app = app
        self.hosts = hosts

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and scope["method"] in CHANGES_STATE:
            source = refusal(_headers(scope["headers"])[0], self.hosts)
            if source is not None:
                await _forbid(send, source)
                return
        await self.app(scope, receive, send)


class FramingGuard:
    """Pure ASGI middleware: every HTTP answer says who may frame it (`X-Frame-Options` and
    CSP `frame-ancestors`: nobody; the rerun viewer: our own pages), and that its type is
    the one declared (`nosniff`). A page's own Content-Security-Policy is kept and given
    `frame-ancestors` where it has none."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        path: str = scope["path"]
        ours = path == FRAMED_BY_US or path.startswith(f"{FRAMED_BY_US}/")
        frame_option = b"SAMEORIGIN" if ours else b"DENY"
        ancestors = "frame-ancestors 'self'" if ours else "frame-ancestors 'none'"

        async def framed(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = [
                    (name, value)
                    for name, value in message.get("headers", [])
                    if name.lower() not in (b"x-frame-options", b"x-content-type-options")
                ]
                csp = [v for n, v in headers if n.lower() == b"content-security-policy"]
                if not csp:
                    headers.append((b"content-security-policy", ancestors.encode()))
                elif b"frame-ancestors" not in csp[0]:
                    headers = [
                        (n, v + b"; " + ancestors.encode())
                        if n.lower() == b"content-security-policy"
                        else (n, v)
                        for n, v in headers
                    ]
                headers += [
                    (b"x-frame-options", frame_option),
                    (b"x-content-type-options", b"nosniff"),
                ]
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, receive, framed)


def _headers(raw: Iterable[tuple[bytes, bytes]]) -> tuple[dict[str, str], list[str]]:
    """The headers by lower-case name, and which of SINGLE came more than once."""
    headers: dict[str, str] = {}
    repeated: list[str] = []
    for name, value in raw:
        key = name.decode("latin-1").lower()
        if key in headers and key in SINGLE and key not in repeated:
            repeated.append(key)
        headers[key] = value.decode("latin-1")
    return headers, repeated


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
