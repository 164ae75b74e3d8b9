"""Logging in and out, and who the caller is (docs/security.md, "Access")."""

from __future__ import annotations

import math
from typing import Annotated, Literal, cast

from fastapi import APIRouter, Request, Response
from fastapi.responses import JSONResponse
from pydantic import BaseModel, Field

from servodesk.access.actor import Actor, Role, current_actor
from servodesk.access.guard import Access
from servodesk.access.sessions import COOKIE
from servodesk.api.audited import AuditedRoute
from servodesk.api.errors import body_response
from servodesk.models.base import RequestBody
from servodesk.models.common import ErrorBody

router = APIRouter(tags=["access"], route_class=AuditedRoute)

RoleName = Literal["viewer", "operator", "engineer"]


class Permissions(BaseModel):
    operate: bool  # enable, jog, home, fault reset, scope
    configure: bool  # parameters, OD, PDOs, DCF, store/restore, NMT, node id/bitrate


class SessionInfo(BaseModel):
    user: str
    role: RoleName
    auth_required: bool
    may: Permissions


class LoginRequest(RequestBody):
    token: Annotated[str, Field(min_length=1, max_length=512)]


LOGIN_ERRORS: dict[int | str, dict[str, object]] = {
    401: {"model": ErrorBody, "description": "The token is not valid"},
    429: {"model": ErrorBody, "description": "Too many failed logins: wait `retry_after_s`"},
}


def _info(actor: Actor, access: Access) -> SessionInfo:
    return SessionInfo(
        user=actor.user,
        role=cast(RoleName, actor.role.label),
        auth_required=access.required,
        may=Permissions(operate=actor.may(Role.OPERATOR), configure=actor.may(Role.ENGINEER)),
    )


def _access(request: Request) -> Access:
    access: Access = request.app.state.access
    return access


@router.get("/session")
async def session(request: Request) -> SessionInfo:
    """Who the caller is and what their role may do (401 when a login is needed)."""
    return _info(current_actor(), _access(request))


@router.post("/login", responses=LOGIN_ERRORS, response_model=SessionInfo)
async def login(
    body: LoginRequest, request: Request, response: Response
) -> SessionInfo | JSONResponse:
    """Trade an access token for a login cookie (HttpOnly, SameSite=Strict; Secure over TLS)."""
    access = _access(request)
    if not access.required:
        return _info(current_actor(), access)
    client = request.client.host if request.client else "unknown"
    wait = access.limiter.retry_after(client)
    if wait > 0:
        seconds = max(1, math.ceil(wait))
        return body_response(
            429,
            ErrorBody(
                error="rate_limited",
                message=f"too many failed logins from {client}: try again in {seconds} s",
                retry_after_s=seconds,
            ),
            {"Retry-After": str(seconds)},
        )
    credential = access.tokens.lookup(body.token.strip())
    if credential is None:
        access.limiter.failed(client)
        return body_response(
            401, ErrorBody(error="unauthorized", message="that token is not valid: check it")
        )
    sid = access.sessions.create(credential.user, credential.role)
    response.set_cookie(
        COOKIE,
        sid,
        max_age=int(access.sessions.max_age_s),
        httponly=True,
        samesite="strict",
        secure=access.secure_cookies,
        path="/",
    )
    actor = Actor(credential.user, credential.role, None)
    return _info(actor, access)


@router.post("/logout", status_code=204, response_class=Response)
async def logout(request: Request) -> Response:
    """End the browser's login (the cookie is cleared and forgotten by the server)."""
    sid = request.cookies.get(COOKIE)
    if sid:
        _access(request).sessions.end(sid)
    answer = Response(status_code=204)
    answer.delete_cookie(COOKIE, path="/", httponly=True, samesite="strict")
    return answer
