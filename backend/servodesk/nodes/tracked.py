"""A node session that tells the heartbeat monitor how its SDO exchanges went, and names NMT
Stopped instead of a bare timeout.

For nodes without heartbeats the only evidence of loss is an SDO request that timed out, and
the only evidence of life an answer (an abort is an answer too). A write of 1017h through the
session also tells the monitor the node's new heartbeat period. A node known to be Stopped
(its heartbeat says so, or the tool stopped it) has no SDO (MDi-S1-C manual table 2.8): a request
is refused at once with NodeStoppedError, and a timeout that turns out to be that is named so.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import TypeVar

import canopen

from servodesk.errors import CommTimeoutError, NodeStoppedError, SdoAbortError
from servodesk.nodes.identity import PRODUCER_HEARTBEAT
from servodesk.nodes.session import NodeSession
from servodesk.nodes.write_step import WriteStep

T = TypeVar("T")

Outcome = Callable[[int, bool], None]  # (node, answered)
HeartbeatWritten = Callable[[int, int], None]  # (node, period ms)
IsStopped = Callable[[int], bool]  # the monitor knows the node to be NMT Stopped


class TrackedSession(NodeSession):
    def __init__(
        self,
        remote: canopen.RemoteNode,
        *,
        sdo_timeout: float,
        on_outcome: Outcome,
        on_heartbeat_written: HeartbeatWritten,
        is_stopped: IsStopped | None = None,
    ) -> None:
        super().__init__(remote, sdo_timeout=sdo_timeout)
        self._on_outcome = on_outcome
        self._on_heartbeat_written = on_heartbeat_written
        self._is_stopped = is_stopped

    def _stopped(self) -> bool:
        return self._is_stopped is not None and self._is_stopped(self.node_id)

    async def run(
        self,
        fn: Callable[[canopen.RemoteNode], T],
        *,
        what: str,
        index: int = 0,
        subindex: int = 0,
        command: bool = False,
    ) -> T:
        if self._stopped():
            raise NodeStoppedError(self.node_id)
        call = super().run(fn, what=what, index=index, subindex=subindex, command=command)
        return await self._tracked(call)

    async def priority(self, fn: Callable[[canopen.RemoteNode], T], *, what: str) -> T:
        # A Stopped node has no SDO: say so at once rather than after a timeout (a stop would
        # otherwise hold its caller for the whole SDO timeout).
        if self._stopped():
            raise NodeStoppedError(self.node_id)
        return await self._tracked(super().priority(fn, what=what))

    async def _tracked(self, call: Awaitable[T]) -> T:
        """Await `call` and tell the monitor whether the node answered."""
        try:
            result = await call
        except CommTimeoutError as timeout:
            self._on_outcome(self.node_id, False)
            if self._stopped():  # a heartbeat said "stopped" while we waited
                raise NodeStoppedError(self.node_id) from timeout
            raise
        except SdoAbortError:
            self._on_outcome(self.node_id, True)
            raise
        self._on_outcome(self.node_id, True)
        return result

    async def download(self, index: int, subindex: int, data: bytes) -> None:
        await super().download(index, subindex, data)
        if index == PRODUCER_HEARTBEAT and subindex == 0 and data:
            self._on_heartbeat_written(self.node_id, int.from_bytes(data[:2], "little"))

    async def write_and_read(
        self,
        index: int,
        subindex: int,
        data: bytes,
        *,
        read_back: bool,
        read_first: bool = False,
        seen: WriteStep | None = None,
    ) -> bytes | None:
        result = await super().write_and_read(
            index, subindex, data, read_back=read_back, read_first=read_first, seen=seen
        )
        if index == PRODUCER_HEARTBEAT and subindex == 0 and data:
            self._on_heartbeat_written(self.node_id, int.from_bytes(data[:2], "little"))
        return result
