"""One capture being recorded: the bus tap, the SDO pollers, the flush task and the files.

The flush task wakes ~30 times a second, drains the frames the notifier queued and hands them
to the capture core on a worker thread (decoding and file writes stay off the event loop).
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from servodesk.errors import CommTimeoutError, SdoAbortError, ServodeskError
from servodesk.events.bus import BusEvent
from servodesk.models.scope import Capture
from servodesk.nodes.access import NodeAccess
from servodesk.scope.capture import CaptureCore, Floats
from servodesk.scope.frames import FrameSink
from servodesk.scope.recording import CaptureRecording
from servodesk.scope.samples import SamplesWriter
from servodesk.scope.setup import SDO_STREAM_BASE

log = logging.getLogger(__name__)

FLUSH_S = 1 / 30  # the live view's refresh: samples reach rerun in batches this often
STALL_S = 2.0  # no new sample for this long after the window should have ended: finish
SILENT_S = 3.0  # a signal that sent nothing for this long after the start fails the capture


class CaptureOutput:
    """Samples to the samples table and the recording; per signal in physical units."""

    def __init__(
        self, capture: Capture, writer: SamplesWriter, recording: CaptureRecording
    ) -> None:
        self.capture = capture
        self.writer = writer
        self.recording = recording
        self._scales = [s.scale for s in capture.signals]

    def samples(self, signal: int, times: Floats, rel: Floats, raw: Floats) -> None:
        values = raw * self._scales[signal]
        self.writer.write(signal, rel, times, raw, values)
        self.recording.samples(self.capture.signals[signal], times, rel, raw, values)

    def texts(
        self, node: int, lane: str, times: Sequence[float], rel: Sequence[float], texts: list[str]
    ) -> None:
        self.recording.texts(f"drives/{node}/{lane}", times, rel, texts)


@dataclass
class CaptureRun:
    capture: Capture
    core: CaptureCore
    sink: FrameSink
    output: CaptureOutput
    started: float = field(default_factory=time.time)
    stop_reason: str | None = None
    events: list[BusEvent] = field(default_factory=list)
    cleanups: list[Callable[[], None]] = field(default_factory=list)
    pollers: list[asyncio.Task[None]] = field(default_factory=list)
    task: asyncio.Task[None] | None = None

    def on_event(self, item: BusEvent) -> None:
        """EventBus subscriber (on the loop): the flush takes them with the frames."""
        self.events.append(item)

    def stop(self, reason: str) -> None:
        if self.stop_reason is None:
            self.stop_reason = reason

    async def flush(self) -> None:
        frames = self.sink.drain()
        events, self.events = self.events, []
        await asyncio.to_thread(self.core.process, frames, events)
        self.refresh()

    def refresh(self) -> None:
        """The capture's record from the core's progress (counts, state, latest values)."""
        capture, core = self.capture, self.core
        for signal, track in zip(capture.signals, core.tracks, strict=True):
            signal.samples = track.count
            if track.last_raw is not None:
                signal.last_value = track.last_raw * signal.scale
            if track.first is not None and track.last is not None and track.count > 1:
                span = track.last - track.first
                signal.rate_hz = round((track.count - 1) / span, 1) if span > 0 else None
        capture.samples = sum(s.samples for s in capture.signals)
        capture.lost = self.sink.lost
        if capture.state in ("arming", "armed") and core.trigger_time is not None:
            capture.state = "running"
        elif capture.state == "arming" and core.listening():
            capture.state = "armed"
        capture.trigger_time = core.trigger_time

    def stalled(self, now: float) -> bool:
        """Past the window's end, a signal still short of its samples has had none for
        STALL_S: its drive stopped sending (NMT state, SYNC, bus, another mapping)."""
        core = self.core
        if core.trigger_time is None or now < core.trigger_time + core.post_s + STALL_S:
            return False
        end = core.trigger_time + core.post_s
        for track in core.tracks:
            short = track.remaining > 0 if track.pdo else (track.last or 0.0) < end
            if short and now - (track.last or self.started) > STALL_S:
                return True
        return False

    def silent(self, now: float) -> list[str]:
        """Signals that have sent nothing at all since the capture started more than
        SILENT_S ago (a free-running capture would wait for ever; an armed one could never
        trigger): their labels, empty when every signal has been heard."""
        if now - self.started < SILENT_S:
            return []
        return [
            f"node {s.node} {s.index:04X}h:{s.subindex:02X}"
            for s, track in zip(self.capture.signals, self.core.tracks, strict=True)
            if track.last is None
        ]


async def poll_sdo(
    access: NodeAccess,
    sink: FrameSink,
    signals: Sequence[tuple[int, int, int, int]],
    period_s: float,
    notes: list[str],
) -> None:
    """Read the SDO-polled signals of one node in turn, as fast as the node answers but not
    faster than the SYNC period; (number, node, index, subindex) per signal."""
    active = list(signals)
    while active:
        began = time.monotonic()
        for item in list(active):
            number, node, index, subindex = item
            try:
                data = await access.session(node).upload(index, subindex)
            except SdoAbortError as error:
                notes.append(f"node {node} {index:04X}h:{subindex:02X}: polling stopped ({error})")
                active.remove(item)
                continue
            except (CommTimeoutError, ServodeskError) as error:
                log.debug("scope SDO poll of node %s failed: %s", node, error)
                await asyncio.sleep(period_s)
                continue
            sink.push((SDO_STREAM_BASE + number, time.time(), data))
        await asyncio.sleep(max(0.0, period_s - (time.monotonic() - began)))


def close_files(run: CaptureRun) -> None:
    """Blocking: the recording flushed to its .rrd and the samples table closed."""
    try:
        run.output.recording.close()
    except Exception:  # the samples table must still be closed; the .rrd may lack its tail
        log.exception("capture %s: closing the rerun recording failed", run.capture.id)
    run.output.writer.close()
