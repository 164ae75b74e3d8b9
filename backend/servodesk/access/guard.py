"""The access check in front of every request: who is asking (bearer token, login cookie, or
the local user when no tokens are configured), whether their role may, and the acting user
for the audit log (docs/security.md)."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping

from starlette.requests import cookie_parser
from starlette.types import ASGIApp, Receive, Scope, Send

from servodesk.access.actor import LOCAL_USER, Actor, Role, acting
from servodesk.access.policy import WHAT_NEEDS, required_role
from servodesk.access.sessions import COOKIE, LoginLimiter, SessionStore
from servodesk.access.tokens import TokenTable

# WebSocket close code for a policy violation (RFC 6455 §7.4.1)
POLICY_VIOLATION = 1008


class Access:
    """The app's tokens, login sessions and login rate limit."""

    def __init__(
        self,
        tokens: TokenTable,
        *,
        secure_cookies: bool = False,
        limiter: LoginLimiter | None = None,
    ) -> None:
        self.tokens = tokens
        self.sessions = SessionStore()
        self.limiter = limiter or LoginLimiter()
        self.secure_cookies = secure_cookies  # served over TLS: the cookie says Secure

    @property
    def required(self) -> bool:
        return self.tokens.configured

    def actor(self, headers: Mapping[str, str], client: str | None) -> Actor | None:
        """The acting user of a request, None when it presents no valid credential."""
        if not self.required:
            return Actor(LOCAL_USER, Role.ENGINEER, client)
        scheme, _, token = headers.get("authorization", "").partition(" ")
        if scheme.lower() == "bearer" and token.strip():
            credential = self.tokens.lookup(token.strip())
            return None if credential is None else Actor(credential.user, credential.role, client)
        sid = self.session_id(headers)
        if sid:
            session = self.sessions.get(sid)
            if session is not None:
                return Actor(session.user, session.role, client)
        return None

    def session_id(self, headers: Mapping[str, str]) -> str | None:
        """The login session a request rides on: its cookie's, unless a bearer token (which
        wins in `actor`) is presented or no tokens are configured."""
        if not self.required or _presents_bearer(headers):
            return None
        return cookie_parser(headers.get("cookie", "")).get(COOKIE) or None


def client_host(scope: Scope) -> str:
    """The client's address without its port, as the login limit counts it."""
    client = scope.get("client")
    return str(client[0]) if client else "unknown"


def _presents_bearer(headers: Mapping[str, str]) -> bool:
    scheme, _, token = headers.get("authorization", "").partition(" ")
    return scheme.lower() == "bearer" and bool(token.strip())


def client_address(scope: Scope) -> str | None:
    client = scope.get("client")
    if not client:
        return None
    host, port = client
    return f"{host}:{port}"


class AccessGuard:
    """Pure ASGI middleware (bodies stream through untouched): 401 without a valid credential
    where one is needed, 403 for a role that may not; sets the acting user for the request."""

    def __init__(self, app: ASGIApp, access: Access) -> None:
        self.app = app
        self.access = access

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
        method = "WEBSOCKET" if scope["type"] == "websocket" else scope["method"]
        path: str = scope["path"]
        needed = required_role(method, path)
        guessing = self.access.required and _presents_bearer(headers)
        host = client_host(scope)
        if guessing:  # a bearer token counts toward the login limit (api/access.py)
            wait = self.access.limiter.retry_after(host)
            if wait > 0:
                if scope["type"] == "websocket":
                    await send({"type": "websocket.close", "code": POLICY_VIOLATION})
                    return
                await _too_many(send, host, wait)
                return
        actor = self.access.actor(headers, client_address(scope))
        if guessing and actor is None:
            self.access.limiter.failed(host)
        if needed is not None and (actor is None or not actor.may(needed)):
            if scope["type"] == "websocket":
                await send({"type": "websocket.close", "code": POLICY_VIOLATION})
                return
            if actor is None:
                await _send_json(send, 401, _unauthorized(headers), {"www-authenticate": "Bearer"})
            else:
                await _send_json(send, 403, _forbidden(actor, needed, method, path))
            return
        if actor is None:  # an open route (login, health) asked without a credential
            actor = Actor("anonymous", Role.VIEWER, client_address(scope))
        scope.setdefault("state", {})["actor"] = actor
        with acting(actor):
            await self.app(scope, receive, send)


def _unauthorized(headers: Mapping[str, str]) -> dict[str, str]:
    if headers.get("authorization"):
        message = "the access token is not valid: check it, or ask for a new one"
    elif COOKIE in headers.get("cookie", ""):
        message = "the login has expired or ended: log in again"
    else:
        message = (
            "log in first: ServoDesk needs an access token here "
            "(browser: the login page; scripts: Authorization: Bearer <token>)"
        )
    return {"error": "unauthorized", "message": message}


def _forbidden(actor: Actor, needed: Role, method: str, path: str) -> dict[str, str]:
    return {
        "error": "forbidden",
        "message": (
            f"the {actor.role.label} role may not {method} {path}: that needs "
            f"{WHAT_NEEDS[needed]}; log in with such a token"
        ),
        "role": actor.role.label,
        "required": needed.label,
    }


async def _too_many(send: Send, host: str, wait: float) -> None:
    seconds = max(1, math.ceil(wait))
    body = {
        "error": "rate_limited",
        "message": f"too many wrong access tokens from {host}: try again in {seconds} s",
        "retry_after_s": seconds,
    }
    await _send_json(send, 429, body, {"retry-after": str(seconds)})


async def _send_json(
    send: Send, status: int, content: Mapping[str, object], headers: dict[str, str] | None = None
) -> None:
    body = json.dumps(content).encode()
    raw = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    raw += [(k.encode(), v.encode()) for k, v in (headers or {}).items()]
    await send({"type": "http.response.start", "status": status, "headers": raw})
    await send({"type": "http.response.body", "body": body})
