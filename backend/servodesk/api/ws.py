"""The live WebSocket: pushes bus status, node states and events (docs/api.md)."""

from __future__ import annotations

import asyncio
import contextlib

from fastapi import APIRouter, WebSocket, WebSocketDisconnect

from servodesk.api.security import origin_allowed
from servodesk.live import LiveClient
from servodesk.services import Services

router = APIRouter()


@router.websocket("/ws")
async def live(websocket: WebSocket) -> None:
    # A page from another site must not drive the tool through the user's browser (DNS
    # rebinding / cross-site WebSocket): only our own origin may connect.
    if not origin_allowed(websocket.headers.get("origin"), websocket.headers.get("host")):
        await websocket.close(code=1008)
        return
    services: Services = websocket.app.state.services
    await websocket.accept()
    client = services.live.connect()
    sender = asyncio.create_task(_send(websocket, client))
    try:
        while True:
            message = await websocket.receive_json()
            if isinstance(message, dict) and message.get("type") == "ping":
                await websocket.send_json({"type": "pong"})
    except (WebSocketDisconnect, RuntimeError, ValueError):
        pass
    finally:
        services.live.disconnect(client)
        sender.cancel()
        with contextlib.suppress(asyncio.CancelledError, WebSocketDisconnect, RuntimeError):
            await sender


async def _send(websocket: WebSocket, client: LiveClient) -> None:
    while True:
        for message in await client.next_messages():
            await websocket.send_json(message)
