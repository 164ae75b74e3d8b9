"""NodeRegistry: which nodes are on the bus, what they are, and how to reach them.

Composed of the table it shares with its parts (nodes/table.py), the scanner that finds and
identifies nodes (nodes/scanner.py) and the dictionary swaps (nodes/dictionaries.py); it keeps
the lookups, NMT and heartbeat commands, and the bus-status lifecycle, and publishes the node
and bus events on the app's event bus.

Each known node has an identity (1000h, 1018h, 1008h), a profile (profiles/match.py), an object
dictionary model (the profile's EDS or the user's upload, kept in memory only) and a session
bound to the current connection's canopen Network. The registry empties itself when the bus is
disconnected; after a reconnect (a new Network) it binds every node's session again.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from servodesk.bus.connection import BusManager
from servodesk.errors import (
    CommTimeoutError,
    InvalidValueError,
    NodeStoppedError,
    SdoAbortError,
    StateConflictError,
)
from servodesk.events.bus import EventBus, EventKind, event
from servodesk.events.texts import Said, say
from servodesk.models.bus import BusState, BusStatus
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NodeInfo, ScanResult
from servodesk.network.monitor import NodeMonitor
from servodesk.network.nmt import STATE_AFTER, send_broadcast, send_to_node
from servodesk.network.scan import NODE_IDS
from servodesk.nodes.dictionaries import DictionarySwap
from servodesk.nodes.entry import NodeEntry, OdSource, live_row
from servodesk.nodes.heartbeat_floor import HEARTBEAT_FLOOR_MS as HEARTBEAT_FLOOR_MS
from servodesk.nodes.heartbeat_floor import check_heartbeat_time
from servodesk.nodes.identity import PRODUCER_HEARTBEAT
from servodesk.nodes.moved import moved
from servodesk.nodes.profile_dictionaries import ProfileDictionaries
from servodesk.nodes.rediscovery import Rediscovery
from servodesk.nodes.scanner import Scanner
from servodesk.nodes.session import NodeSession
from servodesk.nodes.table import NodeTable
from servodesk.od import ObjectDictionaryModel
from servodesk.od.parser import OdParser
from servodesk.profiles import ProfileMatch, load_known
from servodesk.settings import Settings
from servodesk_data import DriveData

log = logging.getLogger(__name__)

OdListener = Callable[[int], None]  # (node) whose dictionary was replaced
MAX_HEARTBEAT_MS = 0xFFFF  # 1017h is UNSIGNED16


def _check_id(node: int) -> None:
    if not NODE_IDS.start <= node < NODE_IDS.stop:
        raise InvalidValueError(f"node id {node} is outside 1–127")


class NodeRegistry:
    def __init__(
        self,
        bus: BusManager,
        settings: Settings,
        *,
        parser: OdParser | None = None,
        events: EventBus | None = None,
    ) -> None:
        """`parser` parses the profiles' dictionaries (the app's own; one of the registry's
        when none is given). `events` is the app's event bus: boot-ups, nodes lost and back,
        the NMT commands the tool sends and bus changes are published there, typed (a bus of
        the registry's own when none is given)."""
        self._bus = bus
        self._settings = settings
        self._own_parser = parser is None
        self._parser = parser or OdParser()
        dictionaries = ProfileDictionaries(self._parser)
        self.events = events or EventBus()
        self._od_listeners: list[OdListener] = []
        self._rediscovery = Rediscovery(self, settings)
        self._monitor = NodeMonitor(settings, self.events.publish, on_boot=self._rediscovery.booted)
        # the parts: the table they share, finding nodes, swapping their dictionaries
        self._table = NodeTable(bus, settings, self._monitor)
        self._nodes = self._table.nodes
        self._scanner = Scanner(self._table, dictionaries, load_known())
        self._swap = DictionarySwap(self._table, dictionaries, self._od_replaced)
        self._bus_state: BusState | None = None
        self._unsubscribe = [
            bus.add_frame_listener(self._monitor.watch),
            bus.add_listener(self._on_bus_status),
        ]

    # ------------------------------------------------------------------ lookups

    def session(self, node: int) -> NodeSession:
        entry = self._entry(node)
        network = self._bus.network  # BusNotConnectedError
        return self._table.bound(entry, network)

    def od(self, node: int) -> ObjectDictionaryModel:
        return self._entry(node).model

    def profile(self, node: int) -> ProfileMatch:
        return self._entry(node).profile

    def profile_data(self, node: int) -> DriveData | None:
        return self._entry(node).profile.data

    def info(self, node: int) -> NodeInfo:
        found = self._info(node)
        if found.online or not found.serial:
            return found
        return next((n for n in self.all() if n.node == node), found)

    def _info(self, node: int) -> NodeInfo:
        health = self._monitor.health(node)
        return self._entry(node).info(health, self._monitor.wall_time(health.last_seen))

    def all(self) -> list[NodeInfo]:
        nodes = [self._info(node) for node in sorted(self._nodes)]
        to = moved(nodes)
        return [n.model_copy(update={"moved_to": to[n.node]}) if n.node in to else n for n in nodes]

    async def answers(self, node: int) -> bool:
        # asked on the bus every time: the list's "online" may be the drive's last answer
        # before it went to another id
        try:
            # an SDO read of 1000h (a throw-away session if unknown)
            await self._scanner.identify(node)
        except NodeStoppedError:
            return True  # its heartbeat says Stopped: there, without SDO
        except CommTimeoutError:
            return False
        except SdoAbortError:
            return True  # an abort is an answer
        return True

    async def forget(self, node: int) -> None:
        """Drop a node that is gone (silent, or answering at another id now): a scan or its
        boot-up adds it again. One that answers is refused: it would be found at once."""
        info = self.info(node)
        if info.online:
            raise StateConflictError(
                "node_online",
                f"node {node} answers on the bus: only a node that is gone can be forgotten "
                "(disconnect it or change its id first)",
            )
        entry = self._nodes.pop(node)
        entry.unbind()
        self._monitor.untrack(node)
        said = (
            say("event.forgotten_moved", node=node, moved_to=info.moved_to)
            if info.moved_to
            else say("event.forgotten", node=node)
        )
        self._event(EventKind.NODE_LOST, node, said)

    def live(self) -> list[dict[str, Any]]:
        """Node states for the WebSocket's 5 Hz "nodes" message."""
        return [live_row(node, self._monitor.health(node)) for node in sorted(self._nodes)]

    def heard(self) -> list[int]:
        """Node ids whose boot-up or heartbeat was heard on this connection, scanned or not."""
        return sorted(self._monitor.heard())

    def add_od_listener(self, fn: OdListener) -> Callable[[], None]:
        """Call `fn(node)` when a node's dictionary is replaced; returns its remover."""
        self._od_listeners.append(fn)

        def remove() -> None:
            if fn in self._od_listeners:
                self._od_listeners.remove(fn)

        return remove

    # ------------------------------------------------------------------ adding and scanning

    async def add(self, node: int) -> NodeInfo:
        """Identify the node (1000h, 1018h, 1008h, 1017h), match its profile, bind a session.

        A node already known keeps an uploaded dictionary while it is the same kind of device.
        CommTimeoutError when nothing answers at `node`."""
        _check_id(node)
        if node in self._nodes:
            await self._scanner.add(node)
        else:
            # an unknown node is probed with raw SDO: never beside a scan's sweep
            async with self._scanner.lock:
                await self._scanner.add(node)
        return self.info(node)

    async def scan(self, *, sdo_sweep: bool, timeout_ms: int) -> ScanResult:
        """Known nodes, nodes heard (boot-up/heartbeat) and, with `sdo_sweep`, every id that
        answers a 1000h read, identified in parallel. Known nodes that no longer answer stay
        listed with online=false."""
        took = await self._scanner.scan(sdo_sweep=sdo_sweep, timeout_ms=timeout_ms)
        return ScanResult(nodes=self.all(), duration_ms=took)

    # ------------------------------------------------------------------ NMT and heartbeat

    async def nmt(self, node: int, command: NmtCommandName) -> NodeInfo:
        remote = self.session(node).remote
        sent_at = self._monitor.now()  # before sending: a boot-up answering a reset is newer
        await self._table.send(send_to_node, remote, command)
        self._monitor.commanded(node, STATE_AFTER[command], at=sent_at)
        self._event(
            EventKind.NMT,
            node,
            say("event.nmt_sent", nmt_command=command.value, node=node),
            {"tool": True, "command": command.value, "broadcast": False},
        )
        return self.info(node)

    async def nmt_broadcast(self, command: NmtCommandName) -> None:
        network = self._bus.network
        sent_at = self._monitor.now()
        await self._table.send(send_broadcast, network, command)
        for node in self._nodes:
            self._monitor.commanded(node, STATE_AFTER[command], at=sent_at)
        self._event(
            EventKind.NMT,
            None,
            say("event.nmt_sent_all", nmt_command=command.value),
            {"tool": True, "command": command.value, "broadcast": True},
        )

    async def heartbeat(self, node: int) -> int:
        """Read 1017h Producer heartbeat time (ms)."""
        raw = await self.session(node).upload(PRODUCER_HEARTBEAT, 0)
        ms = int.from_bytes(raw[:2], "little")
        self._table.heartbeat_known(node, ms)
        return ms

    async def set_heartbeat(self, node: int, ms: int, *, confirm: bool = False) -> int:
        """Write 1017h and return the value read back."""
        if not 0 <= ms <= MAX_HEARTBEAT_MS:
            raise InvalidValueError(f"heartbeat time {ms} ms is outside 0–{MAX_HEARTBEAT_MS} ms")
        check_heartbeat_time(node, ms, confirm=confirm)
        await self.session(node).download(PRODUCER_HEARTBEAT, 0, ms.to_bytes(2, "little"))
        return await self.heartbeat(node)

    async def wait_boot(self, node: int, timeout: float) -> bool:
        return await self._monitor.wait_boot(node, timeout)

    # ------------------------------------------------------------------ dictionaries, node ids

    async def set_od(self, node: int, model: ObjectDictionaryModel, source: OdSource) -> NodeInfo:
        """Use `model` as the node's dictionary. The old one is released (nothing keeps it)."""
        await self._swap.set_od(node, model, source)
        return self.info(node)

    async def reset_od(self, node: int) -> NodeInfo:
        """Back to the profile's dictionary."""
        await self._swap.reset_od(node)
        return self.info(node)

    async def move(self, old: int, new: int) -> NodeInfo:
        """The node formerly at `old` answers at `new` now (its node id was changed)."""
        _check_id(new)
        await self._swap.move(old, new)
        return self.info(new)

    def _od_replaced(self, node: int) -> None:
        for fn in list(self._od_listeners):
            fn(node)

    # ------------------------------------------------------------------ lifecycle

    async def close(self) -> None:
        """Stop the monitor and close every session (app shutdown)."""
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        self._unsubscribe = []
        await self._monitor.stop()
        self._clear()
        if self._own_parser:
            self._parser.close()

    def _clear(self) -> None:
        self._rediscovery.cancel()
        for entry in self._nodes.values():
            entry.unbind()
        self._nodes.clear()
        self._monitor.forget()

    def _on_bus_status(self, status: BusStatus) -> None:
        previous, self._bus_state = self._bus_state, status.state
        if status.state is BusState.DISCONNECTED:
            self._clear()
            self._monitor.stop_soon()
        elif status.state is BusState.CONNECTED:
            self._monitor.start()
            network = self._bus.network
            for entry in self._nodes.values():
                if entry.network is not network:
                    self._table.bound(entry, network)  # a new connection: new sessions
            if previous is not BusState.CONNECTED:
                self._rediscovery.connected()  # no manual scan after any (re)connect
        if status.state is previous or status.state is BusState.CONNECTING:
            return
        if status.state is BusState.CONNECTED:
            where = " ".join(str(part) for part in (status.interface, status.channel) if part)
            self._event(EventKind.BUS, None, say("event.bus_connected", where=where))
        elif status.state is BusState.ERROR:
            self._event(EventKind.BUS, None, say("event.bus_error", error=str(status.error)))
        elif previous is not None:
            self._event(EventKind.BUS, None, say("event.bus_disconnected"))

    async def settled(self) -> None:
        """Wait for the scan that follows a connect (if one is running)."""
        await self._rediscovery.settled()

    # ------------------------------------------------------------------ rediscovery's needs

    def known(self, node: int) -> bool:
        return node in self._nodes

    async def rescan(self) -> None:
        await self.scan(sdo_sweep=True, timeout_ms=round(self._settings.scan_timeout * 1000))

    async def add_if_unknown(self, node: int) -> None:
        async with self._scanner.lock:  # never beside a scan's sweep (see `add`)
            if node not in self._nodes:
                await self._scanner.add(node)

    # ------------------------------------------------------------------ helpers

    def _entry(self, node: int) -> NodeEntry:
        return self._table.entry(node)

    def _event(
        self, kind: EventKind, node: int | None, message: Said, data: dict[str, Any] | None = None
    ) -> None:
        """Published on the loop: every subscriber sees it at once (events/bus.py)."""
        self.events.publish(event(kind, node, message, data))
