"""One capture's data path, run on the flush thread: frames in, samples out.

Each flush hands `CaptureCore.process` the frames queued since the last one (and the timeline
events of the captured nodes). The core decodes them per frame stream (batch.py), waits for the
trigger while keeping `pre_s` of history, then writes the window — `pre_s` before the trigger,
`post` after — to the samples table and the rerun recording.

A TPDO signal's window is counted in SYNC cycles on both sides of the trigger (pre_s / SYNC
period samples before it, the rest of the duration after: sample k belongs to SYNC k, whatever
the host's timing, so a SYNC sent late and made up later moves no sample out of the window); an
SDO-polled signal's by time. Pure of the bus and the loop: the service does the I/O around it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
import numpy.typing as npt

from servodesk.events.bus import BusEvent, EventKind
from servodesk.scope.batch import BatchDecoder, sdo_value, strictly_increasing
from servodesk.scope.frames import Frame
from servodesk.scope.trigger import BitTrigger, Fired, LevelTrigger, StateTrigger, state_changes
from servodesk.scope.trigger import state_words as state_text
from servodesk_protocol.cia402 import STATUSWORD

Floats = npt.NDArray[np.float64]
_EMPTY = np.empty(0, dtype=np.float64)
ANNOTATED = (  # timeline events shown beside the plots
    EventKind.NMT,
    EventKind.BOOT_UP,
    EventKind.NODE_LOST,
    EventKind.NODE_BACK,
    EventKind.EMCY,
    EventKind.FAULT_CLEARED,
    EventKind.FAULT_RESET,
)


class Output(Protocol):
    """Where the window's samples go (the samples table and the rerun recording)."""

    def samples(self, signal: int, times: Floats, rel: Floats, raw: Floats) -> None: ...

    def texts(
        self, node: int, lane: str, times: Sequence[float], rel: Sequence[float], texts: list[str]
    ) -> None: ...


@dataclass
class SignalTrack:
    """One signal's progress through the capture."""

    number: int  # position in Capture.signals
    node: int
    index: int
    subindex: int
    pdo: bool
    data_type: int | None
    remaining: int  # TPDO samples still wanted after the trigger
    before: int = 0  # TPDO samples kept from before the trigger
    count: int = 0
    first: float | None = None
    last: float | None = None  # arrival time of the latest sample (monotonic fix-up)
    last_raw: float | None = None
    ring: list[tuple[Floats, Floats]] = field(default_factory=list)  # pre-trigger history
    state: int | None = None  # statusword: the last CiA 402 state written


@dataclass(frozen=True)
class Stream:
    """A frame stream: a TPDO (decoder and its signals) or one SDO-polled signal."""

    decoder: BatchDecoder | None
    signals: tuple[int, ...]


@dataclass(frozen=True)
class TriggerSetup:
    kind: str  # none | level | bit | emcy | state
    detector: LevelTrigger | BitTrigger | StateTrigger | None = None
    signal: int | None = None  # the track the detector watches
    emcy_node: int | None = None  # emcy: this node (None: any)


