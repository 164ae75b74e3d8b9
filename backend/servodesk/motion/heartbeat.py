"""The drive stops by itself if the tool dies (DESIGN: Motion safety).

While the tool controls a drive that has a heartbeat consumer (1016h), the tool produces its own
heartbeat (700h + tool node id, state Operational 05h) and sets one of the drive's 1016h entries
to watch it with `heartbeat_consumer_ms`: if the tool goes silent, the drive raises its
heartbeat fault and its fault reaction stops the axis. Releasing control writes the entry back,
so a drive left alone does not fault when the tool later exits.

The frame is sent by python-can's cyclic send task (a thread of its own), so a
busy event loop does not make held drives fault. It is gated on the loop's liveness all the
same: the jog watchdog lives on the loop, so a loop that has not run for
`tool_heartbeat_liveness_ms` can no longer stop a jog, and the drives must then see the tool as
gone. The task's thread checks the loop's last tick before every frame and stops itself when it
is too old; the loop starts it again when it runs again (docs/architecture.md, "The tool's
heartbeat").
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import can
import canopen

from servodesk.errors import ServodeskError
from servodesk.models.safety import HeartbeatProtection
from servodesk.nodes.access import NodeAccess
from servodesk.settings import Settings
from servodesk_protocol.cob_id import HEARTBEAT
from servodesk_protocol.nmt import (
    CONSUMER_HEARTBEAT_TIME,
    NmtState,
    consumer_entry,
    make_heartbeat,
    parse_consumer_entry,
)

log = logging.getLogger(__name__)

TICK = 0.05  # s: how often the loop says it is alive


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
        self._network = network
        self._known = known_nodes
        self._guarded: dict[int, _Guarded] = {}
        self._why_not: dict[int, str] = {}
        self._producer = GatedHeartbeat(
            HEARTBEAT + self._tool,
            settings.tool_heartbeat_ms / 1000,
            settings.tool_heartbeat_liveness_ms / 1000,
            network,
        )

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
            sub, data = guarded.subindex, guarded.previous.to_bytes(4, "little")
            try:
                # on the priority lane: a released drive must not wait behind a page's polls or
                # an upload-all to stop watching a heartbeat that is about to end
                await self._access.session(node).priority(
                    lambda remote: remote.sdo.download(CONSUMER_HEARTBEAT_TIME, sub, data),
                    what=f"release node {node}: restore 1016h:{sub:02X}h",
                )
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
        await self._producer.stop()

    def _refusal(self, node: int) -> str | None:
        if self._tool in self._known():
            return (
                f"node id {self._tool} (ServoDesk's heartbeat) is used on the bus: "
                "change tool_node_id"
            )
        od = self._access.od(node)
        if od.get(CONSUMER_HEARTBEAT_TIME, 0) is None or od.get(CONSUMER_HEARTBEAT_TIME, 1) is None:
            return "the drive has no heartbeat consumer (1016h): stop it from ServoDesk only"
        return None

    async def _configure(self, node: int) -> str | None:
        session = self._access.session(node)
        count = int.from_bytes(await session.upload(CONSUMER_HEARTBEAT_TIME, 0), "little")
        chosen: tuple[int, int] | None = None
        for sub in range(1, count + 1):
            value = int.from_bytes(await session.upload(CONSUMER_HEARTBEAT_TIME, sub), "little")
            watched, ms = parse_consumer_entry(value)
            if watched == self._tool:
                chosen = (sub, value)  # ours already (left by a previous run): reuse it
                break
            if chosen is None and (watched == 0 or ms == 0):
                chosen = (sub, value)
        if chosen is None:
            return "every heartbeat consumer entry (1016h) of the drive is in use"
        sub, previous = chosen
        if parse_consumer_entry(previous)[0] == self._tool:
            previous = 0  # a left-over of ours: released means unused
        value = consumer_entry(self._tool, self._consumer_ms)
        await session.download(CONSUMER_HEARTBEAT_TIME, sub, value.to_bytes(4, "little"))
        self._guarded[node] = _Guarded(subindex=sub, previous=previous)
        self._why_not.pop(node, None)
        return None

    def _start_producer(self) -> None:
        self._producer.start()

    def _stop_producer_if_idle(self) -> None:
        if not self._guarded:
            self._producer.stop_soon()


class GatedHeartbeat:
    """One CAN frame sent every `period` s by python-can's cyclic send task while the event loop
    has run within `liveness` s; `start`, `stop_soon` and `stop` are called on the loop.

    The loop ticks a timestamp every TICK s and (re)binds the task to the network's current bus
    (a reconnect brings a new one). The task's thread reads the timestamp before each frame: a
    loop silent for longer than `liveness` stops the task, so at most one more frame goes out;
    the next tick starts it again.
    """

    def __init__(
        self,
        cob_id: int,
        period: float,
        liveness: float,
        network: Callable[[], canopen.Network],
    ) -> None:
        self._message = can.Message(
            arbitration_id=cob_id,
            data=make_heartbeat(NmtState.OPERATIONAL),
            is_extended_id=False,
        )
        self._period = period
        self._liveness = liveness
        self._network = network
        self._ticked = time.monotonic()  # written on the loop, read on the task's thread
        self._bus: can.BusABC | None = None
        self._task: can.broadcastmanager.CyclicSendTaskABC | None = None
        self._withheld = False  # the task stopped itself: the loop had stalled
        self._ticker: asyncio.Task[None] | None = None

    def start(self) -> None:
        if self._ticker is None:
            self._ticked = time.monotonic()
            self._bind()
            self._ticker = asyncio.get_running_loop().create_task(
                self._tick(), name="tool-heartbeat"
            )

    def stop_soon(self) -> None:
        ticker, self._ticker = self._ticker, None
        if ticker is not None:
            ticker.cancel()
        self._unbind()

    async def stop(self) -> None:
        ticker = self._ticker
        self.stop_soon()
        if ticker is not None:
            with contextlib.suppress(asyncio.CancelledError):
                await ticker

    async def _tick(self) -> None:
        while True:
            self._ticked = time.monotonic()
            self._bind()
            await asyncio.sleep(TICK)

    def _bind(self) -> None:
        """The task on the network's current bus, running (started again after a stall)."""
        try:
            bus: can.BusABC | None = self._network().bus
        except (ServodeskError, RuntimeError):
            bus = None  # no bus right now: the drives see silence, which is the truth
        if bus is not self._bus:
            self._unbind()
            self._bus = bus
            self._task = self._send(bus)
        elif self._withheld and bus is not None:
            self._withheld = False
            log.warning("the event loop runs again: the tool's heartbeat is sent again")
            self._task = self._send(bus)

    def _send(self, bus: can.BusABC | None) -> can.broadcastmanager.CyclicSendTaskABC | None:
        """python-can's thread-based cyclic task (what `send_periodic` makes for a task with a
        callback on every interface), built here to give it `on_error`: a failing adapter ends
        the task quietly, and the reconnect's new bus gets a new one."""
        if bus is None:
            return None
        mine: list[can.broadcastmanager.CyclicSendTaskABC] = []
        task = can.broadcastmanager.ThreadBasedCyclicSendTask(
            bus,
            threading.Lock(),
            self._message,
            self._period,
            on_error=lambda _: False,
            modifier_callback=partial(self._gate, mine),
        )
        mine.append(task)
        return task

    def _unbind(self) -> None:
        task, self._task, self._bus = self._task, None, None
        self._withheld = False
        if task is not None:
            task.stop()

    def _gate(self, mine: list[can.broadcastmanager.CyclicSendTaskABC], _: can.Message) -> None:
        """The task's thread, before each frame: a loop silent for too long gets no heartbeat.
        `mine` holds the task this call comes from (empty until the task is built)."""
        silent = time.monotonic() - self._ticked
        if silent <= self._liveness or not mine:
            return
        task = mine[0]
        if task is self._task and not self._withheld:
            self._withheld = True
            log.warning(
                "the event loop has not run for %.0f ms: the tool's heartbeat stops, and the "
                "drives that watch it stop by themselves",
                silent * 1000,
            )
        task.stop()  # the frame of this call still goes out: the last one
