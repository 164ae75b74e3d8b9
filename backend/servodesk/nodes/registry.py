"""NodeRegistry: which nodes are on the bus, what they are, and how to reach them.

Each known node has an identity (1000h, 1018h, 1008h), a profile (profiles/match.py), an object
dictionary model (the profile's EDS or the user's upload, kept in memory only) and a session
bound to the current connection's canopen Network. The registry empties itself when the bus is
disconnected; after a reconnect (a new Network) it binds every node's session again.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any, ParamSpec

import can
import canopen
from canopen.objectdictionary import ObjectDictionary

from servodesk.bus.connection import BusManager
from servodesk.errors import (
    BusNotConnectedError,
    CommTimeoutError,
    InvalidValueError,
    NodeNotFoundError,
    NodeStoppedError,
    SdoAbortError,
    ServodeskError,
    StateConflictError,
)
from servodesk.events.bus import EventBus, EventKind, event
from servodesk.heap import keep_long_lived
from servodesk.models import (
    BusState,
    BusStatus,
    NmtCommandName,
    NodeInfo,
    ScanResult,
)
from servodesk.network.monitor import NodeMonitor
from servodesk.network.nmt import STATE_AFTER, send_broadcast, send_to_node
from servodesk.network.scan import NODE_IDS, SweepListener, send_sweep
from servodesk.nodes.entry import NodeEntry, OdSource, live_row
from servodesk.nodes.heartbeat_floor import HEARTBEAT_FLOOR_MS as HEARTBEAT_FLOOR_MS
from servodesk.nodes.heartbeat_floor import check_heartbeat_time
from servodesk.nodes.identity import (
    DEVICE_TYPE,
    PRODUCER_HEARTBEAT,
    Identity,
    read_identity,
    read_versions,
)
from servodesk.nodes.moved import moved
from servodesk.nodes.profile_models import ProfileModels
from servodesk.nodes.rediscovery import Rediscovery
from servodesk.nodes.session import NodeSession
from servodesk.nodes.tracked import TrackedSession
from servodesk.od import ObjectDictionaryModel
from servodesk.od.parser import OdParser, release_memory
from servodesk.od.to_canopen import dispose, to_canopen
from servodesk.profiles import ProfileMatch, load_known, match
from servodesk.settings import Settings
from servodesk_data import DriveData

log = logging.getLogger(__name__)

OdListener = Callable[[int], None]  # (node) whose dictionary was replaced
P = ParamSpec("P")
MAX_HEARTBEAT_MS = 0xFFFF  # 1017h is UNSIGNED16


def _free(od: ObjectDictionary) -> None:
    dispose(od, pause=True)
    release_memory()


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
        self._nodes: dict[int, NodeEntry] = {}
        self._known_profiles = load_known()
        self._own_parser = parser is None
        self._parser = parser or OdParser()
        self._dictionaries = ProfileModels(self._parser)
        self.events = events or EventBus()
        self._od_listeners: list[OdListener] = []
        self._rediscovery = Rediscovery(self, settings)
        self._monitor = NodeMonitor(settings, self.events.publish, on_boot=self._rediscovery.booted)
        self._scan_lock = asyncio.Lock()
        self._node_locks: dict[int, asyncio.Lock] = {}
        self._bus_state: BusState | None = None
        self._unsubscribe = [
            bus.add_frame_listener(self._monitor.watch),
            bus.add_listener(self._on_bus_status),
        ]

    # ------------------------------------------------------------------ lookups

    def session(self, node: int) -> NodeSession:
        entry = self._entry(node)
        network = self._bus.network  # BusNotConnectedError
        return self._bound(entry, network)

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
            await self._identify(node)  # an SDO read of 1000h (a throw-away session if unknown)
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
        moved_note = f" (it answers as node {info.moved_to} now)" if info.moved_to else ""
        self._event(EventKind.NODE_LOST, node, f"node {node} forgotten{moved_note}")

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
            return await self._add(node)
        # An unknown node is probed with raw SDO: never while a scan's sweep asks every id
        # (two requests to one node would steal each other's answers).
        async with self._scan_lock:
            return await self._add(node)

    async def _add(self, node: int) -> NodeInfo:
        self._monitor.attach_loop()
        async with self._node_locks.setdefault(node, asyncio.Lock()):
            identity = await self._identify(node)
            await self._register(node, identity)
        return self.info(node)

    async def scan(self, *, sdo_sweep: bool, timeout_ms: int) -> ScanResult:
        """Known nodes, nodes heard (boot-up/heartbeat) and, with `sdo_sweep`, every id that
        answers a 1000h read, identified in parallel. Known nodes that no longer answer stay
        listed with online=false."""
        started = time.perf_counter()
        async with self._scan_lock:
            self._monitor.attach_loop()
            network = self._bus.network
            known = set(self._nodes)
            heard = self._monitor.heard() - known
            found: set[int] = set()
            if sdo_sweep:
                # Known nodes are probed through their own sessions instead: a raw request in
                # the middle of one of their transfers would break it.
                unknown = [node for node in NODE_IDS if node not in known]
                found = await self._sweep(network, unknown, timeout_ms / 1000)
            targets = sorted(known | heard | found)
            await asyncio.gather(*(self._scan_one(node, node in heard) for node in targets))
        duration_ms = round((time.perf_counter() - started) * 1000)
        return ScanResult(nodes=self.all(), duration_ms=duration_ms)

    async def _scan_one(self, node: int, heard_only: bool) -> None:
        try:
            await self._add(node)  # the scan holds the scan lock
        except NodeStoppedError:
            # Stopped nodes have no SDO: keep what is known, or list the node unidentified.
            if node not in self._nodes:
                async with self._node_locks.setdefault(node, asyncio.Lock()):
                    await self._register(node, Identity())
        except CommTimeoutError:
            if node in self._nodes:
                self._monitor.absent(node)  # vanished since the last scan: listed offline
            elif heard_only:
                # It sends heartbeats but does not answer SDO (e.g. Stopped): list it anyway.
                async with self._node_locks.setdefault(node, asyncio.Lock()):
                    await self._register(node, Identity())

    async def _sweep(self, network: canopen.Network, ids: list[int], timeout: float) -> set[int]:
        listener = SweepListener(ids)
        remove = self._bus.add_frame_listener(listener)
        try:
            await self._send(send_sweep, network, ids)
            await asyncio.sleep(timeout)
        finally:
            remove()
        return set(listener.found)

    async def _identify(self, node: int) -> Identity:
        what = f"identify node {node} (read {DEVICE_TYPE:04X}h)"
        if node in self._nodes:
            return await self.session(node).run(read_identity, what=what, index=DEVICE_TYPE)
        # Not known yet: a throw-away session with an empty dictionary (raw SDO is enough).
        network = self._bus.network
        remote = canopen.RemoteNode(node, ObjectDictionary())  # type: ignore[no-untyped-call]
        network.add_node(remote)
        probe = self._new_session(remote)
        try:
            return await probe.run(read_identity, what=what, index=DEVICE_TYPE)
        finally:
            probe.close()
            if network.nodes.get(node) is remote:
                del network[node]

    async def _register(self, node: int, identity: Identity) -> None:
        profile = match(
            identity.device_type,
            identity.vendor_id,
            identity.product_code,
            known=self._known_profiles,
        )
        existing = self._nodes.get(node)
        keeps_upload = (
            existing is not None
            and existing.od_source == "upload"
            and existing.identity.same_device(identity)
        )
        if existing is not None and (keeps_upload or existing.profile.name == profile.name):
            existing.identity = identity
            existing.profile = profile
        else:
            model = await self._dictionaries.model(profile, node)
            entry = NodeEntry(
                node=node,
                identity=identity,
                profile=profile,
                model=model,
                od_source="profile",
                od_filename=self._dictionaries.filename(profile),
                canopen_od=await self._dictionaries.canopen(model, node),
            )
            self._nodes[node] = entry
            if existing is not None:
                existing.unbind()
        self._monitor.track(node, identity.heartbeat_ms)
        entry = self._nodes[node]
        self._bind_if_connected(entry)
        # only of a node that just answered its identification (not one listed from its
        # heartbeat alone, which may not answer SDO at all)
        if entry.session is not None and identity.vendor_id is not None:
            with contextlib.suppress(ServodeskError):  # versions are shown, never required
                entry.identity = await entry.session.run(
                    functools.partial(read_versions, identity=entry.identity),
                    what=f"read the versions of node {node} (1009h, 100Ah)",
                )

    # ------------------------------------------------------------------ NMT and heartbeat

    async def nmt(self, node: int, command: NmtCommandName) -> NodeInfo:
        remote = self.session(node).remote
        sent_at = self._monitor.now()  # before sending: a boot-up answering a reset is newer
        await self._send(send_to_node, remote, command)
        self._monitor.commanded(node, STATE_AFTER[command], at=sent_at)
        self._event(
            EventKind.NMT,
            node,
            f"NMT {command.value} sent to node {node}",
            {"tool": True, "command": command.value, "broadcast": False},
        )
        return self.info(node)

    async def nmt_broadcast(self, command: NmtCommandName) -> None:
        network = self._bus.network
        sent_at = self._monitor.now()
        await self._send(send_broadcast, network, command)
        for node in self._nodes:
            self._monitor.commanded(node, STATE_AFTER[command], at=sent_at)
        self._event(
            EventKind.NMT,
            None,
            f"NMT {command.value} sent to all nodes",
            {"tool": True, "command": command.value, "broadcast": True},
        )

    async def heartbeat(self, node: int) -> int:
        """Read 1017h Producer heartbeat time (ms)."""
        raw = await self.session(node).upload(PRODUCER_HEARTBEAT, 0)
        ms = int.from_bytes(raw[:2], "little")
        self._heartbeat_known(node, ms)
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
        if source == "profile":
            canopen_od = await self._dictionaries.canopen(model, node)
        else:
            canopen_od = await asyncio.to_thread(to_canopen, model, node)  # large files: seconds
        entry = self._entry(node)
        old_od = entry.canopen_od if entry.od_source == "upload" else None  # not shared
        entry.model = model
        entry.od_source = source
        entry.od_filename = (
            Path(model.source).name
            if source == "upload"
            else self._dictionaries.filename(entry.profile)
        )
        entry.canopen_od = canopen_od
        session, network = entry.session, entry.network

        def retire() -> None:
            # on a thread of its own, not the node's: emptying a large dictionary takes tens of
            # milliseconds that a stop queued for the node must not wait for
            if old_od is not None:
                threading.Thread(target=_free, args=(old_od,), name="od-retire").start()

        if source == "upload":
            keep_long_lived()  # a large dictionary is never walked by a full collection
        if session is not None and network is not None:
            # Requests already queued for the node finish with the old dictionary; the new one
            # takes over after them on the node's own thread (no request is cut off).
            session.replace_dictionary(entry.canopen_od, then=retire)
        else:
            self._bind_if_connected(entry)
            await asyncio.to_thread(retire)
        for fn in list(self._od_listeners):
            fn(node)
        return self.info(node)

    async def reset_od(self, node: int) -> NodeInfo:
        """Back to the profile's dictionary."""
        entry = self._entry(node)
        model = await self._dictionaries.model(entry.profile, node)
        return await self.set_od(node, model, "profile")

    async def move(self, old: int, new: int) -> NodeInfo:
        """The node formerly at `old` answers at `new` now (its node id was changed).

        An uploaded dictionary moves with it (to_canopen resolves its node-relative entries
        for `new`); a node registered at `new` before is replaced."""
        _check_id(new)
        entry = self._entry(old)
        if new == old:
            return self.info(old)
        if entry.od_source == "profile":
            model = await self._dictionaries.model(entry.profile, new)
            canopen_od = await self._dictionaries.canopen(model, new)
        else:
            model = entry.model
            canopen_od = await asyncio.to_thread(to_canopen, model, new)  # large files: seconds
        for stale in (self._nodes.pop(new, None), self._nodes.pop(old)):
            if stale is not None:
                stale.unbind()
        self._monitor.untrack(new)
        self._monitor.untrack(old)
        moved = replace(
            entry,
            node=new,
            model=model,
            canopen_od=canopen_od,
            session=None,
            network=None,
        )
        self._nodes[new] = moved
        self._monitor.track(new, entry.identity.heartbeat_ms)
        self._bind_if_connected(moved)
        return self.info(new)

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
                    self._bound(entry, network)  # a new connection: new sessions
            if previous is not BusState.CONNECTED:
                self._rediscovery.connected()  # no manual scan after any (re)connect
        if status.state is previous or status.state is BusState.CONNECTING:
            return
        if status.state is BusState.CONNECTED:
            where = " ".join(str(part) for part in (status.interface, status.channel) if part)
            self._event(EventKind.BUS, None, f"bus connected ({where})")
        elif status.state is BusState.ERROR:
            self._event(EventKind.BUS, None, f"bus error: {status.error}")
        elif previous is not None:
            self._event(EventKind.BUS, None, "bus disconnected")

    async def settled(self) -> None:
        """Wait for the scan that follows a connect (if one is running)."""
        await self._rediscovery.settled()

    # ------------------------------------------------------------------ rediscovery's needs

    def known(self, node: int) -> bool:
        return node in self._nodes

    async def rescan(self) -> None:
        await self.scan(sdo_sweep=True, timeout_ms=round(self._settings.scan_timeout * 1000))

    async def add_if_unknown(self, node: int) -> None:
        async with self._scan_lock:  # never beside a scan's sweep (see `add`)
            if node not in self._nodes:
                await self._add(node)

    # ------------------------------------------------------------------ helpers

    def _entry(self, node: int) -> NodeEntry:
        entry = self._nodes.get(node)
        if entry is None:
            raise NodeNotFoundError(node)
        return entry

    def _new_session(self, remote: canopen.RemoteNode) -> TrackedSession:
        return TrackedSession(
            remote,
            sdo_timeout=self._settings.sdo_timeout,
            on_outcome=self._monitor.sdo_outcome,
            on_heartbeat_written=self._heartbeat_known,
            is_stopped=self._monitor.is_stopped,
        )

    def _bound(self, entry: NodeEntry, network: canopen.Network) -> TrackedSession:
        return entry.bound(network, self._new_session)

    def _bind_if_connected(self, entry: NodeEntry) -> None:
        try:
            network = self._bus.network
        except BusNotConnectedError:
            return  # bound on first use after the bus is back
        self._bound(entry, network)

    def _heartbeat_known(self, node: int, ms: int) -> None:
        entry = self._nodes.get(node)
        if entry is not None:
            entry.identity = replace(entry.identity, heartbeat_ms=ms)
        self._monitor.heartbeat_known(node, ms)

    async def _send(self, fn: Callable[P, None], *args: P.args, **kwargs: P.kwargs) -> None:
        """Run a blocking send off the loop; a failing adapter becomes BusNotConnectedError."""
        try:
            await asyncio.to_thread(fn, *args, **kwargs)
        except can.CanError as error:
            raise BusNotConnectedError(f"the CAN adapter refused to send: {error}") from error

    def _event(
        self, kind: EventKind, node: int | None, message: str, data: dict[str, Any] | None = None
    ) -> None:
        """Published on the loop: every subscriber sees it at once (events/bus.py)."""
        self.events.publish(event(kind, node, message, data))
