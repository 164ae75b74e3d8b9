"""The live fault collector's notifier-thread half: subscribes to the bus's frame tap
(`BusManager.frames`, bus/frame_tap.py: EMCY 80h+id and SDO aborts 580h+id, recognised once for
every service) and hands the frames' bytes to the event loop through `EventBus.hand_over`
(DESIGN rule 1: no decoding, no I/O on the notifier thread). The tap follows every reconnect.

Also `quiet_short_emcy`: python-canopen's own EMCY consumer must not flood the log.
"""

from __future__ import annotations

import logging
import struct
import time
from collections.abc import Callable

from servodesk.bus.frame_tap import FrameTap
from servodesk.events.bus import EventBus, EventKind, event
from servodesk.events.texts import say
from servodesk.sdo.service import where
from servodesk.sdo_aborts import abort_meaning
from servodesk_protocol.sdo import parse_abort

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
    EMCYs itself (the fault service, per the profile's format) and never reads canopen's
    consumer, so exactly that record is dropped; every other canopen error still reaches the log.
    (Unsubscribing `remote.emcy.on_emcy` where nodes are bound, nodes/entry.py, would stop it
    at the source.)"""

    def filter(self, record: logging.LogRecord) -> bool:
        return not (record.levelno == logging.ERROR and record.getMessage() == _SHORT_EMCY)


def quiet_short_emcy() -> None:
    """Install ShortEmcyFilter on canopen's network logger (once per process)."""
    logger = logging.getLogger(CANOPEN_LOGGER)
    if not any(isinstance(f, ShortEmcyFilter) for f in logger.filters):
        logger.addFilter(ShortEmcyFilter())


def collect(frames: FrameTap, bus: EventBus, on_emcy: EmcyHandler) -> Callable[[], None]:
    """Subscribe to the tap: on the notifier thread each EMCY (with its time of arrival) and SDO
    abort is handed over to the loop, nothing else. Returns the remover of both."""

    def emcy(node: int, data: bytes) -> None:
        bus.hand_over(on_emcy, node, data, time.time())

    def abort(node: int, data: bytes) -> None:
        bus.hand_over(sdo_abort, bus, node, data)

    removers = (frames.on_emcy(emcy), frames.on_sdo_abort(abort))

    def remove() -> None:
        for remover in removers:
            remover()

    return remove


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
            say(
                "event.sdo_abort",
                node=node,
                where=where(index, subindex),
                abort_code=f"0x{code:08X}",
                meaning=meaning,
            ),
            {"index": index, "subindex": subindex, "abort_code": f"0x{code:08X}"},
        )
    )
