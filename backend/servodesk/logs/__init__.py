"""Offline CAN log analysis: read any log python-can reads, decode NMT, heartbeats, SDO
transfers, EMCYs and PDOs into a timeline, summarise it in words, export or store it.

- `reader.read_frames`: frames from a file, streamed.
- `sdo.SdoChannel`: SDO transfers reassembled (pure state machine).
- `decoder.LogDecoder`: frames -> events, flat memory.
- `analysis.LogAnalysis`: one file decoded, with summary and totals.
- `store.LogStore`: the service: `decode_file(...)`, `events(id, since, limit)`.
- `export`: text / CSV / JSON lines / Parquet writers; `pcap`: frames as a SocketCAN pcap.
"""

from __future__ import annotations

from servodesk.logs.analysis import LogAnalysis
from servodesk.logs.events import Event, EventKind
from servodesk.logs.reader import LogFormatError, read_frames
from servodesk.logs.store import LogNotFoundError, LogResult, LogStore

__all__ = [
    "Event",
    "EventKind",
    "LogAnalysis",
    "LogFormatError",
    "LogNotFoundError",
    "LogResult",
    "LogStore",
    "read_frames",
]
