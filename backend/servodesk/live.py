"""Live state for the browser over one WebSocket: bus status, node states, events.

Each client keeps only the newest bus and node snapshot plus a short queue of events, so a slow
browser skips stale states instead of building up a backlog (docs/api.md, WebSocket).
"""

from __future__ import annotations

import asyncio
import contextlib
from collections import deque
from typing import Any

from servodesk.bus.connection import BusManager
from servodesk.models import BusStatus, LiveEvent
from servodesk.nodes.registry import NodeRegistry

NODES_PERIOD = 0.2  # s: node states at 5 Hz
BUS_PERIOD = 2.0  # s: bus status (counters) even when nothing changed
EVENT_BACKLOG = 100  # per client; older events are dropped for a client that does not read
RECENT_EVENTS = 200  # kept by the server for pages that connect later (a reload loses none)


class LiveClient:
    def __init__(self) -> None:
        self._latest: dict[str, dict[str, Any]] = {}
        self._events: deque[dict[str, Any]] = deque(maxlen=EVENT_BACKLOG)
        self._ready = asyncio.Event()

    def offer(self, kind: str, message: dict[str, Any]) -> None:
        self._latest[kind] = message
        self._ready.set()

    def event(self, message: dict[str, Any]) -> None:
        self._events.append(message)
        self._ready.set()

    async def next_messages(self) -> list[dict[str, Any]]:
        await self._ready.wait()
        self._ready.clear()
        messages = list(self._events)
        self._events.clear()
        messages += self._latest.values()
        self._latest.clear()
        return messages


class LiveHub:
    def __init__(self, bus: BusManager, registry: NodeRegistry) -> None:
        self._bus = bus
        self._registry = registry
        self._clients: set[LiveClient] = set()
        self._recent: deque[dict[str, Any]] = deque(maxlen=RECENT_EVENTS)
        self._task: asyncio.Task[None] | None = None
        self._unsubscribe = [
            bus.add_listener(self._on_bus),
            registry.add_event_listener(self._on_event),
        ]

    def start(self) -> None:
        if self._task is None:
            self._task = asyncio.create_task(self._run(), name="live-hub")

    async def close(self) -> None:
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
            self._task = None

    def connect(self) -> LiveClient:
        client = LiveClient()
        self._clients.add(client)
        # first the recent events (a page that reloads or reconnects replaces its list with it)
        client.event({"type": "history", "events": list(self._recent)})
        client.offer("bus", self._bus_message(self._bus.status()))
        client.offer("nodes", self._nodes_message())
        return client

    def disconnect(self, client: LiveClient) -> None:
        self._clients.discard(client)

    def _bus_message(self, status: BusStatus) -> dict[str, Any]:
        return {"type": "bus", "bus": status.model_dump(mode="json")}

    def _nodes_message(self) -> dict[str, Any]:
        return {"type": "nodes", "nodes": self._registry.live()}

    def _on_bus(self, status: BusStatus) -> None:
        message = self._bus_message(status)
        for client in self._clients:
            client.offer("bus", message)

    def _on_event(self, event: LiveEvent) -> None:
        dumped = event.model_dump(mode="json")
        self._recent.append(dumped)
        message = {"type": "event", "event": dumped}
        for client in self._clients:
            client.event(message)

    async def _run(self) -> None:
        ticks_per_bus = round(BUS_PERIOD / NODES_PERIOD)
        tick = 0
        while True:
            await asyncio.sleep(NODES_PERIOD)
            if not self._clients:
                continue
            nodes = self._nodes_message()
            bus = self._bus_message(self._bus.status()) if tick % ticks_per_bus == 0 else None
            tick += 1
            for client in self._clients:
                client.offer("nodes", nodes)
                if bus is not None:
                    client.offer("bus", bus)
