"""The active part of a node scan: an SDO upload request for 1000h to many node ids at once.

Any answer on 580h+id, an abort included, means a node with that id is there. The requests go
out from a worker thread as raw frames; a python-can listener collects the answers (it only adds
to a set: no I/O on the notifier thread). The passive part of a scan (boot-ups and heartbeats
heard so far) lives in network/monitor.py.
"""

from __future__ import annotations

from collections.abc import Iterable

import can
import canopen

from servodesk_protocol import cob_id
from servodesk_protocol.sdo import upload_request

# initiate upload, 1000h:00 Device type (CiA 301 §7.2.4.3.6); every CANopen node has 1000h
UPLOAD_DEVICE_TYPE = upload_request(0x1000, 0)  # 1000h Device type
NODE_IDS = range(1, 128)


class SweepListener(can.Listener):
    """Collects the node ids that answered on 580h+id while it is attached."""

    def __init__(self, ids: Iterable[int]) -> None:
        self._wanted = frozenset(cob_id.SDO_TX + node for node in ids)
        self.found: set[int] = set()

    def on_message_received(self, msg: can.Message) -> None:
        if msg.arbitration_id in self._wanted and not (msg.is_remote_frame or msg.is_error_frame):
            self.found.add(msg.arbitration_id - cob_id.SDO_TX)

    def stop(self) -> None:
        """Nothing to release."""


def send_sweep(network: canopen.Network, ids: Iterable[int]) -> None:
    """Send the 1000h upload request to every id in `ids`, back to back (blocking)."""
    for node in ids:
        network.send_message(cob_id.SDO_RX + node, UPLOAD_DEVICE_TYPE)
