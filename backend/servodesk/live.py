"""Live state for the browser over one WebSocket: bus status, node states, events, the timeline
(every event of the event bus) and each node's active fault, and for the drive panel the watched
drives' state (~10 Hz), who controls them, and stopped jogs.

Each client keeps only the newest snapshot per kind plus a short queue of events, so a slow
browser skips stale states instead of building up a backlog (docs/api.md, WebSocket). Message
shapes are the models of models/live.py.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
from collections import deque
from collections.abc import Callable
from typing import Any

from servodesk.bus.connection import BusManager
from servodesk.errors import ServodeskError
from servodesk.events.bus import BusEvent, EventBus, EventKind
from servodesk.models.bus import BusStatus
from servodesk.models.faults import Fault, TimelineEvent
from servodesk.models.live import (
    BusMessage,
    ControllerMessage,
    DriveStateMessage,
    EventMessage,
    FaultMessage,
    JogStoppedMessage,
    TimelineMessage,
    dump,
)
from servodesk.models.nodes import LiveEvent, NodeEventKind
from servodesk.models.safety import JogInfo
from servodesk.motion.lease import Client
from servodesk.motion.safety import MotionSafety
from servodesk.nodes.registry import NodeRegistry

log = logging.getLogger(__name__)

NODES_PERIOD = 0.2  # s: node states at 5 Hz
BUS_PERIOD = 2.0  # s: bus status (counters) even when nothing changed
DRIVE_PERIOD = 0.1  # s: a watched drive's state at ~10 Hz
EVENT_BACKLOG = 100  # per client; older events are dropped for a client that does not read
RECENT_EVENTS = 200  # kept by the server for pages that connect later (a reload loses none)
# the kinds the channel sends as `event` (LiveEvent.kind): what the registry publishes
NODE_EVENT_KINDS: dict[EventKind, NodeEventKind] = {
    EventKind.BOOT_UP: "boot-up",
    EventKind.NODE_LOST: "node-lost",
    EventKind.NODE_BACK: "node-back",
    EventKind.NMT: "nmt",
    EventKind.BUS: "bus",
}
# timeline events per client, apart from the events above: an EMCY storm never pushes the
# Network page's events (or the history) out; a page that misses some sees a gap in the ids
TIMELINE_BACKLOG = 500

EventId = Callable[[BusEvent], int | None]  # the timeline id the store gave an event


class LiveClient:
    def __init__(self) -> None:
        self._latest: dict[str, dict[str, Any]] = {}
        self._events: deque[dict[str, Any]] = deque(maxlen=EVENT_BACKLOG)
        self._timeline: deque[dict[str, Any]] = deque(maxlen=TIMELINE_BACKLOG)
        self._ready = asyncio.Event()
        # Set by the socket's `hello`; until then the socket is anonymous and owns no jogs.
        self.client = Client(id="", anonymous=True)
        self.watching: set[int] = set()
        # the socket's quick stops in flight: they finish even when the socket closes
        self.background: set[asyncio.Task[None]] = set()

    def offer(self, kind: str, message: dict[str, Any]) -> None:
        self._latest[kind] = message
        self._ready.set()

    def event(self, message: dict[str, Any]) -> None:
        self._events.append(message)
        self._ready.set()

    def timeline(self, message: dict[str, Any]) -> None:
        self._timeline.append(message)
        self._ready.set()

    async def next_messages(self) -> list[dict[str, Any]]:
        await self._ready.wait()
        self._ready.clear()
        messages = list(self._events)
        self._events.clear()
        messages += self._timeline
        self._timeline.clear()
        messages += self._latest.values()
        self._latest.clear()
        return messages


class LiveHub:
    def __init__(self, bus: BusManager, registry: NodeRegistry, safety: MotionSafety) -> None:
        self._bus = bus
        self._registry = registry
        self._safety = safety
        self._clients: set[LiveClient] = set()
        self._recent: deque[dict[str, Any]] = deque(maxlen=RECENT_EVENTS)
        self._task: asyncio.Task[None] | None = None
        self._pollers: dict[int, asyncio.Task[None]] = {}
        self._unsubscribe = [
            bus.add_listener(self._on_bus),
            registry.events.subscribe(self._on_event),
        ]
        safety.lease.add_listener(self._on_controller)
        safety.jogs.add_listener(self._on_jog_stopped)
        self._event_id: EventId = lambda _item: None
        self._active_faults: Callable[[], list[Fault]] = list

    def follow_diagnostics(
        self,
        events: EventBus,
        event_id: EventId,
        add_fault_listener: Callable[[Callable[[int, Fault | None], None]], Callable[[], None]],
        active_faults: Callable[[], list[Fault]],
    ) -> None:
        """Push every event of `events` as a `timeline` message (with the id `event_id` tells:
        subscribe after the store) and each change of a node's active fault as `fault`."""
        self._event_id = event_id
        self._active_faults = active_faults
        self._unsubscribe += [
            events.subscribe(self._on_timeline),
            add_fault_listener(self._on_fault),
        ]

    def start(self) -> None:
        if self._task is None:
            self._task = asyncio.create_task(self._run(), name="live-hub")

    async def close(self) -> None:
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        tasks = [t for t in (self._task, *self._pollers.values()) if t is not None]
        for task in tasks:
            task.cancel()
        for task in tasks:
            with contextlib.suppress(asyncio.CancelledError):
                await task
        self._task = None
        self._pollers.clear()

    def connect(self) -> LiveClient:
        client = LiveClient()
        self._clients.add(client)
        # first the recent events (a page that reloads or reconnects replaces its list with it)
        client.event({"type": "history", "events": list(self._recent)})
        client.offer("bus", self._bus_message(self._bus.status()))
        client.offer("nodes", self._nodes_message())
        for fault in self._active_faults():  # the banner is right from the start
            client.offer(f"fault:{fault.node}", dump(FaultMessage(node=fault.node, fault=fault)))
        return client

    def disconnect(self, client: LiveClient) -> None:
        self._clients.discard(client)
        for node in list(client.watching):
            self.unwatch(client, node)

    def watch(self, client: LiveClient, node: int) -> None:
        """Send `client` the node's drive state at ~10 Hz and who controls it."""
        client.watching.add(node)
        self._send_controller(client, node)
        if node not in self._pollers:
            self._pollers[node] = asyncio.create_task(self._poll(node), name=f"drive-state {node}")

    def unwatch(self, client: LiveClient, node: int) -> None:
        client.watching.discard(node)
        if not any(node in c.watching for c in self._clients):
            poller = self._pollers.pop(node, None)
            if poller is not None:
                poller.cancel()

    def _bus_message(self, status: BusStatus) -> dict[str, Any]:
        return dump(BusMessage(bus=status))

    def _nodes_message(self) -> dict[str, Any]:
        # registry rows are already the LiveNode shape: no model round trip at 5 Hz
        return {"type": "nodes", "nodes": self._registry.live()}

    def _on_bus(self, status: BusStatus) -> None:
        message = self._bus_message(status)
        for client in self._clients:
            client.offer("bus", message)

    def _on_event(self, item: BusEvent) -> None:
        """The node and bus events, in the channel's `event` message (its wire form, LiveEvent);
        the other kinds reach the page as timeline entries (`_on_timeline`)."""
        kind = NODE_EVENT_KINDS.get(item.kind)
        if kind is None:
            return
        event = LiveEvent(
            time=item.time,
            node=item.node,
            kind=kind,
            message=item.message,
            message_id=item.message_id,
            params=item.params,
        )
        dumped = event.model_dump(mode="json")
        self._recent.append(dumped)
        message = dump(EventMessage(event=event))
        for client in self._clients:
            client.event(message)

    def _on_timeline(self, item: BusEvent) -> None:
        if not self._clients:
            return
        event_id = self._event_id(item)
        if event_id is None:
            return  # not stored (the store is not open yet): it has no id to page from
        timeline = TimelineEvent(
            id=event_id,
            time=item.time,
            kind=item.kind.value,
            node=item.node,
            message=item.message,
            data=json.loads(json.dumps(item.data, default=str)),  # as the store keeps it
            message_id=item.message_id,
            params=item.params,
        )
        message = dump(TimelineMessage(event=timeline))
        for client in self._clients:
            client.timeline(message)

    def _on_fault(self, node: int, fault: Fault | None) -> None:
        message = dump(FaultMessage(node=node, fault=fault))
        for client in self._clients:
            client.offer(f"fault:{node}", message)

    def _on_controller(self, node: int) -> None:
        for client in self._clients:
            self._send_controller(client, node)

    def _send_controller(self, client: LiveClient, node: int) -> None:
        try:
            info = self._safety.controller(node, client.client)
        except ServodeskError:
            return  # the node is gone
        message = ControllerMessage(
            node=node, holder=info.holder, you=info.you, protection=info.protection
        )
        client.offer(f"controller:{node}", dump(message))

    def _on_jog_stopped(self, jog: JogInfo) -> None:
        message = dump(JogStoppedMessage(jog=jog))
        for client in self._clients:
            if client.client.id == jog.owner or jog.node in client.watching:
                client.event(message)

    async def _poll(self, node: int) -> None:
        loop = asyncio.get_running_loop()
        while True:
            started = loop.time()
            try:
                state = await self._safety.motion.polled_state(node)
            except ServodeskError as error:
                log.debug("drive state of node %d: %s", node, error)
            else:
                message = dump(DriveStateMessage(node=node, state=state))
                for client in self._clients:
                    if node in client.watching:
                        client.offer(f"drive:{node}", message)
            await asyncio.sleep(max(0.0, DRIVE_PERIOD - (loop.time() - started)))

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
