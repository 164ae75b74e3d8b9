"""A node session that tells the heartbeat monitor how its SDO exchanges went.

For nodes without heartbeats the only evidence of loss is an SDO request that timed out, and
the only evidence of life an answer (an abort is an answer too). A write of 1017h through the
session also tells the monitor the node's new heartbeat period.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import canopen

from servodesk.errors import CommTimeoutError, SdoAbortError
from servodesk.nodes.identity import PRODUCER_HEARTBEAT
from servodesk.nodes.session import NodeSession

T = TypeVar("T")

Outcome = Callable[[int, bool], None]  # (node, answered)
HeartbeatWritten = Callable[[int, int], None]  # (node, period ms)


class TrackedSession(NodeSession):
    def __init__(
        self,
        remote: canopen.RemoteNode,
        *,
        sdo_timeout: float,
        on_outcome: Outcome,
        on_heartbeat_written: HeartbeatWritten,
    ) -> None:
        super().__init__(remote, sdo_timeout=sdo_timeout)
        self._on_outcome = on_outcome
        self._on_heartbeat_written = on_heartbeat_written

    async def run(
        self,
        fn: Callable[[canopen.RemoteNode], T],
        *,
        what: str,
        index: int = 0,
        subindex: int = 0,
    ) -> T:
        try:
            result = await super().run(fn, what=what, index=index, subindex=subindex)
        except CommTimeoutError:
            self._on_outcome(self.node_id, False)
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
