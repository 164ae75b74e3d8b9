"""Scanner: finding and identifying nodes. A scan lists the known nodes, those heard (boot-up,
heartbeat) and, with an SDO sweep, every id that answers a 1000h read; each is identified
(1000h, 1018h, 1008h, 1017h, then 1009h/100Ah), matched to a profile and bound to a session."""

from __future__ import annotations

import asyncio
import contextlib
import functools
import time

import canopen
from canopen.objectdictionary import ObjectDictionary

from servodesk.errors import CommTimeoutError, NodeStoppedError, ServodeskError
from servodesk.network.scan import NODE_IDS, SweepListener, send_sweep
from servodesk.nodes.entry import NodeEntry
from servodesk.nodes.identity import DEVICE_TYPE, Identity, read_identity, read_versions
from servodesk.nodes.profile_dictionaries import ProfileDictionaries
from servodesk.nodes.table import NodeTable
from servodesk.profiles import match
from servodesk_data import DriveData


class Scanner:
    def __init__(
        self,
        table: NodeTable,
        dictionaries: ProfileDictionaries,
        known_profiles: tuple[DriveData, ...],
    ) -> None:
        self._table = table
        self._dictionaries = dictionaries
        self._known_profiles = known_profiles
        # an unknown node is probed with raw SDO: never while a scan's sweep asks every id
        # (two requests to one node would steal each other's answers)
        self.lock = asyncio.Lock()
        self._node_locks: dict[int, asyncio.Lock] = {}

    async def add(self, node: int) -> None:
        """Identify the node, match its profile, bind a session (the caller holds `lock`
        where the node is not known yet). CommTimeoutError when nothing answers at `node`."""
        self._table.monitor.attach_loop()
        async with self._node_locks.setdefault(node, asyncio.Lock()):
            identity = await self.identify(node)
            await self._register(node, identity)

    async def scan(self, *, sdo_sweep: bool, timeout_ms: int) -> int:
        """Scan; the time it took (ms)."""
        started = time.perf_counter()
        table = self._table
        async with self.lock:
            table.monitor.attach_loop()
            network = table.bus.network
            known = set(table.nodes)
            heard = table.monitor.heard() - known
            found: set[int] = set()
            if sdo_sweep:
                # Known nodes are probed through their own sessions instead: a raw request in
                # the middle of one of their transfers would break it.
                unknown = [node for node in NODE_IDS if node not in known]
                found = await self._sweep(network, unknown, timeout_ms / 1000)
            targets = sorted(known | heard | found)
            await asyncio.gather(*(self._scan_one(node, node in heard) for node in targets))
        return round((time.perf_counter() - started) * 1000)

    async def _scan_one(self, node: int, heard_only: bool) -> None:
        table = self._table
        try:
            await self.add(node)  # the scan holds the scan lock
        except NodeStoppedError:
            # Stopped nodes have no SDO: keep what is known, or list the node unidentified.
            if node not in table.nodes:
                async with self._node_locks.setdefault(node, asyncio.Lock()):
                    await self._register(node, Identity())
        except CommTimeoutError:
            if node in table.nodes:
                table.monitor.absent(node)  # vanished since the last scan: listed offline
            elif heard_only:
                # It sends heartbeats but does not answer SDO (e.g. Stopped): list it anyway.
                async with self._node_locks.setdefault(node, asyncio.Lock()):
                    await self._register(node, Identity())

    async def _sweep(self, network: canopen.Network, ids: list[int], timeout: float) -> set[int]:
        listener = SweepListener(ids)
        remove = self._table.bus.add_frame_listener(listener)
        try:
            await self._table.send(send_sweep, network, ids)
            await asyncio.sleep(timeout)
        finally:
            remove()
        return set(listener.found)

    async def identify(self, node: int) -> Identity:
        """An SDO read of 1000h and the rest of the identity (a throw-away session with an
        empty dictionary where the node is not known yet: raw SDO is enough)."""
        table = self._table
        what = f"identify node {node} (read {DEVICE_TYPE:04X}h)"
        known = table.nodes.get(node)
        if known is not None:
            session = table.bound(known, table.bus.network)
            return await session.run(read_identity, what=what, index=DEVICE_TYPE)
        network = table.bus.network
        remote = canopen.RemoteNode(node, ObjectDictionary())  # type: ignore[no-untyped-call]
        network.add_node(remote)
        probe = table.new_session(remote)
        try:
            return await probe.run(read_identity, what=what, index=DEVICE_TYPE)
        finally:
            probe.close()
            if network.nodes.get(node) is remote:
                del network[node]

    async def _register(self, node: int, identity: Identity) -> None:
        table = self._table
        profile = match(
            identity.device_type,
            identity.vendor_id,
            identity.product_code,
            known=self._known_profiles,
        )
        existing = table.nodes.get(node)
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
            table.nodes[node] = entry
            if existing is not None:
                existing.unbind()
        table.monitor.track(node, identity.heartbeat_ms)
        entry = table.nodes[node]
        table.bind_if_connected(entry)
        # only of a node that just answered its identification (not one listed from its
        # heartbeat alone, which may not answer SDO at all)
        if entry.session is not None and identity.vendor_id is not None:
            with contextlib.suppress(ServodeskError):  # versions are shown, never required
                entry.identity = await entry.session.run(
                    functools.partial(read_versions, identity=entry.identity),
                    what=f"read the versions of node {node} (1009h, 100Ah)",
                )