class CaptureCore:
    def __init__(
        self,
        tracks: Sequence[SignalTrack],
        streams: dict[int, Stream],
        trigger: TriggerSetup,
        output: Output,
        *,
        pre_s: float,
        post_s: float,
        nodes: Sequence[int],
    ) -> None:
        self.tracks = list(tracks)
        self.streams = streams
        self.trigger = trigger
        self.output = output
        self.pre_s = pre_s
        self.post_s = post_s
        self.nodes = frozenset(nodes)
        self.trigger_time: float | None = None
        self.trigger_words: str | None = None
        self.short_frames = 0
        self._recent_events: list[BusEvent] = []
        self._newest = 0.0  # the latest sample time seen

    @property
    def armed(self) -> bool:
        return self.trigger_time is None

    def listening(self) -> bool:
        """The trigger can fire: the signal it watches has sent its first sample (a level or
        edge is judged against the one before it); emcy or free-running: any signal has."""
        signal = self.trigger.signal
        tracks = self.tracks if signal is None else [self.tracks[signal]]
        return any(track.last is not None for track in tracks)

    def done(self) -> bool:
        if self.trigger_time is None:
            return False
        end = self.trigger_time + self.post_s
        for track in self.tracks:
            if track.pdo and track.remaining > 0:
                return False
            if not track.pdo and (track.last is None or track.last < end):
                return False
        return True

    def process(self, frames: Sequence[Frame], events: Sequence[BusEvent]) -> None:
        batches = self._decode(frames)
        if self.armed:
            self._arm(batches, events)
        else:
            for number, (times, raw) in batches.items():
                self._emit(self.tracks[number], times, raw)
            self._annotate(events)

    # ------------------------------------------------------------------ decoding

    def _decode(self, frames: Sequence[Frame]) -> dict[int, tuple[Floats, Floats]]:
        grouped: dict[int, tuple[list[float], list[bytes]]] = {}
        for can_id, stamp, payload in frames:
            group = grouped.get(can_id)
            if group is None:
                group = grouped[can_id] = ([], [])
            group[0].append(stamp)
            group[1].append(payload)
        out: dict[int, tuple[Floats, Floats]] = {}
        for can_id, (stamps, payloads) in grouped.items():
            stream = self.streams.get(can_id)
            if stream is None:
                continue
            times = np.asarray(stamps, dtype=np.float64)
            decoder = stream.decoder
            if decoder is None:
                track = self.tracks[stream.signals[0]]
                raw = np.fromiter((sdo_value(p, track.data_type) for p in payloads), np.float64)
                columns = [raw]
            else:
                short = decoder.short(payloads)
                if short.any():  # another mapping than the scope set: those frames are skipped
                    self.short_frames += int(short.sum())
                    keep = ~short
                    times = times[keep]
                    payloads = [p for p, ok in zip(payloads, keep, strict=True) if ok]
                columns = decoder.decode(decoder.words(payloads))
            first = self.tracks[stream.signals[0]]
            times = strictly_increasing(times, first.last)
            for number, raw in zip(stream.signals, columns, strict=True):
                track = self.tracks[number]
                track.last = float(times[-1]) if times.size else track.last
                if raw.size:
                    track.last_raw = float(raw[-1])
                out[number] = (times, raw)
            if times.size:
                self._newest = max(self._newest, float(times[-1]))
        return out

    # ------------------------------------------------------------------ waiting for the trigger

    def _arm(self, batches: dict[int, tuple[Floats, Floats]], events: Sequence[BusEvent]) -> None:
        for number, batch in batches.items():
            if batch[0].size:  # a batch of skipped (short) frames only: nothing to keep
                self.tracks[number].ring.append(batch)
        self._recent_events.extend(e for e in events if e.node in self.nodes)
        fired = self._fired(batches, events)
        if fired is None:
            self._prune()
            return
        self.trigger_time = fired.time
        self.trigger_words = fired.words
        start = fired.time - self.pre_s
        for track in self.tracks:
            if not track.ring:
                continue
            times = np.concatenate([t for t, _ in track.ring])
            raw = np.concatenate([r for _, r in track.ring])
            track.ring.clear()
            if track.pdo:  # the last `before` samples ahead of the trigger, counted in SYNCs
                ahead = int(np.count_nonzero(times < fired.time))
                keep = np.arange(times.size) >= ahead - track.before
            else:
                keep = times >= start
            self._emit(track, times[keep], raw[keep], counted=True)
        node = self._trigger_node()
        self.output.texts(node, "events", [fired.time], [0.0], [f"trigger: {fired.words}"])
        recent, self._recent_events = self._recent_events, []
        self._annotate(recent)

    def _fired(
        self, batches: dict[int, tuple[Floats, Floats]], events: Sequence[BusEvent]
    ) -> Fired | None:
        trigger = self.trigger
        if trigger.kind == "none":
            firsts = [float(t[0]) for t, _ in batches.values() if t.size]
            if not firsts:
                return None
            return Fired(min(firsts), 0, "free-running: the first sample")
        if trigger.kind == "emcy":
            for item in events:
                if item.kind is EventKind.EMCY and (
                    trigger.emcy_node is None or item.node == trigger.emcy_node
                ):
                    return Fired(item.time, 0, f"EMCY from node {item.node}: {item.message}")
            return None
        if trigger.detector is None or trigger.signal is None:
            return None
        batch = batches.get(trigger.signal)
        if batch is None:
            return None
        return trigger.detector.feed(*batch)

    def _trigger_node(self) -> int:
        if self.trigger.signal is not None:
            return self.tracks[self.trigger.signal].node
        if self.trigger.emcy_node is not None:
            return self.trigger.emcy_node
        return min(self.nodes)

    def _prune(self) -> None:
        """Keep `pre_s` of history (and a margin) per signal: bounded by the pre-trigger time."""
        horizon = self._newest - self.pre_s - 0.1
        for track in self.tracks:
            ring = track.ring
            while len(ring) > 1 and ring[1][0].size and ring[1][0][0] < horizon:
                ring.pop(0)
            if ring and ring[0][0].size and ring[0][0][-1] < horizon:
                ring.pop(0)
        cutoff = self._newest - self.pre_s - 1.0
        self._recent_events = [e for e in self._recent_events if e.time >= cutoff]

    # ------------------------------------------------------------------ writing the window

    def _emit(
        self, track: SignalTrack, times: Floats, raw: Floats, *, counted: bool = False
    ) -> None:
        if self.trigger_time is None:  # only called once triggered
            return
        start = self.trigger_time - self.pre_s
        # late arrivals from before the window (a TPDO's: from before the trigger, whose
        # `before` SYNCs were taken from the ring when it fired) are not the window's
        first = self.trigger_time if track.pdo else start
        if not counted and times.size and times[0] < first:
            keep = times >= first
            times, raw = times[keep], raw[keep]
        if track.pdo:
            # the window after the trigger is counted in SYNC cycles
            after = int(np.count_nonzero(times >= self.trigger_time))
            excess = max(0, after - track.remaining)
            if excess:
                times, raw = times[: times.size - excess], raw[: raw.size - excess]
            track.remaining -= after - excess
        else:
            keep = times < self.trigger_time + self.post_s
            times, raw = times[keep], raw[keep]
        if not times.size:
            return
        if track.first is None:
            track.first = float(times[0])
        track.count += int(times.size)
        rel = times - self.trigger_time
        self.output.samples(track.number, times, rel, raw)
        if track.index == STATUSWORD and track.subindex == 0:
            changes, track.state = state_changes(times, raw, track.state)
            if changes:
                self.output.texts(
                    track.node,
                    "state",
                    [t for t, _ in changes],
                    [t - self.trigger_time for t, _ in changes],
                    [state_text(s) for _, s in changes],
                )

    def _annotate(self, events: Sequence[BusEvent]) -> None:
        start = (self.trigger_time or 0.0) - self.pre_s
        for item in events:
            if item.node not in self.nodes or item.kind not in ANNOTATED or item.time < start:
                continue
            rel = item.time - (self.trigger_time or 0.0)
            self.output.texts(item.node, "events", [item.time], [rel], [item.message])
