"""Raw-frame recording of the live bus with python-can's writers (BLF, ASC, candump .log, MF4).

The listener on the notifier thread only appends each frame to a bounded queue (DESIGN rule 1);
a writer thread of the recording drains it into the python-can writer. Registered with
`BusManager.add_frame_listener`, it follows reconnects: a recording goes on across them. Frames
the tool itself sends are in the file only when the adapter echoes them (python-can delivers
received frames).
"""

from __future__ import annotations

import asyncio
import collections
import copy
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

import can

from servodesk.errors import StateConflictError

log = logging.getLogger(__name__)

QUEUE_LIMIT = 1_000_000  # frames waiting for the writer thread
WRITER_IDLE = 0.05  # s the writer thread sleeps when the queue is empty


class RecordingFormat(StrEnum):
    BLF = "blf"
    ASC = "asc"
    LOG = "log"  # candump -L
    MF4 = "mf4"  # ASAM MDF 4 (python-can's MF4Writer, through asammdf)


class RecordingNotRunningError(StateConflictError):
    """Stopping a recording when none runs (409 recording_not_running)."""

    def __init__(self) -> None:
        super().__init__("recording_not_running", "no recording is running: start one first")


AddListener = Callable[[can.Listener], Callable[[], None]]


@dataclass(frozen=True)
class RecordingStatus:
    active: bool
    format: str | None
    file: str | None
    since: float | None
    frames: int
    dropped: int


class _Tap(can.Listener):
    """Notifier thread: append only."""

    def __init__(self) -> None:
        self.queue: collections.deque[can.Message] = collections.deque()
        self.dropped = 0

    def on_message_received(self, msg: can.Message) -> None:
        if len(self.queue) >= QUEUE_LIMIT:
            self.dropped += 1
            return
        self.queue.append(msg)

    def stop(self) -> None:
        """The recording closes its writer itself."""


class _Recording:
    def __init__(self, path: Path, fmt: RecordingFormat) -> None:
        self.path = path
        self.format = fmt
        self.since = time.time()
        self.tap = _Tap()
        self.frames = 0
        self._stop = threading.Event()
        self._writer: can.Listener = can.Logger(path)  # the writer is chosen by the suffix
        self._thread = threading.Thread(target=self._run, name="recording", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        queue = self.tap.queue
        while True:
            try:
                msg = queue.popleft()
            except IndexError:
                if self._stop.is_set():
                    break
                time.sleep(WRITER_IDLE)
                continue
            if self.format is RecordingFormat.MF4:
                msg = _fit_channel(msg, 0xFF)
            elif self.format is RecordingFormat.BLF:
                msg = _fit_channel(msg, 0xFFFE)  # written as a 16-bit number + 1
            try:
                self._writer.on_message_received(msg)
            except Exception:  # the thread goes on: the file is still closed properly
                if self.tap.dropped == 0:
                    log.exception("recording: a frame could not be written")
                self.tap.dropped += 1
                continue
            self.frames += 1
        self._writer.stop()

    def finish(self) -> None:
        """Write what is queued, close the file (blocking: run off the loop)."""
        self._stop.set()
        self._thread.join()


def _fit_channel(msg: can.Message, highest: int) -> can.Message:
    """MF4 and BLF keep the bus channel as a number (python-can takes the digits that end the
    channel's name: can0 → 0, and a simulated bus "servodesk-sim-…4817290" → 4817290, which
    stopped every frame of a BLF recording); a channel the file cannot hold is left out (a
    copy: the message is shared with the other listeners)."""
    channel = can.util.channel2int(msg.channel)
    if msg.channel is None or (channel is not None and 0 <= channel <= highest):
        return msg
    frame = copy.copy(msg)
    frame.channel = None
    return frame


class Recorder:
    def __init__(self, add_listener: AddListener, data_dir: Path) -> None:
        self._add_listener = add_listener
        self.root = data_dir / "recordings"
        self._current: _Recording | None = None
        self._remove: Callable[[], None] | None = None
        self._lock = asyncio.Lock()

    def status(self) -> RecordingStatus:
        rec = self._current
        if rec is None:
            return RecordingStatus(False, None, None, None, 0, 0)
        return RecordingStatus(
            True, rec.format.value, rec.path.name, rec.since, rec.frames, rec.tap.dropped
        )

    async def start(self, fmt: RecordingFormat) -> RecordingStatus:
        """Start recording (a running recording goes on: its status is returned)."""
        async with self._lock:
            if self._current is None:
                stamp = time.strftime("%Y%m%d-%H%M%S")
                path = self.root / f"servodesk-{stamp}-{time.time_ns() % 10**9:09d}.{fmt.value}"
                await asyncio.to_thread(self.root.mkdir, parents=True, exist_ok=True)
                rec = await asyncio.to_thread(_Recording, path, fmt)
                self._current = rec
                self._remove = self._add_listener(rec.tap)
            return self.status()

    async def stop(self) -> tuple[Path, RecordingStatus]:
        """Stop and close the file; RecordingNotRunningError when none runs."""
        async with self._lock:
            rec = self._current
            if rec is None:
                raise RecordingNotRunningError
            if self._remove is not None:
                self._remove()
            self._remove = None
            await asyncio.to_thread(rec.finish)
            status = RecordingStatus(
                False, rec.format.value, rec.path.name, rec.since, rec.frames, rec.tap.dropped
            )
            self._current = None
            return rec.path, status

    async def close(self) -> None:
        if self._current is not None:
            await self.stop()
