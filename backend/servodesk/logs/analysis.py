"""One log file decoded: the events as a stream, then the summary and the totals.

The CLI and the service both use this: `events()` streams (flat memory), `summary()` and
`stats()` are ready once the stream is exhausted.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from servodesk.logs.context import DecodeContext
from servodesk.logs.decoder import LogDecoder
from servodesk.logs.events import Event, clock
from servodesk.logs.reader import read_frames
from servodesk_data import DriveData


class LogAnalysis:
    def __init__(
        self,
        path: Path,
        *,
        dcf: Path | None = None,
        bitrate: int | None = None,
        known: Sequence[DriveData] | None = None,
        frames: bool = False,
        profiles: Mapping[int, str] | None = None,
    ) -> None:
        self.path = path
        context = DecodeContext(dcf=dcf, known=known, profiles=profiles)
        self.decoder = LogDecoder(context, bitrate=bitrate, frames=frames)
        self._skipped = [0]
        self._done = False

    def events(self, progress: Callable[[int], None] | None = None) -> Iterator[Event]:
        frames = read_frames(self.path, progress=progress, skipped=self._skipped)
        yield from self.decoder.decode(frames)
        self._done = True

    def stats(self) -> dict[str, Any]:
        d = self.decoder
        start = d.first_time if d.first_time is not None else 0.0
        nodes = sorted(set(d.context.nodes) | set(d.seen_nodes()))
        return {
            "frames": d.frame,
            "duration_s": round(d.last_time - start, 6) if d.frame else 0.0,
            "start": start,
            "end": d.last_time,
            "nodes": nodes,
            "profiles": {
                str(n): p.profile.name for n, p in sorted(d.context.nodes.items()) if p.data
            },
            "counts": dict(sorted(d.counts.items())),
            "error_frames": self._skipped[0],
            "bitrate": d.bitrate,
            "bus_load_peak_percent": round(d.load_peak[0], 2),
            "bus_load_peak_time": d.load_peak[1],
            "bus_load_mean_percent": round(d.load_mean, 2),
            "events": d.events_emitted,
            "polling_events": d.polling_events,
        }

    def summary(self) -> list[str]:
        """Totals first, then what happened in order (see SummaryBuilder)."""
        d = self.decoder
        s = self.stats()
        if not s["frames"]:
            return [f"{self.path.name}: no CAN frames"]
        nodes = ", ".join(d.who(n) for n in s["nodes"]) or "no CANopen nodes"
        fd = s["counts"].get("fd", 0)
        header = [
            f"{s['frames']:,} frames over {s['duration_s']:.3f} s"
            f" ({clock(s['start'])} – {clock(s['end'])}) from {nodes}.",
            f"Bus load at {d.bitrate // 1000} kbit/s: peak {s['bus_load_peak_percent']:.1f} %"
            f" in the second from {clock(s['bus_load_peak_time'])},"
            f" mean {s['bus_load_mean_percent']:.1f} %."
            if fd < s["frames"]
            else "Bus load: no classic CAN frames to count.",
        ]
        faults = d.summary.count("emcy")
        aborts = d.summary.count("sdo-abort")
        losses = d.summary.count("heartbeat-lost")
        header.append(
            f"{faults} EMCY(s), {aborts} SDO abort(s), {losses} heartbeat loss(es)."
            if faults or aborts or losses
            else "No EMCY, no SDO abort, no heartbeat loss."
        )
        if fd:
            header.append(
                f"{fd:,} CAN FD frame(s) (more than 8 data bytes) counted, not decoded as"
                " CANopen and not in the bus load."
            )
        if s["polling_events"]:
            header.append(
                f"{s['polling_events']:,} of {s['events']:,} events are SDO polling reads (one"
                " object read again at a steady period, such as ServoDesk's own Drive page);"
                " hide them on the Logs page or with hide_polling=true."
            )
        header += self._emcy_notes()
        if s["error_frames"]:
            header.append(f"{s['error_frames']} CAN error frame(s) in the log.")
        return d.summary.render(header)

    def _emcy_notes(self) -> list[str]:
        """How EMCYs of nodes of unknown drive were read, and how to say which drive it is."""
        d = self.decoder
        notes = [
            f"node {n}: no identity in the log, EMCYs read as CiA 301; name its drive to decode"
            f" vendor alarms (profiles {n}=<profile>, one of {d.context.profile_names()};"
            " or its DCF)."
            for n in sorted(d.read_as_cia301)
            if d.context.node(n).data is None
        ]
        for n in sorted(d.shape_guessed):
            guess = d.context.alarm_profile()
            label = guess.label if guess is not None else "alarm-number drive"
            notes.append(
                f"node {n}: no identity in the log; its 2-byte EMCYs (CiA 301's have 8 bytes)"
                f" are read as {label} alarm numbers."
            )
        return notes
