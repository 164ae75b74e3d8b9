"""The live scope's data path under load: TPDO frames replayed on a python-can `virtual` bus
through ServoDesk's pipeline and through the naive one people usually write.

ServoDesk's pipeline is the app's, piece for piece: the capture planned by `plan_node` and built
by `build_core` (2 nodes, TPDO1 + TPDO2 each, two INTEGER32 signals per frame: position and
velocity, actual and demand); the receiving bus opened as the app opens it (`open_link`:
MonitoredBus, canopen's listener, the frame counter) with a `FrameSink` added to its
`can.Notifier` (what BusManager.add_frame_listener does); the flush loop of
ScopeService._record (sleep FLUSH_S, then `CaptureRun.flush`: drain, `CaptureCore.process` on a
worker thread) writing a real `SamplesWriter` (samples.parquet) and a real `CaptureRecording`
(rerun, FileSink to a temporary .rrd, no live view). The naive pipeline is python-canopen's
`node.tpdo[n]` maps with `add_callback`, and one `rr.log(path, rr.Scalars(value))` per sample
after `rr.set_time("time", timestamp=…)`.

A sender thread sends pre-built `can.Message`s in a tight loop (paced for the latency run); it
holds back while more than BACKLOG frames wait, so the bus queue stays bounded and the receiving
side is what limits the rate: frames/s = frames whose samples are written / time from the first
send to the last write. Sender and receiver share one interpreter (one GIL), so the sender's own
cost (python-can's virtual bus copies every message) is in every rate; the bus-alone lines and
the CPU lines show how much, and the "frames queued beforehand" line shows the receiving side
without it. Prints:

- the bus alone: sender alone, Notifier + a no-op listener alone, both at once;
- ServoDesk's frames/s with zero loss (read back from samples.parquet) vs. ≥ 36,000 (4× a
  saturated 1 Mbit/s bus, 7,400–9,000 8-byte frames/s) and vs. ≥ 3× the naive pipeline's;
- frame-to-rerun latency p50/p99 (sent → its batch handed to `send_columns`) at 4 TPDOs ×
  1 kHz (4,000 frames/s), target p99 ≤ 100 ms;
- RSS at the start and the end of a `--duration` s capture at full rate, target growth ≤ 50 MB.

Not part of the test run. Run: `make bench` (60 s capture) or
`.venv/bin/python bench/scope_pipeline.py --duration 600` (the documented 10-minute run).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import tempfile
import threading
import time
import uuid
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import can
import canopen
import numpy as np
import numpy.typing as npt
import psutil  # type: ignore[import-untyped]  # no stubs installed; dev dependency
import rerun as rr
from canopen.objectdictionary import INTEGER32, ObjectDictionary, ODRecord, ODVariable
from canopen.pdo.base import PdoMap

from servodesk.bus.counters import BusCounters
from servodesk.bus.link import NOTIFIER_CYCLE, Link, close_link, open_link
from servodesk.models.scope import (
    MAX_DURATION_S,
    MIN_SYNC_PERIOD_US,
    Capture,
    CaptureRequest,
    CaptureSignal,
)
from servodesk.motion.units import DriveUnits
from servodesk.od import datatypes as dt
from servodesk.od.model import OdSub
from servodesk.pdo.bus_load import frame_bits
from servodesk.pdo.model import PdoConfig
from servodesk.scope.capture import Floats
from servodesk.scope.frames import FrameSink
from servodesk.scope.plan import plan_node
from servodesk.scope.recording import CaptureRecording
from servodesk.scope.run import FLUSH_S, CaptureOutput, CaptureRun, close_files
from servodesk.scope.samples import SamplesWriter, read_samples
from servodesk.scope.setup import Key, build_core, capture_signals
from servodesk.scope.signals import SignalInfo, signal_info
from servodesk_protocol.pdo import Direction, default_can_id

RATE_TARGET = 36_000.0  # frames/s: 4× a saturated 1 Mbit/s bus
NAIVE_TARGET = 3.0  # ours / the naive pipeline's frames/s
P99_TARGET_MS = 100.0
RSS_TARGET_MB = 50.0
BITRATE = 1_000_000
STUFF_BITS_8 = (34 + 64 - 1) // 4  # worst-case stuff bits of an 8-byte frame (bus_load.py)
NODES = (1, 2)
OBJECTS = (  # per node, in request order: two INTEGER32 per TPDO
    (0x6064, "position_actual"),
    (0x606C, "velocity_actual"),
    (0x6062, "position_demand"),
    (0x606B, "velocity_demand"),
)
SIGNALS_PER_FRAME = 2
CYCLES = 4096  # SYNC cycles of motion pre-built; the sender replays them round and round
SYNC_HZ = 1000  # the latency run: every TPDO at 1 kHz
BACKLOG = 20_000  # frames sent but not yet written: the sender holds back beyond this
CHUNK = 256  # frames the sender sends between two looks at the backlog
STALL_S = 3.0  # no progress for this long after the last send: the rest is lost
MB = 1024 * 1024
WINDOW_SAMPLES = 10**12  # per signal: the capture never ends by itself here


# ---------------------------------------------------------------------------------- the setup


@dataclass
class Scope:
    """A planned capture (as ScopePlanner.prepare makes it) and the frames its drives send."""

    signals: list[CaptureSignal]
    infos: dict[Key, SignalInfo]
    pdos: dict[int, tuple[PdoConfig, ...]]
    request: CaptureRequest
    messages: list[can.Message]  # CYCLES × the TPDOs, in bus order
    expected: list[npt.NDArray[np.int64]]  # per signal: its raw value in each cycle
    stream_of: list[int]  # per signal: its TPDO's position in a cycle

    @property
    def streams(self) -> int:
        return len(self.messages) // CYCLES


def motion(node: int, cycles: int) -> dict[int, npt.NDArray[np.float64]]:
    """A drive following a sine velocity profile (±3000 rpm at 0.5 Hz) with a following error
    and noise: every frame differs from the one before."""
    rng = np.random.default_rng(node)
    t = np.arange(cycles) / SYNC_HZ
    rpm = 3000.0 * np.sin(2 * np.pi * 0.5 * t + node)
    demand_uu_s = rpm / 60.0 * DriveUnits().user_units
    position_demand = np.cumsum(demand_uu_s) / SYNC_HZ
    return {
        0x6064: np.round(position_demand - demand_uu_s * 0.002 + rng.normal(0, 20, cycles)),
        0x606C: np.round(rpm + rng.normal(0, 3, cycles)),
        0x6062: np.round(position_demand),
        0x606B: np.round(demand_uu_s),
    }


def number_of(signals: Sequence[CaptureSignal], key: Key) -> int:
    return next(i for i, s in enumerate(signals) if (s.node, s.index, s.subindex) == key)


def plan_scope() -> Scope:
    units = DriveUnits()
    infos: dict[Key, SignalInfo] = {}
    plans = {}
    for node in NODES:
        node_infos = []
        for index, name in OBJECTS:
            sub = OdSub(index, 0, name, dt.DataType.INTEGER32, "ro", True)
            info = infos[(node, index, 0)] = signal_info(node, sub, units)
            node_infos.append(info)
        free = [  # TPDO1–4 not in use
            PdoConfig("tpdo", n, (default_can_id(Direction.TRANSMIT, n) or 0) + node, False, 255)
            for n in (1, 2, 3, 4)
        ]
        plans[node] = plan_node(
            node, node_infos, free, byte_granular=True, fixed_cob_ids=4, taken_ids={}
        )
    keys = tuple((node, index, 0) for node in NODES for index, _ in OBJECTS)
    signals = capture_signals(keys, plans, {})
    assert all(s.source == "pdo" for s in signals), [s.note for s in signals]
    # the longest capture at the shortest SYNC period: room for 7.2 M samples per signal
    request = CaptureRequest.model_validate(
        {
            "signals": [{"node": n, "index": i, "subindex": s} for n, i, s in keys],
            "sync_period_us": MIN_SYNC_PERIOD_US,
            "duration_s": MAX_DURATION_S,
        }
    )
    pdos = {node: plan.scope_pdos for node, plan in plans.items()}
    expected: list[npt.NDArray[np.int64]] = [np.empty(0, np.int64)] * len(keys)
    stream_of = [0] * len(keys)
    streams: list[tuple[int, list[npt.NDArray[np.int64]]]] = []
    for node in NODES:
        values = motion(node, CYCLES)
        for pdo in pdos[node]:
            columns = []
            for obj in pdo.mapping:
                assert obj.bits == 32
                number = number_of(signals, (node, obj.index, obj.subindex))
                expected[number] = values[obj.index].astype(np.int64)
                stream_of[number] = len(streams)
                columns.append(expected[number])
            streams.append((pdo.cob_id, columns))
    messages = [
        can.Message(
            arbitration_id=cob_id,
            data=b"".join(int(c[cycle]).to_bytes(4, "little", signed=True) for c in columns),
            is_extended_id=False,
        )
        for cycle in range(CYCLES)
        for cob_id, columns in streams
    ]
    return Scope(signals, infos, pdos, request, messages, expected, stream_of)


# ---------------------------------------------------------------------------------- the sender


class Sender(threading.Thread):
    """Sends the scope's frames round and round: `count` frames or until `stop`; at `rate`
    frames/s in SYNC-cycle bursts, or flat out while at most BACKLOG frames wait (`hold`)."""

    def __init__(
        self,
        bus: can.BusABC,
        scope: Scope,
        processed: Callable[[], int],
        *,
        count: int | None = None,
        rate: float | None = None,
        hold: bool = True,
    ) -> None:
        super().__init__(name="bench-sender", daemon=True)
        self.bus = bus
        self.messages = scope.messages
        self.burst = scope.streams
        self.processed = processed
        self.count = count
        self.rate = rate
        self.hold = hold
        self.stop = threading.Event()
        self.sent = 0
        self.first = 0.0  # epoch s of the first send
        self.held = 0.0  # s spent waiting for the receiving side
        self.peak_backlog = 0
        self.cpu = 0.0  # CPU s of this thread
        self.late: list[float] = []  # paced: s each burst went out after its due time
        self.finished = False

    def run(self) -> None:
        began = time.thread_time()
        try:
            if self.rate is None:
                self._flat_out()
            else:
                self._paced(self.rate)
        finally:
            self.cpu = time.thread_time() - began
            self.finished = True

    def _flat_out(self) -> None:
        send, messages, total = self.bus.send, self.messages, len(self.messages)
        self.first = time.time()
        position = 0
        while not self.stop.is_set():
            todo = CHUNK if self.count is None else min(CHUNK, self.count - self.sent)
            if todo <= 0:
                return
            end = position + todo
            if end <= total:
                for message in messages[position:end]:
                    send(message)
            else:
                for i in range(position, end):
                    send(messages[i % total])
            position = end % total
            self.sent += todo
            if not self.hold:
                continue
            backlog = self.sent - self.processed()
            self.peak_backlog = max(self.peak_backlog, backlog)
            if backlog > BACKLOG:
                began = time.perf_counter()
                while self.sent - self.processed() > BACKLOG // 2 and not self.stop.is_set():
                    time.sleep(0.002)
                self.held += time.perf_counter() - began

    def _paced(self, rate: float) -> None:
        send, messages, total = self.bus.send, self.messages, len(self.messages)
        start = time.perf_counter()
        self.first = time.time()
        while not self.stop.is_set() and (self.count is None or self.sent < self.count):
            due = start + self.sent / rate
            delay = due - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
            self.late.append(time.perf_counter() - due)
            for _ in range(self.burst):  # a SYNC: every TPDO at once
                send(messages[self.sent % total])
                self.sent += 1
            self.peak_backlog = max(self.peak_backlog, self.sent - self.processed())


# ---------------------------------------------------------------------------------- CPU shares


def process_cpu() -> float:
    times = psutil.Process().cpu_times()
    return float(times.user + times.system)


def notifier_cpu() -> float:
    """CPU s of the live can.Notifier thread (python-can names it `Notifier for bus …`)."""
    ids = {t.native_id for t in threading.enumerate() if t.name.startswith("Notifier for bus")}
    threads = psutil.Process().threads()
    return float(sum(t.user_time + t.system_time for t in threads if t.id in ids))


@dataclass
class Cpu:
    process: float = 0.0
    notifier: float = 0.0

    @classmethod
    def now(cls) -> Cpu:
        return cls(process_cpu(), notifier_cpu())


def cpu_line(label: str, before: Cpu, after: Cpu, sender: Sender, frames: int) -> str:
    total = after.process - before.process
    notifier = after.notifier - before.notifier
    rest = total - notifier - sender.cpu
    per = 1e6 / max(frames, 1)
    return (
        f"  CPU per frame ({label}): sender {sender.cpu * per:.1f} µs, Notifier thread (bus"
        f" recv + listeners) {notifier * per:.1f} µs, the rest (flush, writers, rerun threads)"
        f" {rest * per:.1f} µs; process {total:.1f} CPU s in {frames:,} frames"
    )


# ---------------------------------------------------------------------------------- the bus alone


class Counter(can.Listener):
    def __init__(self) -> None:
        self.count = 0

    def on_message_received(self, msg: can.Message) -> None:
        self.count += 1


@dataclass
class BusAlone:
    send: float  # frames/s of the sender, nobody reading
    receive: float  # Notifier + no-op listener draining frames queued beforehand
    both: float  # sender thread and Notifier at once


def bus_alone(scope: Scope, channel: str, frames: int) -> BusAlone:
    rx = can.Bus(interface="virtual", channel=channel)
    tx = can.Bus(interface="virtual", channel=channel)
    counter = Counter()
    try:
        sender = Sender(tx, scope, lambda: counter.count, count=frames, hold=False)
        sender.run()  # on this thread, into rx's queue: nobody reads it yet
        send_rate = frames / (time.time() - sender.first)
        began = time.time()
        notifier = can.Notifier(rx, [counter], NOTIFIER_CYCLE)
        wait_for(lambda: counter.count >= frames)
        receive_rate = frames / (time.time() - began)
        counter.count = 0
        sender = Sender(tx, scope, lambda: counter.count, count=frames)
        sender.start()
        sender.join()
        wait_for(lambda: counter.count >= frames)
        both = frames / (time.time() - sender.first)
        notifier.stop()
        return BusAlone(send_rate, receive_rate, both)
    finally:
        rx.shutdown()
        tx.shutdown()


def wait_for(condition: Callable[[], bool]) -> None:
    while not condition():
        time.sleep(0.0005)


# ---------------------------------------------------------------------------------- ServoDesk


class TimedRecording(CaptureRecording):
    """CaptureRecording that notes, per frame, how long after its send its batch was through
    `send_columns` (each TPDO's first signal stands for its frame)."""

    def __init__(self, capture: Capture, rrd_path: Path, firsts: set[int]) -> None:
        super().__init__(capture, rrd_path, None)
        self._numbers = {id(s): i for i, s in enumerate(capture.signals)}
        self._firsts = firsts
        self.timing = False
        self.latencies: list[Floats] = []
        self.chunks = 0  # batches handed to the recording (value and raw per signal and flush)

    def samples(
        self, signal: CaptureSignal, times: Floats, rel: Floats, raw: Floats, values: Floats
    ) -> None:
        super().samples(signal, times, rel, raw, values)
        self.chunks += 2
        if self.timing and self._numbers.get(id(signal)) in self._firsts:
            self.latencies.append(time.time() - times)


@dataclass
class Pipeline:
    """What ScopeService._begin builds, on a virtual bus of our own."""

    run: CaptureRun
    writer: SamplesWriter
    recording: TimedRecording
    sink: FrameSink
    raw: can.BusABC  # the receiving bus, opened (it queues) before the link reads it
    tx: can.BusABC
    folder: Path
    link: Link | None = None
    failures: list[str] = field(default_factory=list)  # the link's, from the Notifier thread
    slowest_flush: tuple[float, float] = (0.0, 0.0)  # (s, when: s after the first send)

    @property
    def samples_path(self) -> Path:
        return self.folder / "samples.parquet"

    @property
    def rrd_path(self) -> Path:
        return self.folder / "capture.rrd"

    def processed(self) -> int:
        return self.writer.rows // SIGNALS_PER_FRAME

    def listen(self) -> None:
        # the frame listeners BusManager.add_frame_listener keeps, as it opens a link
        self.link = open_link(self.raw, BusCounters(), [self.sink], self.failures.append)

    def close(self) -> None:
        if self.link is not None:
            close_link(self.link)
        else:
            self.raw.shutdown()
        self.tx.shutdown()
        close_files(self.run)


def servodesk_pipeline(scope: Scope, folder: Path, channel: str) -> Pipeline:
    folder.mkdir()
    capture = Capture(
        id=1,
        name="bench",
        state="running",
        created=time.time(),
        started=time.time(),
        signals=[s.model_copy(deep=True) for s in scope.signals],
        nodes=list(NODES),
        sync_period_us=scope.request.sync_period_us,
        duration_s=scope.request.duration_s,
        trigger=scope.request.trigger,
        samples=0,
        recording_id=str(uuid.uuid4()),
    )
    firsts = {
        number_of(capture.signals, (node, pdo.mapping[0].index, pdo.mapping[0].subindex))
        for node, pdos in scope.pdos.items()
        for pdo in pdos
    }
    recording = TimedRecording(capture, folder / "capture.rrd", firsts)
    writer = SamplesWriter(folder / "samples.parquet")
    output = CaptureOutput(capture, writer, recording)
    core = build_core(capture.signals, scope.infos, scope.pdos, scope.request, output)
    for track in core.tracks:
        # full rate is ~7× the fastest SYNC (2 kHz): the longest window a request can ask
        # for (7.2 M samples per signal) would end a 10-minute run early and drop the rest
        track.remaining = WINDOW_SAMPLES
    sink = FrameSink([cob for cob in core.streams if cob < 0x800])
    run = CaptureRun(capture, core, sink, output)
    raw = can.Bus(interface="virtual", channel=channel)
    tx = can.Bus(interface="virtual", channel=channel)
    return Pipeline(run, writer, recording, sink, raw, tx, folder)


async def record(pipeline: Pipeline, sender: Sender, tick: Callable[[], None] | None) -> float:
    """ScopeService._record's loop until every sent frame is written (or STALL_S without
    progress after the last send); returns the epoch s of the last write."""
    last_progress, done, written = time.monotonic(), -1, time.time()
    while True:
        await asyncio.sleep(FLUSH_S)
        began = time.perf_counter()
        await pipeline.run.flush()
        took = time.perf_counter() - began
        if took > pipeline.slowest_flush[0]:
            pipeline.slowest_flush = (took, time.time() - sender.first)
        if tick is not None:
            tick()
        processed = pipeline.processed()
        if processed != done:
            done, last_progress, written = processed, time.monotonic(), time.time()
        if sender.finished and processed >= sender.sent:
            return written
        if sender.finished and time.monotonic() - last_progress > STALL_S:
            return written


@dataclass
class Result:
    sent: int
    written: int  # frames whose samples are in the table
    rate: float
    held: float
    peak_backlog: int
    cpu: str
    late: list[float] = field(default_factory=list)  # the paced sender's lateness, s

    @property
    def lost(self) -> int:
        return self.sent - self.written


def replay(
    pipeline: Pipeline,
    scope: Scope,
    *,
    count: int | None = None,
    seconds: float | None = None,
    rate: float | None = None,
    queued: bool = False,
    tick: Callable[[], None] | None = None,
) -> Result:
    """Frames through the pipeline; `queued`: all `count` frames are on the bus before the
    pipeline starts reading (the receiving side alone)."""
    sender = Sender(pipeline.tx, scope, pipeline.processed, count=count, rate=rate, hold=not queued)
    if queued:
        sender.run()
        pipeline.listen()
        sender.first = time.time()
        sender.cpu = 0.0
    else:
        pipeline.listen()
    before = Cpu.now()
    if not queued:
        sender.start()
    timer = threading.Timer(seconds, sender.stop.set) if seconds is not None else None
    if timer is not None:
        timer.start()
    end = asyncio.run(record(pipeline, sender, tick))
    if not queued:
        sender.join()
    after = Cpu.now()
    if pipeline.failures:
        raise SystemExit(f"the receiving bus failed: {pipeline.failures[0]}")
    written = pipeline.processed()
    return Result(
        sent=sender.sent,
        written=written,
        rate=written / (end - sender.first),
        held=sender.held,
        peak_backlog=sender.peak_backlog,
        cpu=cpu_line("ServoDesk", before, after, sender, written),
        late=sender.late,
    )


def verify(scope: Scope, samples_path: Path, frames: int) -> tuple[int, int]:
    """samples.parquet read back against what was sent: (rows missing or extra, rows with
    another value). The j-th frame of a TPDO carries cycle j % CYCLES."""
    streams = scope.streams
    due = [frames // streams + (1 if k < frames % streams else 0) for k in range(streams)]
    seen = [0] * len(scope.signals)
    wrong = 0
    for batch in read_samples(samples_path, columns=["signal", "raw"]):
        signal = batch.column("signal").to_numpy()
        raw = batch.column("raw").to_numpy()
        for number in np.unique(signal).tolist():
            got = raw[signal == number]
            cycles = (seen[number] + np.arange(got.size)) % CYCLES
            wrong += int(np.count_nonzero(got != scope.expected[number][cycles]))
            seen[number] += got.size
    missing = sum(abs(n - due[scope.stream_of[i]]) for i, n in enumerate(seen))
    return missing, wrong


# ---------------------------------------------------------------------------------- the naive one


def naive_dictionary() -> ObjectDictionary:
    od = ObjectDictionary()  # type: ignore[no-untyped-call]
    for index, name in OBJECTS:
        variable = ODVariable(name, index)
        variable.data_type = INTEGER32
        od.add_object(variable)
    for n in range(4):  # python-canopen makes node.tpdo[n] from 1800h/1A00h
        od.add_object(ODRecord(f"TPDO{n + 1} communication parameter", 0x1800 + n))
        od.add_object(ODRecord(f"TPDO{n + 1} mapping parameter", 0x1A00 + n))
    return od


def naive(scope: Scope, folder: Path, channel: str, frames: int) -> Result:
    """canopen TPDO callbacks, one rr.log per sample: the usual way."""
    folder.mkdir()
    rr.init("servodesk-bench-naive", recording_id=str(uuid.uuid4()))
    rr.save(str(folder / "naive.rrd"))
    network = canopen.Network()
    network.connect(interface="virtual", channel=channel)
    done = [0]

    def on_tpdo(pdo: PdoMap) -> None:
        rr.set_time("time", timestamp=pdo.timestamp or 0.0)
        for variable in pdo.map:
            rr.log(f"drives/{(pdo.cob_id or 0) & 0x7F}/{variable.name}", rr.Scalars(variable.raw))
        done[0] += 1

    for node in NODES:
        remote = network.add_node(node, naive_dictionary())
        for config in scope.pdos[node]:
            tpdo = remote.tpdo[config.number]
            tpdo.clear()
            for obj in config.mapping:
                tpdo.add_variable(obj.index, obj.subindex, obj.bits)
            tpdo.cob_id = config.cob_id
            tpdo.trans_type = config.transmission_type
            tpdo.enabled = True
            tpdo.subscribe()
            tpdo.add_callback(on_tpdo)
    tx = can.Bus(interface="virtual", channel=channel)
    try:
        before = Cpu.now()
        sender = Sender(tx, scope, lambda: done[0], count=frames)
        sender.start()
        last, progress, end = -1, time.monotonic(), time.time()
        while True:
            time.sleep(0.001)
            if done[0] != last:
                last, progress, end = done[0], time.monotonic(), time.time()
            if sender.finished and done[0] >= sender.sent:
                break
            if sender.finished and time.monotonic() - progress > STALL_S:
                break
        sender.join()
        after = Cpu.now()
        return Result(
            sent=sender.sent,
            written=done[0],
            rate=done[0] / (end - sender.first),
            held=sender.held,
            peak_backlog=sender.peak_backlog,
            cpu=cpu_line("naive", before, after, sender, done[0]),
        )
    finally:
        network.disconnect()
        tx.shutdown()
        rr.disconnect()


# ---------------------------------------------------------------------------------- report


def verdict(ok: bool) -> str:
    return "PASS" if ok else "MISS"


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def rss_mb() -> float:
    return float(psutil.Process().memory_info().rss) / MB


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300_000, help="frames of a full-rate run")
    parser.add_argument(
        "--naive-frames", type=int, default=60_000, help="frames through the naive pipeline"
    )
    parser.add_argument("--latency-s", type=float, default=10.0, help="s of the 4 kHz run")
    parser.add_argument(
        "--duration", type=float, default=60.0, help="s of the full-rate capture (RSS)"
    )
    args = parser.parse_args()
    start_rss = rss_mb()
    base = f"servodesk-bench-scope-{os.getpid()}"  # virtual bus channels of this run only
    scope = plan_scope()
    slowest, fastest = BITRATE / frame_bits(8), BITRATE / (frame_bits(8) - STUFF_BITS_8)
    print(
        f"{scope.streams} TPDOs from {len(NODES)} nodes, {SIGNALS_PER_FRAME} INTEGER32 signals"
        f" per frame; a saturated 1 Mbit/s bus carries {slowest:,.0f}–{fastest:,.0f} 8-byte"
        " frames/s (worst-case to no bit stuffing)"
    )
    print(f"host: {os.cpu_count()} CPUs, load average {load()} (other processes share them)")
    alone = bus_alone(scope, f"{base}-alone", args.frames)
    print(
        f"bus alone (python-can virtual bus + Notifier, no-op listener): sender alone"
        f" {alone.send:,.0f} frames/s, Notifier alone (frames queued beforehand)"
        f" {alone.receive:,.0f} frames/s, both at once {alone.both:,.0f} frames/s"
    )

    with tempfile.TemporaryDirectory(prefix="servodesk-bench-scope-") as tmp:
        folder = Path(tmp)

        # 1. full rate, a fixed number of frames
        pipeline = servodesk_pipeline(scope, folder / "rate", f"{base}-rate")
        ours = replay(pipeline, scope, count=args.frames)
        began = time.perf_counter()
        pipeline.close()
        closing = time.perf_counter() - began
        missing, wrong = verify(scope, pipeline.samples_path, ours.sent)
        lossless = ours.lost == 0 and missing == 0 and wrong == 0
        print(
            f"ServoDesk pipeline: {ours.rate:,.0f} frames/s ({ours.written:,} of {ours.sent:,}"
            f" frames written, {ours.lost} lost; read back: {missing} rows missing, {wrong}"
            f" wrong; sender held back {ours.held:.1f} s; closing the files took"
            f" {closing:.2f} s more)"
        )
        print(ours.cpu)
        pipeline = servodesk_pipeline(scope, folder / "queued", f"{base}-queued")
        queued = replay(pipeline, scope, count=args.frames, queued=True)
        pipeline.close()
        print(
            f"  receiving side alone (all {queued.sent:,} frames queued beforehand):"
            f" {queued.rate:,.0f} frames/s, {queued.lost} lost"
        )
        print(
            f"  target ≥ {RATE_TARGET:,.0f} frames/s with zero loss: ratio"
            f" {ours.rate / RATE_TARGET:.2f} → {verdict(ours.rate >= RATE_TARGET and lossless)}"
            f" ({ours.rate / fastest:.1f}× a saturated bus)"
        )

        # 2. the naive pipeline, the same frames
        theirs = naive(scope, folder / "naive", f"{base}-naive", args.naive_frames)
        print(
            f"naive pipeline (canopen TPDO callbacks + rr.log per sample): {theirs.rate:,.0f}"
            f" frames/s ({theirs.written:,} of {theirs.sent:,} frames, {theirs.lost} lost only"
            f" because the virtual bus queues without limit: the backlog reached"
            f" {theirs.peak_backlog:,} frames = {theirs.peak_backlog / theirs.rate:.1f} s"
            f" behind, the sender held back {theirs.held:.1f} s)"
        )
        print(theirs.cpu)
        ratio = ours.rate / theirs.rate
        print(
            f"  ServoDesk / naive: {ratio:.1f}× (target ≥ {NAIVE_TARGET:g}×): ratio"
            f" {ratio / NAIVE_TARGET:.2f} → {verdict(ratio >= NAIVE_TARGET)}"
        )

        # 3. latency at a realistic rate
        pipeline = servodesk_pipeline(scope, folder / "latency", f"{base}-latency")
        pipeline.recording.timing = True
        rate = float(scope.streams * SYNC_HZ)
        paced = replay(pipeline, scope, seconds=args.latency_s, rate=rate)
        pipeline.close()
        ms = np.concatenate(pipeline.recording.latencies) * 1000
        p50, p99 = float(np.percentile(ms, 50)), float(np.percentile(ms, 99))
        flush_s, flush_at = pipeline.slowest_flush
        late = np.asarray(paced.late) * 1000
        print(
            f"latency at {scope.streams} TPDOs × {SYNC_HZ} Hz ({paced.rate:,.0f} frames/s,"
            f" {ms.size:,} frames, {paced.lost} lost), frame sent → its batch through"
            f" send_columns: p50 {p50:.1f} ms, p99 {p99:.1f} ms, max {ms.max():.1f} ms"
            f" (flush every {FLUSH_S * 1000:.0f} ms; slowest flush {flush_s * 1000:.0f} ms,"
            f" {flush_at:.1f} s in); .rrd {pipeline.rrd_path.stat().st_size / MB:.0f} MB"
            f" in {args.latency_s:.0f} s, {pipeline.recording.chunks:,} batches"
        )
        print(
            f"  host jitter: the paced sender woke p99 {np.percentile(late, 99):.1f} ms,"
            f" max {late.max():.1f} ms late; load average {load()}"
        )
        print(
            f"  p99 target ≤ {P99_TARGET_MS:.0f} ms: ratio {p99 / P99_TARGET_MS:.2f} →"
            f" {verdict(p99 <= P99_TARGET_MS)}"
        )

        # 4. a long capture at full rate: memory
        pipeline = servodesk_pipeline(scope, folder / "long", f"{base}-long")
        begin_rss = rss_mb()
        trail: list[tuple[float, float]] = []
        began = time.monotonic()
        step = max(args.duration / 10, 1.0)

        def tick() -> None:
            elapsed = time.monotonic() - began
            if not trail or elapsed - trail[-1][0] >= step:
                trail.append((elapsed, rss_mb()))

        long = replay(pipeline, scope, seconds=args.duration, tick=tick)
        end_rss = rss_mb()
        pipeline.close()
        parquet_mb = pipeline.samples_path.stat().st_size / MB
        rrd_mb = pipeline.rrd_path.stat().st_size / MB
        missing, wrong = verify(scope, pipeline.samples_path, long.sent)
        print(
            f"{args.duration:.0f} s capture at full rate: {long.rate:,.0f} frames/s,"
            f" {long.written:,} of {long.sent:,} frames written, {long.lost} lost (read back:"
            f" {missing} rows missing, {wrong} wrong); samples.parquet {parquet_mb:.0f} MB,"
            f" .rrd {rrd_mb:.0f} MB; slowest flush {pipeline.slowest_flush[0] * 1000:.0f} ms"
        )
        print(long.cpu)
        growth = end_rss - begin_rss
        over_time = ", ".join(f"{t:.0f} s {m:.0f}" for t, m in trail)
        chunks = pipeline.recording.chunks
        print(
            f"RSS: process start {start_rss:.0f} MB, capture start {begin_rss:.0f} MB, end"
            f" {end_rss:.0f} MB (MB during the capture: {over_time}); {chunks:,} batches to rerun"
            " sent"
        )
        if len(trail) >= 3:  # the trend after the first sample (start-up)
            t, m = np.array(trail[1:]).T
            print(f"  trend {float(np.polyfit(t, m, 1)[0]) * 60:+.1f} MB/min (linear fit)")
        print(
            f"  growth {growth:+.0f} MB, target ≤ {RSS_TARGET_MB:.0f} MB: ratio"
            f" {max(growth, 0.0) / RSS_TARGET_MB:.2f} → {verdict(growth <= RSS_TARGET_MB)}"
        )


if __name__ == "__main__":
    main()
