"""The live fault collector's notifier-thread half: a python-can listener that recognises EMCY
(80h+id, ids 1–127) and SDO aborts (580h+id, command specifier 80h) and hands their bytes to the
event loop through `EventBus.hand_over` (DESIGN rule 1: no decoding, no I/O on the notifier
thread). Registered with `BusManager.add_frame_listener`, it follows every reconnect.

Also `quiet_short_emcy`: python-canopen's own EMCY consumer must not flood the log.
"""

from __future__ import annotations

import logging
import struct
import time
from collections.abc import Callable

import can

from servodesk.events.bus import EventBus, EventKind, event
from servodesk.sdo.service import where
from servodesk.sdo_aborts import abort_meaning
from servodesk_protocol.cob_id import EMCY, MAX_NODE_ID, SDO_TX
from servodesk_protocol.sdo import ABORT_COMMAND, parse_abort

EmcyHandler = Callable[[int, bytes, float], None]  # (node, data, UNIX time) on the loop

CANOPEN_LOGGER = "canopen.network"  # logs whatever a subscriber of a CAN id raised
# what python-canopen's EmcyConsumer raises on an EMCY shorter than CiA 301's 8 bytes
_SHORT_EMCY = ""
try:
    struct.Struct("<HB5s").unpack(b"\x00\x00")
except struct.error as error:
    _SHORT_EMCY = str(error)  # "unpack requires a buffer of 8 bytes"


class ShortEmcyFilter(logging.Filter):
    """python-canopen gives every RemoteNode an EMCY consumer on 80h+id that unpacks 8 bytes; a
    drive whose EMCY is shorter (the MDi sends its 2-byte alarm number, MDi-S1-C CANopen manual
    §4.1) makes it raise on every alarm, and canopen logs the struct error. ServoDesk decodes
    EMCYs itself (FrameTap, per the profile's format) and never reads canopen's consumer, so
    exactly that record is dropped; every other canopen error still reaches the log.
    (Unsubscribing `remote.emcy.on_emcy` where nodes are bound, nodes/entry.py, would stop it
    at the source.)"""

    def filter(self, record: logging.LogRecord) -> bool:
        return not (record.levelno == logging.ERROR and record.getMessage() == _SHORT_EMCY)


def quiet_short_emcy() -> None:
    """Install ShortEmcyFilter on canopen's network logger (once per process)."""
    logger = logging.getLogger(CANOPEN_LOGGER)
    if not any(isinstance(f, ShortEmcyFilter) for f in logger.filters):
        logger.addFilter(ShortEmcyFilter())


class FrameTap(can.Listener):
    """Notifier-thread side: recognise EMCY and SDO-abort frames, hand them over, nothing else."""

    def __init__(self, bus: EventBus, on_emcy: EmcyHandler) -> None:
        self._bus = bus
        self._on_emcy = on_emcy

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame or msg.is_remote_frame or msg.is_extended_id:
            return
        can_id = msg.arbitration_id
        if EMCY < can_id <= EMCY + MAX_NODE_ID:
            self._bus.hand_over(self._on_emcy, can_id - EMCY, bytes(msg.data), time.time())
        elif SDO_TX < can_id <= SDO_TX + MAX_NODE_ID and msg.data and msg.data[0] == ABORT_COMMAND:
            self._bus.hand_over(sdo_abort, self._bus, can_id - SDO_TX, bytes(msg.data))

    def stop(self) -> None:
        """Nothing to release: the tap outlives each connection's notifier."""


def sdo_abort(bus: EventBus, node: int, data: bytes) -> None:
    """On the loop: an abort frame in words (CiA 301 §7.2.4.3.17)."""
    parsed = parse_abort(data)
    if parsed is None:
        return
    index, subindex, code = parsed
    meaning = abort_meaning(code)
    bus.publish(
        event(
            EventKind.SDO_ABORT,
            node,
            f"node {node} aborted SDO {where(index, subindex)}: 0x{code:08X} {meaning}",
            {"index": index, "subindex": subindex, "abort_code": f"0x{code:08X}"},
        )
    )
