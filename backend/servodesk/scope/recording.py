"""A capture as a rerun recording: one RecordingStream per capture, owned by the capture,
written to its .rrd file and (while live) to the app's loopback rerun server.

Entity paths: `drives/{node}/{key}` in physical units, `raw/drives/{node}/{key}` as the drive
sends it, `drives/{node}/state` the CiA 402 state lane and `drives/{node}/events` (NMT, EMCY,
the trigger) as text annotations; under a statusword or controlword its lanes
(`drives/{node}/statusword/state`, `…/statusword/bit_10 target reached`, scope/lanes.py) as
state changes, drawn one under the other in a state timeline. Two timelines: `time` (wall
clock, all nodes on one axis) and `capture` (seconds from the trigger, negative before it).
Samples go in columns, a batch per flush (`send_columns`), never one log call per sample.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt
import rerun as rr
import rerun.blueprint as rrb

from servodesk.models.scope import Capture, CaptureSignal
from servodesk.scope.lanes import Lane, LaneTracker, lanes_for

Floats = npt.NDArray[np.float64]
APPLICATION_ID = "servodesk-scope"
WINDOW_S = 5.0  # the live plots scroll over the last seconds
FILE_CHUNK_S = 1.0  # samples reach the .rrd in chunks of about this long …
FILE_CHUNK_ROWS = 65_536  # … or this many rows
NS = 1_000_000_000

# one colour per node, so a node's signals read alike across the plots
_COLOURS = ((31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189))


def signal_path(signal: CaptureSignal, *, raw: bool = False) -> str:
    path = f"drives/{signal.node}/{signal.key}"
    return f"raw/{path}" if raw else path


def signal_lanes(capture: Capture, signal: CaptureSignal) -> list[Lane]:
    chosen = capture.lanes
    return lanes_for(signal.index, signal.subindex, chosen.statusword_bits, chosen.controlword_bits)


def lane_path(signal: CaptureSignal, lane: Lane) -> str:
    return f"{signal_path(signal)}/{rr.escape_entity_path_part(lane.key)}"


def blueprint(capture: Capture) -> rrb.Blueprint:
    """One plot per quantity (position, velocity, torque…) with every node's signals of that
    quantity, the raw values below, the state and event annotations beside."""
    by_quantity: dict[str, list[CaptureSignal]] = {}
    for signal in capture.signals:
        by_quantity.setdefault(signal.quantity, []).append(signal)
    scrolling = rrb.VisibleTimeRange(
        "time",
        start=rrb.TimeRangeBoundary.cursor_relative(seconds=-WINDOW_S),
        end=rrb.TimeRangeBoundary.cursor_relative(),
    )
    plots: list[rrb.View] = []
    for quantity, signals in by_quantity.items():
        unit = signals[0].unit
        title = quantity.replace("_", " ").capitalize() + (f" [{unit}]" if unit else "")
        plots.append(
            rrb.TimeSeriesView(
                name=title,
                origin="/",
                contents=[f"+ /{signal_path(s)}" for s in signals],
                time_ranges=scrolling,
            )
        )
    worded = [s for s in capture.signals if signal_lanes(capture, s)]
    if worded:  # the words' lanes, one under the other: readable at a glance
        plots.append(
            rrb.StateTimelineView(
                name="Statusword and controlword lanes",
                origin="/",
                contents=[f"+ /{signal_path(s)}/**" for s in worded],
                time_ranges=scrolling,
            )
        )
    raw = rrb.TimeSeriesView(
        name="Raw values", origin="/raw", contents="$origin/**", time_ranges=scrolling
    )
    lanes = rrb.TextLogView(name="States and events", origin="/drives")
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(*plots, raw),
            lanes,
            column_shares=[3, 1],
        ),
        rrb.TimePanel(timeline="time"),
        collapse_panels=True,
    )


@dataclass
class _Pending:
    """Samples of one signal waiting to go to the file as one larger chunk."""

    since: float  # monotonic time of the oldest
    parts: list[tuple[Floats, Floats, Floats, Floats]] = field(default_factory=list)
    rows: int = 0


class CaptureRecording:
    """Two streams of one recording (same recording id): the live one gets every flush's
    batch (~30 Hz) for the viewer; the file one gets them gathered into chunks of about a
    second. rerun's file writer keeps an index entry per chunk in memory until the file is
    closed, so per-flush chunks would grow memory through a long capture."""

    def __init__(self, capture: Capture, rrd_path: Path, live_url: str | None) -> None:
        self.file = rr.RecordingStream(APPLICATION_ID, recording_id=capture.recording_id)
        self.file.set_sinks(rr.FileSink(str(rrd_path)), default_blueprint=blueprint(capture))
        self.live: rr.RecordingStream | None = None
        if live_url is not None:
            self.live = rr.RecordingStream(APPLICATION_ID, recording_id=capture.recording_id)
            self.live.set_sinks(rr.GrpcSink(live_url), default_blueprint=blueprint(capture))
        self._pending: dict[str, _Pending] = {}
        self._signals = {signal_path(s): s for s in capture.signals}
        self._lanes = {
            signal_path(s): LaneTracker(lanes)
            for s in capture.signals
            if (lanes := signal_lanes(capture, s))
        }
        name = capture.name or f"Capture {capture.id}"
        for rec in self._streams:
            rec.send_recording_name(name)
            for signal in capture.signals:
                colour = _COLOURS[(signal.node - 1) % len(_COLOURS)]
                unit = f" [{signal.unit}]" if signal.unit else ""
                raw_unit = f" [{signal.raw_unit}]" if signal.raw_unit else ""
                label = f"node {signal.node} {signal.name}"
                rec.log(
                    signal_path(signal),
                    rr.SeriesLines(names=label + unit, colors=[colour]),
                    static=True,
                )
                rec.log(
                    signal_path(signal, raw=True),
                    rr.SeriesLines(names=label + raw_unit, colors=[colour]),
                    static=True,
                )
                for lane in signal_lanes(capture, signal):
                    rec.log(lane_path(signal, lane), _lane_style(lane), static=True)

    @property
    def _streams(self) -> list[rr.RecordingStream]:
        return [self.file] if self.live is None else [self.file, self.live]

    def samples(
        self, signal: CaptureSignal, times: Floats, rel: Floats, raw: Floats, values: Floats
    ) -> None:
        if self.live is not None:
            _send(self.live, signal, times, rel, raw, values)
        path = signal_path(signal)
        pending = self._pending.get(path)
        if pending is None:
            pending = self._pending[path] = _Pending(time.monotonic())
        self._send_lanes(signal, path, times, rel, raw)
        pending.parts.append((times, rel, raw, values))
        pending.rows += times.size
        if pending.rows >= FILE_CHUNK_ROWS or time.monotonic() - pending.since >= FILE_CHUNK_S:
            self._write(path)

    def _send_lanes(
        self, signal: CaptureSignal, path: str, times: Floats, rel: Floats, raw: Floats
    ) -> None:
        tracker = self._lanes.get(path)
        if tracker is None:
            return
        for change in tracker.feed(raw):
            rows = change.rows
            for rec in self._streams:  # a change now and then: straight to both
                rec.send_columns(
                    lane_path(signal, change.lane),
                    indexes=_indexes(times[rows], rel[rows]),
                    columns=rr.StateChange.columns(state=change.texts),
                )

    def _write(self, path: str) -> None:
        pending = self._pending.pop(path, None)
        if pending is None or not pending.parts:
            return
        columns = [np.concatenate(part) for part in zip(*pending.parts, strict=True)]
        _send(self.file, self._signals[path], *columns)

    def texts(
        self,
        path: str,
        times: Sequence[float],
        rel: Sequence[float],
        texts: Sequence[str],
        level: str = "INFO",
    ) -> None:
        if not texts:
            return
        t = np.asarray(times, dtype=np.float64)
        r = np.asarray(rel, dtype=np.float64)
        for rec in self._streams:  # rare: straight to both
            rec.send_columns(
                path,
                indexes=_indexes(t, r),
                columns=rr.TextLog.columns(text=list(texts), level=[level] * len(texts)),
            )

    def close(self) -> None:
        """Everything written to the file and sent; the live viewer keeps what it has."""
        for path in list(self._pending):
            self._write(path)
        for rec in self._streams:
            rec.flush()
            rec.disconnect()


def _send(
    rec: rr.RecordingStream,
    signal: CaptureSignal,
    times: Floats,
    rel: Floats,
    raw: Floats,
    values: Floats,
) -> None:
    indexes = _indexes(times, rel)
    rec.send_columns(
        signal_path(signal), indexes=indexes, columns=rr.Scalars.columns(scalars=values)
    )
    rec.send_columns(
        signal_path(signal, raw=True), indexes=indexes, columns=rr.Scalars.columns(scalars=raw)
    )


# state colours: green where the drive works, red on faults, grey where it is off
_STATE_COLOURS = {
    "Not ready to switch on": 0x9E9E9EFF,
    "Switch on disabled": 0xBDBDBDFF,
    "Ready to switch on": 0x90CAF9FF,
    "Switched on": 0x42A5F5FF,
    "Operation enabled": 0x43A047FF,
    "Quick stop active": 0xFFA000FF,
    "Fault reaction active": 0xEF6C00FF,
    "Fault": 0xE53935FF,
    "no CiA 402 state": 0x616161FF,
}
_BIT_OFF, _BIT_ON = 0x9E9E9E40, 0x1E88E5FF  # a cleared bit stays faint, a set one stands out


def _lane_style(lane: Lane) -> rr.StateConfiguration:
    if lane.kind == "state":
        return rr.StateConfiguration(
            values=list(_STATE_COLOURS), colors=list(_STATE_COLOURS.values())
        )
    if lane.kind == "bit":
        return rr.StateConfiguration(values=["0", "1"], colors=[_BIT_OFF, _BIT_ON])
    return rr.StateConfiguration()  # the command lane: the viewer's own palette


def _indexes(times: Floats, rel: Floats) -> list[rr.TimeColumn]:
    return [
        rr.TimeColumn("time", timestamp=(times * NS).astype(np.int64).astype("datetime64[ns]")),
        rr.TimeColumn("capture", duration=(rel * NS).astype(np.int64).astype("timedelta64[ns]")),
    ]
