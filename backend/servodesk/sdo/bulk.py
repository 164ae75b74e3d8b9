"""Reading many entries of one node: "upload all", DCF export, compare.

Each SDO round trip is short, so per-entry costs on our side (an executor hop, a task, a model
copy) would dominate. Entries are therefore read in chunks: one `NodeSession.run` call reads
entries back to back on the node's worker thread for up to `CHUNK_SECONDS`, then returns, which
lets other requests for the node take their turn and the caller publish progress. A stop event,
checked before every entry, ends a chunk within one SDO round trip.
"""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import NamedTuple, Protocol, TypeVar

from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

from servodesk.nodes.session import NodeSession
from servodesk.od import OdSub

R = TypeVar("R")

CHUNK_SECONDS = 0.05
MAX_TIMEOUTS_IN_A_ROW = 3  # then the node is taken as gone, not as slow on a few entries

# (entry, uploaded bytes or None, abort code or None); neither bytes nor code = no answer
Convert = Callable[[OdSub, bytes | None, int | None], R]


class BulkOutcome(Enum):
    DONE = "done"
    CANCELLED = "cancelled"
    STALLED = "stalled"  # MAX_TIMEOUTS_IN_A_ROW entries in a row got no answer


class EntryRead(NamedTuple):
    """The plain result of reading one entry (for callers that decode on their own)."""

    sub: OdSub
    data: bytes | None
    abort_code: int | None

    @property
    def timed_out(self) -> bool:
        return self.data is None and self.abort_code is None


def as_entry_read(sub: OdSub, data: bytes | None, abort_code: int | None) -> EntryRead:
    return EntryRead(sub, data, abort_code)


class _Uploader(Protocol):
    def upload(self, index: int, subindex: int) -> bytes: ...


class SdoNode(Protocol):
    """What a chunk needs of a canopen RemoteNode: its SDO client's upload."""

    @property
    def sdo(self) -> _Uploader: ...


@dataclass
class ChunkCursor:
    """Where the reading stands. Touched only by the chunk running on the worker thread and,
    between chunks, by the awaiting coroutine (the executor future orders the two)."""

    position: int = 0
    timeouts_in_a_row: int = 0


def read_chunk(
    remote: SdoNode,
    subs: Sequence[OdSub],
    cursor: ChunkCursor,
    convert: Convert[R],
    stop: threading.Event,
    *,
    budget: float = CHUNK_SECONDS,
    max_timeouts: int = MAX_TIMEOUTS_IN_A_ROW,
    clock: Callable[[], float] = time.monotonic,
) -> list[R]:
    """Runs on the node's worker thread: read entries from `cursor` on until the time budget is
    spent, `stop` is set, `max_timeouts` entries in a row went unanswered, or all are read."""
    out: list[R] = []
    upload = remote.sdo.upload
    deadline = clock() + budget
    total = len(subs)
    while cursor.position < total and not stop.is_set():
        sub = subs[cursor.position]
        try:
            data = upload(sub.index, sub.subindex)
        except SdoAbortedError as abort:
            cursor.timeouts_in_a_row = 0
            out.append(convert(sub, None, int(abort.code)))
        except SdoCommunicationError:
            cursor.timeouts_in_a_row += 1
            out.append(convert(sub, None, None))
        else:
            cursor.timeouts_in_a_row = 0
            out.append(convert(sub, bytes(data), None))
        cursor.position += 1
        if cursor.timeouts_in_a_row >= max_timeouts or clock() >= deadline:
            break
    return out


async def read_entries(
    session: NodeSession,
    subs: Sequence[OdSub],
    convert: Convert[R],
    sink: list[R],
    *,
    stop: threading.Event | None = None,
    budget: float = CHUNK_SECONDS,
    max_timeouts: int = MAX_TIMEOUTS_IN_A_ROW,
    progress: Callable[[int, int], None] | None = None,
) -> BulkOutcome:
    """Read `subs` in order, appending `convert(...)` of each to `sink` chunk by chunk.

    Setting `stop` (from any thread) ends the reading after the entry in progress. If the
    awaiting task is cancelled, `stop` is set too so the worker does not read on for nobody.
    """
    halt = stop if stop is not None else threading.Event()
    cursor = ChunkCursor()
    try:
        while True:
            chunk = await session.run(
                lambda remote: read_chunk(
                    remote, subs, cursor, convert, halt, budget=budget, max_timeouts=max_timeouts
                ),
                what=f"read {len(subs)} entries",
            )
            sink.extend(chunk)
            if progress is not None:
                progress(cursor.position, len(subs))
            if cursor.timeouts_in_a_row >= max_timeouts:
                return BulkOutcome.STALLED
            if cursor.position >= len(subs):
                return BulkOutcome.DONE
            if halt.is_set():
                return BulkOutcome.CANCELLED
    except asyncio.CancelledError:
        halt.set()
        raise
