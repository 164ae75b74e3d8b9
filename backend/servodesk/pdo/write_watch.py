"""SDO writes to a node's PDO parameters, seen on the bus: what makes its cached PDOs stale.

Fed every frame the tool hears and every frame it sends (BusManager.add_frame_listener with
`sent`), so a PDO write from any path — the PDO page, a raw SDO write, a DCF load, another
master on the bus — drops the node's cached mapping before the drive has even answered.
Runs on the notifier (or sending) thread: it only parses the request and calls `written`,
which must not block.
"""

from __future__ import annotations

from collections.abc import Callable

import can

from servodesk_protocol.cob_id import MAX_NODE_ID, SDO_RX
from servodesk_protocol.sdo import multiplexer, starts_download

Written = Callable[[int, int, int], None]  # node, index, subindex


def written_object(can_id: int, data: bytes) -> tuple[int, int, int] | None:
    """(node, index, subindex) when the frame starts an SDO download (a write), else None."""
    if not SDO_RX < can_id <= SDO_RX + MAX_NODE_ID or not starts_download(data):
        return None
    return can_id - SDO_RX, *multiplexer(data)


class SdoWriteWatch(can.Listener):
    def __init__(self, written: Written) -> None:
        self._written = written

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame or msg.is_remote_frame or msg.is_extended_id:
            return
        found = written_object(msg.arbitration_id, bytes(msg.data))
        if found is not None:
            self._written(*found)

    def stop(self) -> None:
        """Nothing to release: the watch outlives each connection's notifier."""
