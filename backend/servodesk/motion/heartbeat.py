"""The drive stops by itself if the tool dies (DESIGN: Motion safety).

While the tool controls a drive that has a heartbeat consumer (1016h), the tool produces its own
heartbeat (700h + tool node id, state Operational 05h) and sets one of the drive's 1016h entries
to watch it with `heartbeat_consumer_ms`: if the tool goes silent, the drive raises its
heartbeat fault and its fault reaction stops the axis. Releasing control writes the entry back,
so a drive left alone does not fault when the tool later exits.

The heartbeat is produced by a task on the event loop, not by a timer thread, on purpose: the
jog watchdog lives on the loop too, so a loop that stalls can no longer stop a jog, and the
drive should then see the tool as gone.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Callable
from dataclasses import dataclass

import can
import canopen

from servodesk.errors import ServodeskError
from servodesk.motion.safety_models import HeartbeatProtection
from servodesk.nodes.access import NodeAccess
from servodesk.settings import Settings

log = logging.getLogger(__name__)

CONSUMER = 0x1016  # Consumer heartbeat time: bits 16–23 node id, 0–15 time in ms
HEARTBEAT_COB = 0x700
OPERATIONAL = 0x05


@dataclass
class _Guarded:
    subindex: int
    previous: int  # the entry's value before, written back on release


class HeartbeatGuard:
    def __init__(
        self,
        access: NodeAccess,
        settings: Settings,
        network: Callable[[], canopen.Network],
        known_nodes: Callable[[], list[int]],
    ) -> None:
        self._access = access
        self._tool = settings.tool_node_id
        self._consumer_ms = settings.heartbeat_consumer_ms
        self._period = settings.tool_heartbeat_ms / 1000
        self._network = network
        self._known = known_nodes
        self._guarded: dict[int, _Guarded] = {}
        self._why_not: dict[int, str] = {}
        self._producer: asyncio.Task[None] | None = None

    def status(self, node: int) -> HeartbeatProtection:
        active = node in self._guarded
        if active:
            message = (
                f"the drive stops by itself if ServoDesk's heartbeat (node {self._tool}) is "
                f"silent for {self._consumer_ms} ms"
            )
        else:
            message = self._why_not.get(node, "not controlled by ServoDesk")
        return HeartbeatProtection(
            active=active, tool_node_id=self._tool, consumer_ms=self._consumer_ms, message=message
        )

    def guarded(self) -> list[int]:
        return list(self._guarded)

    async def protect(self, node: int) -> HeartbeatProtection:
        """Make `node` watch the tool's heartbeat, where it can; says why not otherwise."""
        if node in self._guarded:
            return self.status(node)
        reason = self._refusal(node)
        if reason is None:
            self._start_producer()
            try:
                reason = await self._configure(node)
            except ServodeskError as error:
                reason = f"could not set the heartbeat consumer (1016h): {error}"
        if reason is not None:
            self._why_not[node] = reason
            self._stop_producer_if_idle()
        return self.status(node)

    async def unprotect(self, node: int) -> None:
        guarded = self._guarded.pop(node, None)
        self._why_not.pop(node, None)
        if guarded is not None:
            try:
                data = guarded.previous.to_bytes(4, "little")
                await self._access.session(node).download(CONSUMER, guarded.subindex, data)
            except ServodeskError as error:
                log.warning(
                    "node %d: could not restore 1016h:%02X: %s", node, guarded.subindex, error
                )
        self._stop_producer_if_idle()

    def forget(self, node: int) -> None:
        """The drive restarted: its 1016h entries are back to their stored values."""
        self._guarded.pop(node, None)

    async def close(self) -> None:
        for node in list(self._guarded):
            await self.unprotect(node)
        if self._producer is not None:
            self._producer.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._producer
            self._producer = None

    def _refusal(self, node: int) -> str | None:
        if self._tool in self._known():
            return (
                f"node id {self._tool} (ServoDesk's heartbeat) is used on the bus: "
                "change tool_node_id"
            )
        od = self._access.od(node)
        if od.get(CONSUMER, 0) is None or od.get(CONSUMER, 1) is None:
            return "the drive has no heartbeat consumer (1016h): stop it from ServoDesk only"
        return None

    async def _configure(self, node: int) -> str | None:
        session = self._access.session(node)
        count = int.from_bytes(await session.upload(CONSUMER, 0), "little")
        chosen: tuple[int, int] | None = None
        for sub in range(1, count + 1):
            value = int.from_bytes(await session.upload(CONSUMER, sub), "little")
            watched, ms = (value >> 16) & 0xFF, value & 0xFFFF
            if watched == self._tool:
                chosen = (sub, value)  # ours already (left by a previous run): reuse it
                break
            if chosen is None and (watched == 0 or ms == 0):
                chosen = (sub, value)
        if chosen is None:
            return "every heartbeat consumer entry (1016h) of the drive is in use"
        sub, previous = chosen
        if (previous >> 16) & 0xFF == self._tool:
            previous = 0  # a left-over of ours: released means unused
        value = (self._tool << 16) | self._consumer_ms
        await session.download(CONSUMER, sub, value.to_bytes(4, "little"))
        self._guarded[node] = _Guarded(subindex=sub, previous=previous)
        self._why_not.pop(node, None)
        return None

    def _start_producer(self) -> None:
        if self._producer is None or self._producer.done():
            self._producer = asyncio.get_running_loop().create_task(
                self._produce(), name="tool-heartbeat"
            )

    def _stop_producer_if_idle(self) -> None:
        if not self._guarded and self._producer is not None:
            self._producer.cancel()
            self._producer = None

    async def _produce(self) -> None:
        loop = asyncio.get_running_loop()
        due = loop.time()
        cob = HEARTBEAT_COB + self._tool
        while True:
            with contextlib.suppress(ServodeskError, can.CanError, OSError, RuntimeError):
                # no bus right now: the drives see silence, which is the truth
                self._network().send_message(cob, bytes([OPERATIONAL]))
            due += self._period
            now = loop.time()
            if due < now:  # after a stall, restart the grid instead of bursting
                due = now + self._period
            await asyncio.sleep(due - now)
