"""The live WebSocket (docs/api.md, WebSocket): pushes bus status, node states, events and the
watched drives' state; takes the page's hello, jog keep-alives and stops, page-hidden and quick
stop. Each socket has an owner (the hello's client id): when it closes, the owner's jogs stop."""

from __future__ import annotations

import asyncio
import contextlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from fastapi import APIRouter, FastAPI, WebSocket, WebSocketDisconnect
from pydantic import ValidationError

from servodesk.access.guard import POLICY_VIOLATION, Access
from servodesk.api.audited import outcome_of
from servodesk.api.errors import describe, validation_message
from servodesk.api.security import LOOPBACK, ServedHosts, origin_allowed
from servodesk.errors import ServodeskError
from servodesk.live import LiveClient
from servodesk.models.live import (
    CLIENT_MESSAGE,
    ClientMessageUnion,
    ErrorMessage,
    HelloMessage,
    JogKeepaliveMessage,
    JogStopMessage,
    JogStoppedMessage,
    PageHiddenMessage,
    PingMessage,
    PongMessage,
    QuickStopMessage,
    UnwatchDriveMessage,
    WatchDriveMessage,
    dump,
    openapi_components,
)
from servodesk.motion.jog import JogStoppedError
from servodesk.motion.lease import Client
from servodesk.motion.stop_reasons import Reason
from servodesk.services import Services

router = APIRouter()


@router.websocket("/ws")
async def live(websocket: WebSocket) -> None:
    # A page from another site must not drive the tool through the user's browser (DNS
    # rebinding / cross-site WebSocket): only our own origin may connect.
    hosts: ServedHosts = getattr(websocket.app.state, "hosts", LOOPBACK)
    if not origin_allowed(websocket.headers.get("origin"), websocket.headers.get("host"), hosts):
        await websocket.close(code=1008)
        return
    services: Services = websocket.app.state.services
    await websocket.accept()
    ends = _login_end(websocket)
    if ends is None:  # the login ended between the access check and here
        await websocket.close(code=POLICY_VIOLATION, reason=LOGIN_ENDED)
        return
    client = services.live.connect()
    sender = asyncio.create_task(_send(websocket, client))
    closer = asyncio.create_task(_close_at(websocket, ends))
    silence = services.settings.live_silence_s
    try:
        while True:
            try:
                raw = await asyncio.wait_for(websocket.receive_json(), silence)
            except TimeoutError:
                # gone without a close frame (a killed tab, a sleeping laptop): its drives are
                # released and its jogs stop in `finally`, as on any close
                with contextlib.suppress(RuntimeError, WebSocketDisconnect):
                    await websocket.close(code=GOING_AWAY, reason=SILENT.format(silence))
                break
            reply = await _handle(services, client, raw)
            if reply is not None:
                await websocket.send_json(reply)
    except (WebSocketDisconnect, RuntimeError, ValueError):
        pass
    finally:
        # first of all: jogs owned by this socket's client stop
        if not client.client.anonymous:
            services.safety.socket_closed(client.client.id)
            services.safety.socket_idle(client.client.id)
        services.live.disconnect(client)
        ends.unwatch()
        for task in (sender, closer):
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError, WebSocketDisconnect, RuntimeError):
                await task


LOGIN_ENDED = "the login ended: log in again"
GOING_AWAY = 1001  # RFC 6455 §7.4.1
SILENT = "nothing received for {:g} s: send a ping at least every 10 s"


@dataclass
class _LoginEnd:
    """When a socket's login session ends: set on logout or eviction, else at its expiry."""

    ended: asyncio.Event = field(default_factory=asyncio.Event)
    expires_in: float | None = None  # s; None: a token or no login, nothing ends it
    unwatch: Callable[[], None] = lambda: None


def _login_end(websocket: WebSocket) -> _LoginEnd | None:
    """Watch the socket's login session (the access check let it in); None if it has ended."""
    access: Access = websocket.app.state.access
    sid = access.session_id(websocket.headers)
    end = _LoginEnd()
    if sid is None:
        return end
    session = access.sessions.get(sid)
    unwatch = access.sessions.watch(sid, end.ended.set)
    if session is None or unwatch is None:
        return None
    end.unwatch = unwatch
    end.expires_in = max(0.0, session.expires - time.monotonic())
    return end


