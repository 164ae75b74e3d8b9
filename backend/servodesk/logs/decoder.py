"""Streaming CANopen log decoder: frames in bus order -> timeline events and a summary.

Flat memory: per-node state (NMT state, heartbeat period, one SDO channel) and per-second bus
load are all it keeps; events leave through `decode()` as they happen. Dispatch is one lookup
in a 2048-entry table by CAN id (function code + node id resolved once, not per frame).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import Any

from servodesk.faults.decode import decode_emcy, fault_words
from servodesk.logs.context import DecodeContext
from servodesk.logs.events import Event, EventKind, clock
from servodesk.logs.lss_time import lss_text, time_of_day
from servodesk.logs.polling import PollingDetector
from servodesk.logs.sdo import SdoChannel, SdoTransfer
from servodesk.logs.sdo_text import cia402_state_of, transfer_text
from servodesk.logs.summary import SummaryBuilder
from servodesk.pdo.bus_load import frame_bits
from servodesk.pdo.decode import value_text
from servodesk_protocol import cob_id, nmt
from servodesk_protocol.cia402 import STATUSWORD

DEFAULT_BITRATE = 500_000
HEARTBEAT_LOSS_PERIODS = 3.0  # silence of this many periods is a lost heartbeat
CLASSIC_MAX = 8  # data bytes of a classic CAN frame; more is CAN FD
_FRAME_BITS = tuple(frame_bits(n) for n in range(CLASSIC_MAX + 1))
_STATE_WORDS = {
    nmt.NmtState.INITIALISING: "Initialising",
    nmt.NmtState.STOPPED: "Stopped",
    nmt.NmtState.OPERATIONAL: "Operational",
    nmt.NmtState.PRE_OPERATIONAL: "Pre-operational",
}
_COMMAND_WORDS = {
    nmt.NmtCommand.START: "Start remote node",
    nmt.NmtCommand.STOP: "Stop remote node",
    nmt.NmtCommand.ENTER_PRE_OPERATIONAL: "Enter pre-operational",
    nmt.NmtCommand.RESET_NODE: "Reset node",
    nmt.NmtCommand.RESET_COMMUNICATION: "Reset communication",
}
_LSS_SAID = {0x04, 0x11, 0x13, 0x15, 0x17}  # LSS commands that change a node's set-up
ALARM_EMCY_LENGTH = 2  # the MDi-S1-C's EMCY: its alarm number only (manual §2.7)
Handler = Callable[[float, int, bytes], None]


@dataclass
class _Node:
    state: int | None = None  # NMT state byte of the last heartbeat
    last_heartbeat: float | None = None
    period: float | None = None  # estimated heartbeat period, s
    lost: bool = False
    cia402: str | None = None  # CiA 402 state name from the last statusword seen
    sdo: SdoChannel = field(default_factory=SdoChannel)


class LogDecoder:
    """Feed frames with `feed(time, can_id, data)` (or iterate `decode(frames)`); events pile up
    in `pending` until taken. `frames=True` adds a FRAME event per NMT/SDO/EMCY frame with its
    decoded fields (for comparisons with other decoders)."""

    def __init__(
        self,
        context: DecodeContext,
        *,
        bitrate: int | None = None,
        frames: bool = False,
    ) -> None:
        self.context = context
        self.bitrate = bitrate or context.bitrate or DEFAULT_BITRATE
        self.frames_mode = frames
        self.pending: list[Event] = []
        self.summary = SummaryBuilder()
        self.counts: dict[str, int] = {}
        self.frame = 0
        self.first_time: float | None = None
        self.last_time = 0.0
        self._seq = 0
        self._nodes: dict[int, _Node] = {}
        self._second: float | None = None  # start of the bus-load second being counted
        self._bits = 0
        self._second_frames = 0
        self.load_peak = (0.0, 0.0)  # (percent, time)
        self._load_sum = 0.0
        self._load_seconds = 0
        self._hb_deadline = float("inf")  # earliest moment some heartbeat is overdue
        self.read_as_cia301: set[int] = set()  # nodes of unknown drive whose EMCYs said a fault
        self.shape_guessed: set[int] = set()  # nodes whose 2-byte EMCYs named their drive
        self._polling = PollingDetector()
        self.polling_events = 0
        self._table: list[Handler] = [self._other] * 0x800
        self._build_table()

    # ------------------------------------------------------------------ input

    def decode(self, frames: Iterable[tuple[float, int, bytes]]) -> Iterator[Event]:
        """Every event of `frames`, then those of the end of the log."""
        pending = self.pending
        feed = self.feed
        for time, can_id, data in frames:
            feed(time, can_id, data)
            if pending:
                yield from pending
                pending.clear()
        self.finish()
        yield from pending
        pending.clear()

    def feed(self, time: float, can_id: int, data: bytes) -> None:
        self.frame += 1
        if self._second is None:
            self.first_time = time
            self._second = float(int(time))
        elif time >= self._second + 1.0:
            self._close_seconds(time)
        self.last_time = time
        if len(data) > CLASSIC_MAX:
            # CAN FD: no CANopen service of CiA 301 fits, and its data-phase bitrate is not in
            # the log, so it is neither decoded nor in the bus load; the summary counts it
            self._count("fd")
            return
        self._bits += _FRAME_BITS[len(data)]
        self._second_frames += 1
        if time > self._hb_deadline:
            self._check_heartbeats(time)
        if can_id < 0x800:
            self._table[can_id](time, can_id, data)
        else:
            self._count("extended")

    def finish(self) -> None:
        """End of the log: open SDO transfers and the last second of bus load."""
        for node, info in sorted(self._nodes.items()):
            done = info.sdo.flush()
            if done is not None:
                self._sdo_done(self.last_time, node, done)
        if self._second is not None and self._second_frames:
            self._close_seconds(self._second + 1.0)  # the last second counts as a whole one

    @property
    def events_emitted(self) -> int:
        return self._seq

    def seen_nodes(self) -> list[int]:
        """Nodes that sent or were sent heartbeat, SDO or EMCY frames."""
        return sorted(self._nodes)

    # ------------------------------------------------------------------ dispatch

    def _build_table(self) -> None:
        table = self._table
        table[cob_id.NMT] = self._nmt
        table[cob_id.SYNC] = self._counter("sync")
        table[cob_id.TIME] = self._time
        for node in range(1, 128):
            table[cob_id.EMCY + node] = self._emcy
            table[cob_id.SDO_TX + node] = self._sdo_response
            table[cob_id.SDO_RX + node] = self._sdo_request
            table[cob_id.HEARTBEAT + node] = self._heartbeat
            for base in (*cob_id.TPDOS, *cob_id.RPDOS):
                table[base + node] = self._counter("pdo")
        # CiA 305 takes these two from the heartbeats of nodes 100 and 101
        table[cob_id.LSS_MASTER] = table[cob_id.LSS_SLAVE] = self._lss
        for cob in self.context.pdos:
            table[cob] = self._pdo

    def _counter(self, kind: str) -> Handler:
        counts = self.counts

        def count(_t: float, _id: int, _d: bytes) -> None:
            counts[kind] = counts.get(kind, 0) + 1

        return count

    def _count(self, kind: str) -> None:
        self.counts[kind] = self.counts.get(kind, 0) + 1

    def _other(self, _t: float, _id: int, _d: bytes) -> None:
        self._count("other")

    def _node(self, node: int) -> _Node:
        info = self._nodes.get(node)
        if info is None:
            info = self._nodes[node] = _Node()
        return info

    def emit(self, time: float, kind: EventKind, node: int | None, text: str, **extra: Any) -> None:
        self.pending.append(Event(self._seq, time, self.frame, kind.value, node, text, **extra))
        self._seq += 1

    def _say(self, kind: EventKind, line: str) -> None:
        self.summary.add(kind.value, line)

    def who(self, node: int) -> str:
        """ "node 1 (MDi-S1-C CAN servo)" once its profile is known, else "node 1"."""
        profile = self.context.nodes.get(node)
        return f"node {node} ({profile.label})" if profile and profile.data else f"node {node}"

    # ------------------------------------------------------------------ NMT and heartbeat

    def _nmt(self, time: float, _id: int, data: bytes) -> None:
        self._count("nmt")
        command = nmt.parse_command(bytes(data))
        if self.frames_mode and len(data) >= 2:
            self.emit(time, EventKind.FRAME, data[1] or None, "NMT", code=data[0])
        if command is None:
            return
        target = f"node {command.node_id}" if command.node_id else "all nodes"
        text = f"NMT {_COMMAND_WORDS[command.command]} → {target}"
        self.emit(time, EventKind.NMT, command.node_id or None, text, code=int(command.command))
        self._say(EventKind.NMT, f"{clock(time)} {text}")

    def _heartbeat(self, time: float, can_id: int, data: bytes) -> None:
        self._count("heartbeat")
        if not data:
            return  # a node-guarding request (RTR) from the master
        node = can_id - cob_id.HEARTBEAT
        info = self._node(node)
        state = data[0] & nmt.STATE_MASK
        if self.frames_mode:
            self.emit(time, EventKind.FRAME, node, "heartbeat", code=state)
        last = info.last_heartbeat
        if info.lost:
            info.lost = False
            gap = f" after {1e3 * (time - last):.0f} ms" if last is not None else ""
            text = f"{self.who(node)} heartbeat resumed{gap}"
            self.emit(time, EventKind.HEARTBEAT_RESUMED, node, text)
            self._say(EventKind.HEARTBEAT_RESUMED, f"{clock(time)} {text}")
        elif last is not None and state == info.state:
            interval = time - last
            if info.period is None:
                info.period = interval
            elif interval < 2 * info.period:  # a smoothed period; gaps do not count
                info.period += 0.2 * (interval - info.period)
        info.last_heartbeat = time
        if state != info.state:
            self._nmt_state(time, node, info, state)
        self._hb_deadline = min(self._hb_deadline, self._deadline(info))

    def _nmt_state(self, time: float, node: int, info: _Node, state: int) -> None:
        words = _STATE_WORDS.get(state, f"state {state:#04x}")  # type: ignore[call-overload]
        info.period = None  # a new state may come with another period (boot-up: none)
        if state == nmt.BOOT_UP:
            text = f"{self.who(node)} booted (boot-up frame)"
            self.emit(time, EventKind.BOOT_UP, node, text, code=state)
            self._say(EventKind.BOOT_UP, f"{clock(time)} {text}")
        else:
            before = _STATE_WORDS.get(info.state, "unknown") if info.state is not None else None  # type: ignore[call-overload]
            change = f"{before} → {words}" if before else words
            text = f"{self.who(node)} NMT state {change}"
            self.emit(time, EventKind.NMT_STATE, node, text, code=state)
            self._say(EventKind.NMT_STATE, f"{clock(time)} {text}")
        # a boot-up is the step into Pre-operational (CiA 301 §7.3.2.2.1)
        info.state = nmt.NmtState.PRE_OPERATIONAL if state == nmt.BOOT_UP else state

    @staticmethod
    def _deadline(info: _Node) -> float:
        if info.lost or info.period is None or info.last_heartbeat is None:
            return float("inf")
        return info.last_heartbeat + HEARTBEAT_LOSS_PERIODS * max(info.period, 1e-3)

    def _check_heartbeats(self, now: float) -> None:
        deadline = float("inf")
        for node, info in self._nodes.items():
            due = self._deadline(info)
            if now > due and info.last_heartbeat is not None and info.period is not None:
                info.lost = True
                stopped = info.last_heartbeat
                text = (
                    f"{self.who(node)} heartbeat stopped after {clock(stopped)}"
                    f" (period {1e3 * info.period:.0f} ms)"
                )
                self.emit(stopped + info.period, EventKind.HEARTBEAT_LOST, node, text)
                self._say(EventKind.HEARTBEAT_LOST, f"{clock(stopped + info.period)} {text}")
            else:
                deadline = min(deadline, due)
        self._hb_deadline = deadline

    # ------------------------------------------------------------------ LSS and TIME

    def _lss(self, time: float, can_id: int, data: bytes) -> None:
        self._count("lss")
        cs, text = lss_text(can_id, bytes(data))
        if self.frames_mode:
            self.emit(time, EventKind.FRAME, None, "LSS", code=cs)
        self.emit(time, EventKind.LSS, None, text, code=cs, data=data.hex(" ").upper() or None)
        if cs is not None and cs in _LSS_SAID:  # what changes a node: said in the summary
            self._say(EventKind.LSS, f"{clock(time)} {text}")

    def _time(self, time: float, _id: int, data: bytes) -> None:
        self._count("time")
        stamp = time_of_day(bytes(data))
        if stamp is None:
            text = f"TIME frame of {len(data)} bytes (TIME_OF_DAY has 6)"
            self.emit(time, EventKind.TIME, None, text, data=data.hex(" ").upper() or None)
            return
        if self.frames_mode:
            detail = json.dumps({"days": stamp.days, "ms": stamp.ms})
            self.emit(time, EventKind.FRAME, None, "TIME", data=detail)
        self.emit(time, EventKind.TIME, None, stamp.text(), code=stamp.days,
                  data=json.dumps({"days": stamp.days, "ms": stamp.ms}))  # fmt: skip

    # ------------------------------------------------------------------ EMCY

    def _emcy(self, time: float, can_id: int, data: bytes) -> None:
        self._count("emcy")
        node = can_id - cob_id.EMCY
        profile = self.context.node(node).data
        shape = ""
        guess = self.context.alarm_profile() if profile is None else None
        if guess is not None and len(data) == ALARM_EMCY_LENGTH:
            # CiA 301's EMCY has 8 bytes: 2 can only be an alarm-number drive (MDi-S1-C)
            profile = guess.data
            self.shape_guessed.add(node)
            shape = f" (2-byte EMCY: {guess.label} alarm number)"
        elif profile is None and len(data) >= 2 and int.from_bytes(data[:2], "little"):
            self.read_as_cia301.add(node)
        record = decode_emcy(profile, node, bytes(data), time=time)
        if self.frames_mode:
            register = json.dumps({"error_register": record.error_register})
            self.emit(time, EventKind.FRAME, node, "EMCY", code=record.code, data=register)
        words = fault_words(record, profile)
        detail = json.dumps(record.as_dict(), ensure_ascii=False)
        self.emit(time, EventKind.EMCY, node, f"{self.who(node)} EMCY: {words}{shape}",
                  code=record.code, data=detail)  # fmt: skip
        info = self._node(node)
        if record.code == 0:
            line = f"{clock(time)} {self.who(node)} cleared its faults (error reset EMCY)"
        else:
            line = f"{clock(time)} {self.who(node)} reported a fault: {words}{shape}"
            last = info.last_heartbeat
            if info.period and last is not None and time - last > 1.5 * info.period:
                line += f", {1e3 * (time - last):.0f} ms after its last heartbeat"
        self._say(EventKind.EMCY, line)

    # ------------------------------------------------------------------ SDO

    def _sdo_request(self, time: float, can_id: int, data: bytes) -> None:
        self._sdo(time, can_id - cob_id.SDO_RX, data, request=True)

    def _sdo_response(self, time: float, can_id: int, data: bytes) -> None:
        self._sdo(time, can_id - cob_id.SDO_TX, data, request=False)

    def _sdo(self, time: float, node: int, data: bytes, *, request: bool) -> None:
        self._count("sdo")
        channel = self._node(node).sdo
        feed = channel.request if request else channel.response
        done = feed(data, time, self.frame)
        if self.frames_mode:
            self._sdo_frame(time, node, channel, "request" if request else "response")
        if done is not None:
            self._sdo_done(time, node, done)

    def _sdo_frame(self, time: float, node: int, channel: SdoChannel, side: str) -> None:
        self.emit(time, EventKind.FRAME, node, f"SDO {side}", code=channel.cs,
                  index=channel.index, subindex=channel.subindex)  # fmt: skip

    def _sdo_done(self, time: float, node: int, done: SdoTransfer) -> None:
        ctx = self.context
        kind, text, value = transfer_text(ctx, node, done)
        text = f"{self.who(node)} {text}"
        polling = (
            kind is EventKind.SDO
            and done.upload
            and self._polling.read(time, node, done.index, done.subindex)
        )
        self.polling_events += polling
        self.emit(time, kind, node, text, index=done.index, subindex=done.subindex,
                  code=done.abort, data=done.data.hex(" ").upper() or None,
                  polling=polling)  # fmt: skip
        if kind is not EventKind.SDO:
            self._say(kind, f"{clock(time)} {text}")
            return
        if value is None:
            return
        label = ctx.identity_value(node, done.index, done.subindex, value)
        if label is not None:
            self.summary.add("identity", f"{clock(time)} node {node} identified as {label}")
        if done.index == STATUSWORD and done.subindex == 0:
            self._statusword(time, node, value)

    def _statusword(self, time: float, node: int, statusword: int) -> None:
        info = self._node(node)
        state = cia402_state_of(statusword)
        if state == info.cia402:
            return
        before, info.cia402 = info.cia402, state
        text = f"{self.who(node)} went to {state}" + (f" (from {before})" if before else "")
        self.emit(time, EventKind.CIA402_STATE, node, text, code=statusword)
        self._say(EventKind.CIA402_STATE, f"{clock(time)} {text}")

    # ------------------------------------------------------------------ PDO

    def _pdo(self, time: float, can_id: int, data: bytes) -> None:
        self._count("pdo")
        channel = self.context.pdos[can_id]
        try:
            decoded = channel.decoder.decode(bytes(data))
        except ValueError as error:
            self.emit(time, EventKind.PDO, channel.node, f"{channel.label}: {error}")
            return
        parts: list[str] = []
        values: dict[str, Any] = {}
        for item in decoded:
            words = value_text(item.index, item.subindex, item.value)
            name = item.name or f"{item.index:04X}:{item.subindex:02X}"
            parts.append(f"{name} = {words or item.value}")
            values[f"{item.index:04X}:{item.subindex:02X}"] = item.value
            if item.index == STATUSWORD and isinstance(item.value, int):
                self._statusword(time, channel.node, item.value)
        text = f"node {channel.node} {channel.label}: " + ", ".join(parts)
        self.emit(time, EventKind.PDO, channel.node, text, data=json.dumps(values))

    # ------------------------------------------------------------------ bus load

    def _close_seconds(self, time: float) -> None:
        """Emit the load of the finished second (seconds without frames are 0 % and quiet)."""
        assert self._second is not None
        start = self._second
        percent = 100.0 * self._bits / self.bitrate
        if percent > self.load_peak[0]:
            self.load_peak = (percent, start)
        self._load_sum += percent
        self._load_seconds += 1
        text = f"bus load {percent:.1f} % ({self._second_frames} frames)"
        self.emit(start, EventKind.BUS_LOAD, None, text, code=round(percent * 10))
        self._bits = 0
        self._second_frames = 0
        self._second = start + float(int(time - start))

    @property
    def load_mean(self) -> float:
        return self._load_sum / self._load_seconds if self._load_seconds else 0.0
