"""Nodes come back by themselves: a scan after every (re)connect, and a node that boots later
is identified when its boot-up arrives (a known one has its heartbeat period read again, as a
reset may have restored the stored 1017h). Background work of the registry, never awaited by a
request; failures are logged, the next boot-up or scan tries again.

A node that booted before the tool connected and sends no heartbeat would sit in NMT "unknown"
(nothing told its state): after the scan, each such node is asked with a node-guarding RTR
(700h+id); its answer (state | toggle) is recorded by the monitor like a heartbeat. Answering
the scan's SDO already showed it is Pre-operational or Operational; the guarding answer says
which."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Coroutine
from typing import Any, Protocol

import can

from servodesk.errors import ServodeskError
from servodesk.models.nodes import NmtStateName, NodeInfo
from servodesk.nodes.session import NodeSession
from servodesk.settings import Settings
from servodesk_protocol import cob_id

log = logging.getLogger(__name__)


class Rediscoverable(Protocol):
    def known(self, node: int) -> bool: ...

    async def rescan(self) -> None:
        """An SDO sweep plus the nodes heard, as `POST /api/scan` does."""
        ...

    async def add_if_unknown(self, node: int) -> None: ...

    async def heartbeat(self, node: int) -> int: ...

    def all(self) -> list[NodeInfo]: ...

    def session(self, node: int) -> NodeSession: ...


class Rediscovery:
    def __init__(self, registry: Rediscoverable, settings: Settings) -> None:
        self._registry = registry
        self._enabled = settings.auto_scan
        self._tasks: set[asyncio.Task[None]] = set()
        self._scan: asyncio.Task[None] | None = None

    def connected(self) -> None:
        """The bus is (back) up: find every node on it."""
        if self._enabled:
            self._scan = self._spawn(self._quietly("scan after connecting", self._scan_and_ask()))

    def booted(self, node: int) -> None:
        work: Coroutine[Any, Any, object]
        if self._registry.known(node):
            work = self._registry.heartbeat(node)
            self._spawn(self._quietly(f"reading 1017h of node {node} after its boot-up", work))
        elif self._enabled:
            work = self._registry.add_if_unknown(node)
            self._spawn(self._quietly(f"identifying node {node} after its boot-up", work))

    async def _scan_and_ask(self) -> None:
        await self._registry.rescan()
        await self.ask_unknown()

    async def ask_unknown(self) -> None:
        """A node-guarding RTR to every online node whose NMT state is unknown."""
        for info in self._registry.all():
            if not info.online or info.nmt_state is not NmtStateName.UNKNOWN:
                continue
            network = self._registry.session(info.node).remote.network
            guard_id = cob_id.HEARTBEAT + info.node
            try:
                await asyncio.to_thread(network.send_message, guard_id, b"", True)
            except can.CanError as error:
                log.info("node-guarding request to node %d failed: %s", info.node, error)

    async def settled(self) -> None:
        """Wait for the scan that follows a connect (if one is running)."""
        task = self._scan
        if task is not None and not task.done():
            await asyncio.wait({task})

    def cancel(self) -> None:
        for task in self._tasks:
            task.cancel()

    def _spawn(self, work: Coroutine[Any, Any, None]) -> asyncio.Task[None]:
        task = asyncio.get_running_loop().create_task(work)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
        return task

    @staticmethod
    async def _quietly(what: str, work: Coroutine[Any, Any, object]) -> None:
        try:
            await work
        except ServodeskError as error:
            log.info("%s failed: %s", what, error)
