"""NodeTable: the known nodes and how to reach them on the current connection (the entries by
id, the sessions bound to the bus's canopen Network, the monitor that tracks each node). What
the registry and its parts (scanning, dictionary swaps) share; it decides nothing itself."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from dataclasses import replace
from typing import ParamSpec

import can
import canopen

from servodesk.bus.connection import BusManager
from servodesk.errors import BusNotConnectedError, NodeNotFoundError
from servodesk.network.monitor import NodeMonitor
from servodesk.nodes.entry import NodeEntry
from servodesk.nodes.tracked import TrackedSession
from servodesk.settings import Settings

P = ParamSpec("P")


class NodeTable:
    def __init__(self, bus: BusManager, settings: Settings, monitor: NodeMonitor) -> None:
        self.bus = bus
        self.settings = settings
        self.monitor = monitor
        self.nodes: dict[int, NodeEntry] = {}

    def entry(self, node: int) -> NodeEntry:
        entry = self.nodes.get(node)
        if entry is None:
            raise NodeNotFoundError(node)
        return entry

    def new_session(self, remote: canopen.RemoteNode) -> TrackedSession:
        return TrackedSession(
            remote,
            sdo_timeout=self.settings.sdo_timeout,
            on_outcome=self.monitor.sdo_outcome,
            on_heartbeat_written=self.heartbeat_known,
            is_stopped=self.monitor.is_stopped,
        )

    def bound(self, entry: NodeEntry, network: canopen.Network) -> TrackedSession:
        return entry.bound(network, self.new_session)

    def bind_if_connected(self, entry: NodeEntry) -> None:
        try:
            network = self.bus.network
        except BusNotConnectedError:
            return  # bound on first use after the bus is back
        self.bound(entry, network)

    def heartbeat_known(self, node: int, ms: int) -> None:
        entry = self.nodes.get(node)
        if entry is not None:
            entry.identity = replace(entry.identity, heartbeat_ms=ms)
        self.monitor.heartbeat_known(node, ms)

    async def send(self, fn: Callable[P, None], *args: P.args, **kwargs: P.kwargs) -> None:
        """Run a blocking send off the loop; a failing adapter becomes BusNotConnectedError."""
        try:
            await asyncio.to_thread(fn, *args, **kwargs)
        except can.CanError as error:
            raise BusNotConnectedError(f"the CAN adapter refused to send: {error}") from error