async def _close_at(websocket: WebSocket, end: _LoginEnd) -> None:
    """Close the socket when its login ends: a logged-out page must not keep receiving the
    drives' state or sending commands (its jogs stop, as on any close)."""
    with contextlib.suppress(TimeoutError):
        await asyncio.wait_for(end.ended.wait(), end.expires_in)
    with contextlib.suppress(RuntimeError, WebSocketDisconnect):
        await websocket.close(code=POLICY_VIOLATION, reason=LOGIN_ENDED)


async def _handle(services: Services, client: LiveClient, raw: Any) -> dict[str, Any] | None:
    """Act on one client message; returns the direct answer, if any."""
    try:
        message: ClientMessageUnion = CLIENT_MESSAGE.validate_python(raw)
    except ValidationError as error:
        return dump(
            ErrorMessage(error="invalid_message", message=validation_message(error.errors()))
        )
    safety = services.safety
    try:
        match message:
            case PingMessage():
                return dump(PongMessage())
            case HelloMessage(client_id=client_id, name=name):
                named = Client(id=client_id, name=name)
                safety.claim(named)  # another login's id is refused: no impersonation
                if not client.client.anonymous:
                    safety.socket_closed(client.client.id)  # a second hello renames the owner
                    safety.socket_idle(client.client.id)
                client.client = named
                safety.socket_opened(client_id)
                for node in client.watching:
                    services.live.watch(client, node)  # "you" may have changed
            case JogKeepaliveMessage(jog_id=jog_id):
                safety.keepalive(jog_id, client.client)  # only from the jog's owner
            case JogStopMessage(jog_id=jog_id):
                async with services.audit.entry(
                    "jog-stop", None, f"stop jog {jog_id} (live channel)", outcome_of, wait=False
                ):
                    await safety.jogs.stop(jog_id, Reason("stop.user"))
            case PageHiddenMessage():
                if not client.client.anonymous:
                    safety.page_hidden(client.client.id)
            case QuickStopMessage(node=node):
                # on a task of its own: the reading after the stop must not hold back the
                # socket's next message (a second stop, a keep-alive of another jog)
                task = asyncio.create_task(_quick_stop(services, client, node))
                client.background.add(task)
                task.add_done_callback(client.background.discard)
            case WatchDriveMessage(node=node):
                services.registry.info(node)
                services.live.watch(client, node)
            case UnwatchDriveMessage(node=node):
                services.live.unwatch(client, node)
    except JogStoppedError as stopped:
        return dump(JogStoppedMessage(jog=stopped.info))
    except ServodeskError as error:
        return dump(ErrorMessage(error=describe(error)[1].error, message=str(error)))
    return None


async def _quick_stop(services: Services, client: LiveClient, node: int | None) -> None:
    """A quick stop from the live channel, audited; what went wrong goes back as `error`."""
    what = "every drive" if node is None else f"node {node}"
    try:
        async with services.audit.entry(
            "quick-stop", node, f"quick stop of {what} (live channel)", outcome_of, wait=False
        ):
            if node is None:
                await services.safety.quick_stop_all()
            else:
                await services.safety.quick_stop(node)
    except ServodeskError as error:
        client.event(dump(ErrorMessage(error=describe(error)[1].error, message=str(error))))


async def _send(websocket: WebSocket, client: LiveClient) -> None:
    while True:
        for message in await client.next_messages():
            await websocket.send_json(message)


def install_live_schema(app: FastAPI) -> None:
    """Add the WebSocket's message models to the OpenAPI components, so `npm run gen:api`
    generates their TypeScript types (`ServerMessage`, `ClientMessage`)."""
    build = app.openapi

    def openapi() -> dict[str, Any]:
        schema = build()
        components = schema.setdefault("components", {}).setdefault("schemas", {})
        for name, definition in openapi_components().items():
            components.setdefault(name, definition)
        return schema

    app.openapi = openapi  # type: ignore[method-assign]  # FastAPI's documented override
