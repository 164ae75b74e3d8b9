"""Timeline events of a decoded CAN log: one flat record type, so CSV, JSON lines, Parquet and
SQLite all store the same columns."""

from __future__ import annotations

import time as _time
from dataclasses import asdict, dataclass
from enum import StrEnum
from typing import Any


class EventKind(StrEnum):
    NMT = "nmt"  # an NMT command (000h)
    BOOT_UP = "boot-up"
    NMT_STATE = "nmt-state"  # a node's heartbeat reports another state
    HEARTBEAT_LOST = "heartbeat-lost"
    HEARTBEAT_RESUMED = "heartbeat-resumed"
    SDO = "sdo"  # a finished transfer
    SDO_ABORT = "sdo-abort"
    SDO_ERROR = "sdo-error"  # frames that broke the protocol, or a transfer cut off
    EMCY = "emcy"
    PDO = "pdo"  # a PDO decoded with its mapping
    CIA402_STATE = "cia402-state"  # the statusword shows another CiA 402 state
    LSS = "lss"  # a layer setting services frame (CiA 305)
    TIME = "time"  # a TIME stamp (TIME_OF_DAY)
    BUS_LOAD = "bus-load"  # one per second of log
    FRAME = "frame"  # per-frame detail (only when asked for)


COLUMNS = (
    "seq", "time", "frame", "kind", "node", "text", "index", "subindex", "code", "data", "polling",
)  # fmt: skip


@dataclass(frozen=True, slots=True)
class Event:
    seq: int  # 0, 1, 2 … in the order the decoder emits them (the paging cursor)
    time: float  # the log's timestamp, s
    frame: int  # 1-based number of the frame that produced it (0: end of log)
    kind: str  # EventKind value
    node: int | None
    text: str  # in words, for the timeline
    index: int | None = None  # object index (SDO, PDO object)
    subindex: int | None = None
    code: int | None = None  # NMT command or state / SDO abort / EMCY code / LSS cs / load ‰
    data: str | None = None  # JSON detail (fault record, PDO values) or hex data
    polling: bool = False  # an SDO read repeated at a steady period (logs/polling.py)

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def clock(t: float) -> str:
    """A log time for people: wall-clock "12:03:44.120" for absolute stamps (local time),
    "+12.345 s" for stamps relative to the start of a recording."""
    if t < 1e8:  # under ~3 years: a relative stamp (ASC/TRC files often start at 0)
        return f"+{t:.3f} s"
    local = _time.localtime(t)
    return f"{_time.strftime('%H:%M:%S', local)}.{int(t * 1000) % 1000:03d}"
