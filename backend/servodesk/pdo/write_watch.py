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

SDO_RX_BASE = 0x600  # client → server (CiA 301 default SDO COB-IDs)
INITIATE_DOWNLOAD = 1  # ccs of an expedited or segmented download's first frame
BLOCK_DOWNLOAD = 6  # ccs of a block download; client subcommand 0 is its initiate

Written = Callable[[int, int, int], None]  # node, index, subindex


def written_object(can_id: int, data: bytes) -> tuple[int, int, int] | None:
    """(node, index, subindex) when the frame starts an SDO download (a write), else None."""
    if not SDO_RX_BASE < can_id <= SDO_RX_BASE + 0x7F or len(data) < 4:
        return None
    ccs = data[0] >> 5
    starts = ccs == INITIATE_DOWNLOAD or (ccs == BLOCK_DOWNLOAD and data[0] & 0x01 == 0)
    if not starts:
        return None
    return can_id - SDO_RX_BASE, int.from_bytes(data[1:3], "little"), data[3]


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
