"""Timing of the simulated drives while the tool works: a scope capture, browser polling, a jog.

For `--duration` seconds (default 20) the app runs, all at once:

- a free-running scope capture at a 1000 µs SYNC period (the tool produces SYNC, python-can's
  cyclic sender thread) of node 1's 6064h and 606Ch and node 2's 6064h (the scope adds each
  node's 6041h for its state lane): TPDOs 281h, 381h (node 1) and 282h (node 2) on every SYNC;
- what a browser on the Drive page polls, at the frontend's rates (frontend/src):
  GET /api/nodes/1/drive every 200 ms (useDrive POLL_MS, the poll that runs when no WebSocket
  push arrives), GET /api/nodes/1/drive/controller every 2 s (CONTROLLER_POLL_MS); and, at
  rates chosen here because no page polls them periodically, GET /api/scope/captures/{id}
  every 330 ms (like the PDO live check's capture poll), GET /api/nodes and GET /api/bus every
  1 s (the frontend fetches those on changes only);
- a PV jog on node 1 at 300 rpm (limit switches 5FF1h/5FF2h moved to ±1000 rev, enable, jog with
  keepalive_ms 500) kept alive with POST /api/jog/{id}/keepalive every 100 ms (holdToRun
  KEEPALIVE_INTERVAL_MS), stopped with DELETE at the end.

The browser load runs in its own process (a browser is one; its threads would otherwise take
the app's interpreter lock, which a real browser does not). Two configurations:

A. in-process, as `servodesk serve --sim` runs today: the app (uvicorn in a thread, as
   tests/live_server.py) starts the three simulated drives on a private virtual channel in its
   own process. A second virtual bus instance on that channel with a `can.Notifier` records SYNC
   as the tool sent it (virtual buses stamp at send); a runner tap records SYNC as the drives
   got it and their TPDOs. `--no-listener` takes the send times from the app's sent-frame hook
   instead, without the Notifier thread (which competes for the interpreter lock itself).
B. separate process: `servodesk-sim --node 1:mdi-s1c --node 2:kinco --node 3:cia402 --serve`
   (the CLI's main(), with a SIGUSR1 hook that prints the SimBus counters, so they are read
   over the window; the CLI's own summary covers its whole life), the app connected through
   python-can's socketcand client (`--tcp-tune`: with TCP_NODELAY). The drives booted before
   the app joined and send no heartbeat, so their NMT state is unknown to it and the scope
   would not start them (the capture then waits forever): a broadcast reset communication
   first lets the app see their boot-ups, as it does in-process. A second socketcand client,
   in its own process, records SYNC as the drives got it and their TPDOs (the server stamps
   frames on the drives' thread); the app's sent-frame hook records SYNC as the tool sent it.

Printed per configuration, over the capture's window: SYNC period error |period - 1 ms|
p50/p99/max and periods over 1.5 ms (as the tool sent it and as the drives got it), SYNC
delivery and SYNC -> last scope TPDO latency, cycles without all scope TPDOs before the next
SYNC (and TPDO answers missing altogether), the runner's ticks/overruns/worst lateness, the
capture's samples against the expected count, p50/p99/max latency of every route the browser
called, the app's warnings, CPU per process and of the whole machine (the bench shares it: a
busy machine shows in every number); then a verdict against bench/sim_realtime.py's target
(p99 period error <= 0.5 ms and no missed cycles: periods over 1.5 ms plus cycles without all
TPDOs, both as the drives got SYNC).

Run: `make bench` or `.venv/bin/python bench/sim_under_load.py [--duration 20] [--only A|B]
[--rounds N] [--no-listener] [--no-load] [--tcp-tune]`.
"""

from __future__ import annotations

import argparse
import bisect
import collections
import itertools
import json
import logging
import multiprocessing
import os
import queue
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import partial
from multiprocessing.context import SpawnProcess
from multiprocessing.queues import Queue
from multiprocessing.synchronize import Event as EventType
from pathlib import Path
from typing import TYPE_CHECKING, Any

import can
import httpx

if TYPE_CHECKING:
    from fastapi import FastAPI

    from servodesk.settings import Settings
    from servodesk_sim.frames import Frame
    from servodesk_sim.runner import SimBus, SimBusStats

PERIOD_US = 1000
SYNC_ID = 0x080
TARGET_P99_MS = 0.5
LATE_PERIOD_S = 1.5 * PERIOD_US / 1e6
SIGNALS = [
    {"node": 1, "index": 0x6064},  # position actual value
    {"node": 1, "index": 0x606C},  # velocity actual value
    {"node": 2, "index": 0x6064},
]
JOG_NODE = 1
CLIENT = {"X-Client-Id": "bench-under-load", "X-Client-Name": "sim_under_load bench"}
SIM_LIMITS = ((0x5FF1, -1000), (0x5FF2, 1000))  # simulated N-OT/P-OT positions, revolutions
COUNTS_PER_REV = 131072
JOG = {"mode": "pv", "velocity_rpm": 300, "keepalive_ms": 500}
KEEPALIVE_S = 0.100  # frontend holdToRun KEEPALIVE_INTERVAL_MS
POLLS: tuple[tuple[str, float], ...] = (  # route (capture id filled in), period s
    ("/api/nodes/1/drive", 0.200),
    ("/api/nodes/1/drive/controller", 2.0),
    ("/api/scope/captures/{id}", 0.330),
    ("/api/nodes", 1.0),
    ("/api/bus", 1.0),
)
SIM_DRIVES = ["--node", "1:mdi-s1c", "--node", "2:kinco", "--node", "3:cia402"]
SERVED_CHANNEL = "can0"
CLK_TCK = os.sysconf("SC_CLK_TCK")
# python-can's socketcand client warns of every frame split across two TCP reads
QUIET_LOGGER = "can.interfaces.socketcand.socketcand"

FrameLog = list[tuple[float, int]]  # (timestamp s, CAN id)


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def wait_port(port: int) -> None:
    for _ in range(400):
        with socket.socket() as sock:
            if sock.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.05)
    raise RuntimeError(f"nothing listens on {port}")


def kept(can_id: int) -> bool:
    """SYNC and PDOs: what the cycle analysis needs (the lists stay small)."""
    return can_id == SYNC_ID or 0x180 <= can_id < 0x580


def percentile(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    if len(values) == 1:
        return values[0]
    return statistics.quantiles(values, n=1000, method="inclusive")[int(q * 10) - 1]


def cpu_seconds(pid: int, tid: int | None = None) -> float:
    """utime + stime of a process (or one of its threads) from /proc."""
    path = f"/proc/{pid}/task/{tid}/stat" if tid is not None else f"/proc/{pid}/stat"
    try:
        fields = Path(path).read_text().rpartition(")")[2].split()
    except OSError:
        return float("nan")
    return (int(fields[11]) + int(fields[12])) / CLK_TCK


def machine_jiffies() -> tuple[int, int]:
    """(busy, total) CPU time of the whole machine from /proc/stat: the bench shares it."""
    values = [int(v) for v in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
    idle = values[3] + values[4]  # idle + iowait
    return sum(values) - idle, sum(values)


class AppLog(logging.Handler):
    """The app's warnings and errors (in this process), kept for the report, not interleaved."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.lines: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.lines.append(f"{record.name}: {record.getMessage()}"[:160])


# ---------------------------------------------------------------------- the browser (child)


_REPORT_LOCK = threading.Lock()


@dataclass
class LoadReport:
    latencies_ms: dict[str, list[float]] = field(default_factory=dict)
    errors: dict[str, int] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def _timed(
    report: LoadReport, label: str, send: Callable[[], httpx.Response], lock: threading.Lock
) -> httpx.Response | None:
    started = time.perf_counter()
    try:
        response = send()
    except httpx.HTTPError as exc:
        with lock:
            report.errors[label] = report.errors.get(label, 0) + 1
            report.notes.append(f"{label}: {type(exc).__name__}: {exc}")
        return None
    elapsed = (time.perf_counter() - started) * 1e3
    with lock:
        report.latencies_ms.setdefault(label, []).append(elapsed)
        if response.status_code >= 400:
            report.errors[label] = report.errors.get(label, 0) + 1
    return response


def _poller(base: str, path: str, period: float, halt: threading.Event, report: LoadReport) -> None:
    """GET `path` every `period` like setInterval: a tick that finds the last one still in
    flight is skipped (the Drive page's inFlight guard), no catch-up burst."""
    lock = _REPORT_LOCK
    label = f"GET {path}"
    with httpx.Client(base_url=base, timeout=10) as http:
        due = time.perf_counter()
        while not halt.is_set():
            _timed(report, label, lambda: http.get(path, headers=CLIENT), lock)
            due += period
            now = time.perf_counter()
            if now > due:
                due += period * ((now - due) // period + 1)
            halt.wait(due - now)


def _jog(base: str, halt: threading.Event, report: LoadReport) -> None:
    lock = _REPORT_LOCK
    node = JOG_NODE
    with httpx.Client(base_url=base, timeout=10) as http:

        def step(label: str, send: Callable[[], httpx.Response]) -> httpx.Response | None:
            response = _timed(report, label, send, lock)
            if response is not None and response.status_code >= 300:
                with lock:
                    report.notes.append(f"{label}: {response.status_code} {response.text[:200]}")
                return None
            return response

        for index, rev in SIM_LIMITS:
            path = f"/api/nodes/{node}/sdo/{index:04X}/0"
            body = {"value": rev * COUNTS_PER_REV}
            step(f"PUT {path}", partial(http.put, path, json=body))
        enable = f"/api/nodes/{node}/drive/enable"
        if step(f"POST {enable}", lambda: http.post(enable, headers=CLIENT)) is None:
            return
        start = f"/api/nodes/{node}/jog"
        answer = step(f"POST {start}", lambda: http.post(start, headers=CLIENT, json=JOG))
        if answer is None:
            return
        jog_id = answer.json()["jog_id"]
        keepalive = f"/api/jog/{jog_id}/keepalive"
        due = time.perf_counter()
        stopped = 0
        while not halt.is_set():
            response = _timed(
                report, "POST /api/jog/{id}/keepalive", lambda: http.post(keepalive), lock
            )
            if response is not None and response.status_code == 409 and not stopped:
                stopped += 1
                with lock:
                    report.notes.append(f"jog stopped early: {response.text[:200]}")
            due += KEEPALIVE_S
            now = time.perf_counter()
            if now > due:
                due += KEEPALIVE_S * ((now - due) // KEEPALIVE_S + 1)
            halt.wait(due - now)
        info = step(f"DELETE /api/jog/{jog_id}", lambda: http.delete(f"/api/jog/{jog_id}"))
        if info is not None and info.json().get("stop_reason") not in (None, "stopped by the user"):
            with lock:
                report.notes.append(f"jog stop reason: {info.json()['stop_reason']}")
        disable = f"/api/nodes/{node}/drive/disable"
        step(f"POST {disable}", lambda: http.post(disable, headers=CLIENT))
        control = f"/api/nodes/{node}/drive/controller"
        step(f"DELETE {control}", lambda: http.delete(control, headers=CLIENT))


def browser(base: str, up: Queue[Any], down: Queue[Any], stop: EventType) -> None:
    """Child process: waits for the capture id, then polls and jogs until `stop`."""
    up.put("ready")
    capture_id = down.get()
    report = LoadReport()
    if capture_id is None:
        up.put(report)
        return
    halt = threading.Event()
    threads = [
        threading.Thread(
            target=_poller,
            args=(base, path.format(id=capture_id), period, halt, report),
            daemon=True,
        )
        for path, period in POLLS
    ]
    threads.append(threading.Thread(target=_jog, args=(base, halt, report), daemon=True))
    for thread in threads:
        thread.start()
    stop.wait()
    halt.set()
    for thread in threads:
        thread.join(30)
    up.put(report)


# ---------------------------------------------------------------------- recorders


class BusSyncs(can.Listener):
    """SYNC with its bus timestamp, on a second virtual bus (virtual buses stamp at send)."""

    def __init__(self) -> None:
        self.times: list[float] = []

    def on_message_received(self, msg: can.Message) -> None:
        if msg.arbitration_id == SYNC_ID:
            self.times.append(msg.timestamp)


class SentSyncs(can.Listener):
    """The app's sent-frame hook (BusManager.add_frame_listener(sent=True)): SYNC as it left,
    on the sending thread; received frames pass by (is_rx)."""

    def __init__(self) -> None:
        self.times: list[float] = []

    def on_message_received(self, msg: can.Message) -> None:
        if not msg.is_rx and msg.arbitration_id == SYNC_ID:
            self.times.append(msg.timestamp)


def socketcand_recorder(port: int, ready: Queue[Any], out: Queue[Any], stop: EventType) -> None:
    """Child process: a second socketcand client; frames as the server stamped them."""
    logging.getLogger(QUIET_LOGGER).setLevel(logging.ERROR)
    bus = can.Bus(interface="socketcand", channel=SERVED_CHANNEL, host="127.0.0.1", port=port)
    log: FrameLog = []
    ready.put("ready")
    try:
        while not stop.is_set():
            msg = bus.recv(0.1)
            if msg is not None and kept(msg.arbitration_id):
                log.append((msg.timestamp, msg.arbitration_id))
    finally:
        bus.shutdown()
    out.put(log)


class Recorder:
    """Where one configuration gets SYNC as sent and frames as the drives saw them."""

    def start(self) -> None: ...

    def stop(self) -> tuple[list[float], FrameLog]:
        """(SYNC send times, drive-side SYNC and TPDO frames in the drives' order)."""
        raise NotImplementedError


class InProcessRecorder(Recorder):
    def __init__(self, app: FastAPI, sim: SimBus, channel: str, use_listener: bool) -> None:
        self.app, self.sim, self.channel, self.use_listener = app, sim, channel, use_listener
        self.listener = BusSyncs()
        self.sent = SentSyncs()
        self.drive: FrameLog = []
        self._removers: list[Callable[[], None]] = []
        self._bus: can.BusABC | None = None
        self._notifier: can.Notifier | None = None

    def _tap(self, frame: Frame, _origin: object | None) -> None:
        if kept(frame.can_id):
            self.drive.append((time.time(), frame.can_id))

    def start(self) -> None:
        if self.use_listener:
            self._bus = can.Bus(interface="virtual", channel=self.channel)
            self._notifier = can.Notifier(self._bus, [self.listener])
        else:
            manager = self.app.state.services.bus
            self._removers.append(manager.add_frame_listener(self.sent, sent=True))
        self._removers.append(self.sim.add_tap(self._tap))

    def stop(self) -> tuple[list[float], FrameLog]:
        for remove in self._removers:
            remove()
        if self._notifier is not None:
            self._notifier.stop()
        if self._bus is not None:
            self._bus.shutdown()
        return (self.listener.times if self.use_listener else self.sent.times), self.drive


class SocketcandRecorder(Recorder):
    def __init__(self, app: FastAPI, port: int) -> None:
        self.app, self.port = app, port
        self.sent = SentSyncs()
        self._remove: Callable[[], None] | None = None
        ctx = multiprocessing.get_context("spawn")
        self._ready: Queue[Any] = ctx.Queue()
        self._out: Queue[Any] = ctx.Queue()
        self._stop = ctx.Event()
        self.process: SpawnProcess = ctx.Process(
            target=socketcand_recorder,
            args=(port, self._ready, self._out, self._stop),
            daemon=True,
        )
        self.process.start()
        self._ready.get(timeout=60)
        time.sleep(0.3)  # the server forwards 0.25 s after a listen-only client's rawmode

    def start(self) -> None:
        self._remove = self.app.state.services.bus.add_frame_listener(self.sent, sent=True)

    def stop(self) -> tuple[list[float], FrameLog]:
        if self._remove is not None:
            self._remove()
        self._stop.set()
        drive: FrameLog = self._out.get(timeout=60)
        self.process.join(10)
        return self.sent.times, drive


# ---------------------------------------------------------------------- analysis


@dataclass
class Periods:
    cycles: int
    err_ms: list[float]
    over: int  # periods over 1.5 ms

    def line(self) -> str:
        worst = max(self.err_ms, default=float("nan"))
        return (
            f"period error ms p50 {percentile(self.err_ms, 50):.3f}  "
            f"p99 {percentile(self.err_ms, 99):.3f}  max {worst:.3f}"
            f"  | periods > 1.5 ms: {self.over}  (cycles {self.cycles})"
        )


def periods(times: list[float], window: tuple[float, float]) -> Periods:
    inside = [t for t in times if window[0] <= t <= window[1]]
    gaps = [b - a for a, b in itertools.pairwise(inside)]
    err = [abs(g - PERIOD_US / 1e6) * 1e3 for g in gaps]
    return Periods(len(gaps), err, sum(1 for g in gaps if g > LATE_PERIOD_S))


@dataclass
class Cycle:
    seen: float  # SYNC as the drives got it
    answers: dict[int, list[float]]  # scope TPDO COB-ID -> times, before the next SYNC


@dataclass
class CycleStats:
    periods: Periods
    incomplete: int  # cycles without every scope TPDO before the next SYNC
    unanswered: int  # scope TPDO answers missing altogether (SYNCs x TPDOs - TPDOs seen)
    per_cycle: collections.Counter[int]  # scope TPDOs per cycle: how many cycles


def drive_cycles(drive: FrameLog, cobs: set[int]) -> list[Cycle]:
    cycles: list[Cycle] = []
    for stamp, can_id in drive:
        if can_id == SYNC_ID:
            cycles.append(Cycle(stamp, {}))
        elif can_id in cobs and cycles:
            cycles[-1].answers.setdefault(can_id, []).append(stamp)
    return cycles


def cycle_stats(cycles: list[Cycle], cobs: set[int], window: tuple[float, float]) -> CycleStats:
    # a cycle counts when its SYNC lies in the window and a next SYNC closes it
    inside = [c for c, _ in itertools.pairwise(cycles) if window[0] <= c.seen <= window[1]]
    per_cycle: collections.Counter[int] = collections.Counter(
        sum(len(c.answers.get(cob, ())) for cob in cobs) for c in inside
    )
    incomplete = sum(1 for c in inside if not cobs <= c.answers.keys())
    answered = {cob: sum(len(c.answers.get(cob, ())) for c in inside) for cob in cobs}
    unanswered = sum(max(0, len(inside) - n) for n in answered.values())
    return CycleStats(periods([c.seen for c in cycles], window), incomplete, unanswered, per_cycle)


def pair_syncs(sent: list[float], seen: list[float]) -> tuple[list[int], str]:
    """For each drive-side SYNC the index of the sent SYNC it is. Both recordings start before
    the scope switches SYNC on, so they pair by position unless a frame was lost on the way;
    then each pairs with the last one sent before it (wrong when delivery took > 1 period)."""
    slack = 2e-6  # socketcand stamps carry whole microseconds
    if len(seen) <= len(sent) and all(s <= d + slack for s, d in zip(sent, seen, strict=False)):
        return list(range(len(seen))), ""
    index = [max(0, bisect.bisect_right(sent, d + slack) - 1) for d in seen]
    return index, (
        f" (sent {len(sent)} / seen {len(seen)} SYNCs do not pair by position: paired with the"
        " last one sent before)"
    )


# ---------------------------------------------------------------------- the app


@contextmanager
def serve_app(settings: Settings) -> Iterator[tuple[str, FastAPI]]:
    """The app on uvicorn in a thread (as tests/live_server.py), with its nodes scanned."""
    import uvicorn

    from servodesk.app import create_app

    app = create_app(settings, static_dir=None)
    config = uvicorn.Config(app, host="127.0.0.1", port=settings.port, log_level="warning")
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, name="live-server", daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            raise RuntimeError("the app did not start")
        time.sleep(0.05)
    base = f"http://127.0.0.1:{settings.port}"
    try:
        while True:
            nodes = {n["node"] for n in httpx.get(f"{base}/api/nodes", timeout=10).json()}
            if {1, 2, 3} <= nodes:
                break
            if time.monotonic() > deadline:
                raise RuntimeError(f"the start-up scan found nodes {sorted(nodes)}, not 1, 2, 3")
            time.sleep(0.1)
        yield base, app
    finally:
        server.should_exit = True
        thread.join(timeout=30)


# `servodesk-sim`'s own main() (what the console script runs, same arguments), with a SIGUSR1
# hook that prints the SimBus counters: the CLI prints them only when it stops.
SIM_WRAPPER = """
import dataclasses, json, signal, sys, threading
from servodesk_sim import cli
from servodesk_sim.runner import SimBus

buses = []

class Counted(SimBus):
    def start(self):
        super().start()
        buses.append(self)
        tid = [t.native_id for t in threading.enumerate() if t.name == "servodesk-sim-bus"]
        print("tid", tid[0], flush=True)

def report(signum, frame):
    print("stats", json.dumps(dataclasses.asdict(buses[0].stats)), flush=True)

cli.SimBus = Counted
signal.signal(signal.SIGUSR1, report)
sys.exit(cli.main(sys.argv[1:]))
"""


class SimProcess:
    """The drives in their own process, as `make sim` runs them (`--serve` on a free port)."""

    def __init__(self, port: int) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-c", SIM_WRAPPER, *SIM_DRIVES, "--serve", f"127.0.0.1:{port}"],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            bufsize=1,
        )
        self.output: list[str] = []
        self._lines: queue.SimpleQueue[str] = queue.SimpleQueue()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self.tid = int(self._expect("tid ", 60))
        wait_port(port)

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.output.append(line.rstrip())
            self._lines.put(line.rstrip())

    def _expect(self, prefix: str, timeout: float) -> str:
        deadline = time.monotonic() + timeout
        while True:
            line = self._lines.get(timeout=max(0.01, deadline - time.monotonic()))
            if line.startswith(prefix):
                return line[len(prefix) :]

    def stats(self) -> SimBusStats:
        from servodesk_sim.runner import SimBusStats

        self.proc.send_signal(signal.SIGUSR1)
        return SimBusStats(**json.loads(self._expect("stats ", 10)))

    def stop(self) -> str:
        """SIGINT as Ctrl+C; the CLI's own summary of the process's whole life."""
        self.proc.send_signal(signal.SIGINT)
        try:
            self.proc.wait(15)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(10)
        self._reader.join(5)
        return next((line for line in self.output if line.startswith("stopped:")), "no summary")


# ---------------------------------------------------------------------- one configuration


@dataclass
class Runner:
    """The SimBus's counters over the window (in-process) or its whole life (subprocess)."""

    text: str


@dataclass
class Outcome:
    name: str
    capture: dict[str, Any]
    samples_at_duration: int
    expected: int
    window: tuple[float, float]
    sent: list[float]
    drive: FrameLog
    load: LoadReport
    cpu: list[tuple[str, float]]  # label, CPU s over the window
    wall: float
    runner: Runner | None = None
    machine_busy: float = float("nan")  # share of all cores busy over the window (anyone's)
    app_log: list[str] = field(default_factory=list)


class Stack:
    """A running configuration: the app's URL, its recorder, what to measure CPU of."""

    def __init__(
        self, base: str, app: FastAPI, recorder: Recorder, stats: Callable[[], SimBusStats]
    ) -> None:
        self.base, self.app, self.recorder, self.stats = base, app, recorder, stats
        self.cpu_targets: list[tuple[str, int, int | None]] = []  # label, pid, tid


def start_capture(http: httpx.Client, duration: float) -> dict[str, Any]:
    body = {"signals": SIGNALS, "sync_period_us": PERIOD_US, "duration_s": duration}
    deadline = time.monotonic() + 15
    while True:
        response = http.post("/api/scope/captures", json=body)
        if response.status_code == 200:
            capture: dict[str, Any] = response.json()
            return capture
        if time.monotonic() > deadline:
            raise RuntimeError(f"the capture did not start: {response.status_code} {response.text}")
        time.sleep(0.5)


def exercise(stack: Stack, name: str, duration: float, with_load: bool) -> Outcome:
    ctx = multiprocessing.get_context("spawn")
    to_parent: Queue[Any] = ctx.Queue()
    to_child: Queue[Any] = ctx.Queue()
    stop = ctx.Event()
    child = ctx.Process(target=browser, args=(stack.base, to_parent, to_child, stop), daemon=True)
    cpu_targets = list(stack.cpu_targets)
    if with_load:
        child.start()
        to_parent.get(timeout=60)  # imported and waiting
        cpu_targets.append(("browser load (httpx)", child.pid or 0, None))
    http = httpx.Client(base_url=stack.base, timeout=30)
    stack.recorder.start()
    capture = start_capture(http, duration)
    # the window: from the running capture to its end
    cpu0 = [cpu_seconds(pid, tid) for _, pid, tid in cpu_targets]
    machine0 = machine_jiffies()
    stats0 = stack.stats()
    wall0 = time.monotonic()
    if with_load:
        to_child.put(capture["id"])
    url = f"/api/scope/captures/{capture['id']}"
    time.sleep(max(0.0, capture["started"] + duration - time.time()))
    samples_at_duration = http.get(url).json()["samples"]
    deadline = time.monotonic() + duration + 30
    while True:
        capture = http.get(url).json()
        if capture["state"] in ("done", "failed"):
            break
        if time.monotonic() > deadline:
            capture = http.delete(url).json()
            break
        time.sleep(0.25)
    wall = time.monotonic() - wall0
    cpu = [cpu_seconds(pid, tid) - c0 for (_, pid, tid), c0 in zip(cpu_targets, cpu0, strict=True)]
    machine1 = machine_jiffies()
    machine_busy = (machine1[0] - machine0[0]) / max(1, machine1[1] - machine0[1])
    runner = runner_window(stats0, stack.stats(), wall)
    load = LoadReport()
    if with_load:
        stop.set()
        load = to_parent.get(timeout=60)
        child.join(10)
    for _ in range(40):  # the scope puts SYNC back (off) after the capture
        if not http.get("/api/sync").json()["producing"]:
            break
        time.sleep(0.05)
    http.close()
    sent, drive = stack.recorder.stop()
    per_signal = round(duration * 1e6 / PERIOD_US)
    return Outcome(
        name=name,
        capture=capture,
        samples_at_duration=samples_at_duration,
        expected=per_signal * len(capture["signals"]),
        window=(capture["started"] + 0.1, capture["ended"]),
        sent=sent,
        drive=drive,
        load=load,
        cpu=[(label, c) for (label, _, _), c in zip(cpu_targets, cpu, strict=True)],
        wall=wall,
        runner=runner,
        machine_busy=machine_busy,
    )


def runner_window(before: SimBusStats, after: SimBusStats, wall: float) -> Runner:
    if after.max_lateness > before.max_lateness:
        worst = f"{after.max_lateness * 1e3:.1f} ms (in the window)"
    else:
        worst = f"<= {before.max_lateness * 1e3:.1f} ms (the start-up's worst was not exceeded)"
    return Runner(
        f"over the window: ticks {after.ticks - before.ticks} in {wall:.1f} s, "
        f"overruns {after.overruns - before.overruns} (since start {after.overruns}), "
        f"worst tick lateness {worst}; frames out {after.frames_out - before.frames_out}, "
        f"send errors {after.send_errors - before.send_errors}"
    )


def sim_thread_id() -> int | None:
    for thread in threading.enumerate():
        if thread.name == "servodesk-sim-bus":
            return thread.native_id
    return None


def run_in_process(duration: float, data_dir: Path, use_listener: bool, with_load: bool) -> Outcome:
    from servodesk.settings import Settings

    settings = Settings(simulated=True, scope_live_view=False, data_dir=data_dir, port=free_port())
    with serve_app(settings) as (base, app):
        manager = app.state.services.bus
        sim: SimBus = manager.sim
        channel: str = manager.status().channel
        recorder = InProcessRecorder(app, sim, channel, use_listener)
        stack = Stack(base, app, recorder, lambda: sim.stats)
        stack.cpu_targets = [
            ("app + drives process", os.getpid(), None),
            ("  of which the drives' thread", os.getpid(), sim_thread_id()),
        ]
        return exercise(
            stack, "A. drives in the app's process (servodesk serve --sim)", duration, with_load
        )


def boot_again(base: str) -> None:
    """The drives booted before the app joined their bus and send no heartbeat, so their NMT
    state is unknown to it, and the scope starts only pre-operational nodes: a broadcast reset
    communication lets the app see their boot-ups, as it does in-process."""
    with httpx.Client(base_url=base, timeout=10) as http:
        http.post("/api/nmt", json={"command": "reset-communication"}).raise_for_status()
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            states = {n["node"]: n["nmt_state"] for n in http.get("/api/nodes").json()}
            if all(states.get(node) == "pre-operational" for node in (1, 2, 3)):
                return
            time.sleep(0.1)
    raise RuntimeError(f"the drives did not boot again: {states}")


def run_separate(duration: float, data_dir: Path, with_load: bool, tcp_tune: bool) -> Outcome:
    from servodesk.settings import Settings

    port = free_port()
    sim = SimProcess(port)
    try:
        options: dict[str, Any] = {"host": "127.0.0.1", "port": port}
        if tcp_tune:
            options["tcp_tune"] = True
        settings = Settings(
            interface="socketcand",
            channel=SERVED_CHANNEL,
            bus_options=options,
            scope_live_view=False,
            data_dir=data_dir,
            port=free_port(),
        )
        with serve_app(settings) as (base, app):
            boot_again(base)
            recorder = SocketcandRecorder(app, port)
            stack = Stack(base, app, recorder, sim.stats)
            stack.cpu_targets = [
                ("app process", os.getpid(), None),
                ("drives process (servodesk-sim)", sim.proc.pid, None),
                ("  of which the drives' thread", sim.proc.pid, sim.tid),
                ("recorder (socketcand client)", recorder.process.pid or 0, None),
            ]
            name = "B. drives in their own process (servodesk-sim --serve)"
            if tcp_tune:
                name += ", app with tcp_tune"
            outcome = exercise(stack, name, duration, with_load)
    finally:
        summary = sim.stop()
    if outcome.runner is not None:
        outcome.runner.text += f"\n  the CLI's summary of the whole process: {summary}"
    return outcome


# ---------------------------------------------------------------------- report


def report(outcome: Outcome, with_load: bool) -> str:
    capture = outcome.capture
    signals = capture["signals"]
    cobs = {s["cob_id"] for s in signals if s["source"] == "pdo"}
    print(f"\n== {outcome.name} ==")
    names = ", ".join(
        f"{s['node']}:{s['index']:04X}h ({s['source']}"
        + (f" {s['cob_id']:03X}h)" if s["cob_id"] is not None else ")")
        for s in signals
    )
    ran = (capture["ended"] or 0) - capture["started"]
    print(f"capture {capture['id']}: {capture['state']}, signals {names}; ran {ran:.2f} s")
    window = outcome.window
    sent = periods(outcome.sent, window)
    cycles = drive_cycles(outcome.drive, cobs)
    stats = cycle_stats(cycles, cobs, window)
    print(f"SYNC as the tool sent it:    {sent.line()}")
    print(f"SYNC as the drives got it:   {stats.periods.line()}")
    seen = [c.seen for c in cycles]
    index, note = pair_syncs(outcome.sent, seen)
    delivery = [
        (d - outcome.sent[i]) * 1e3
        for d, i in zip(seen, index, strict=True)
        if window[0] <= d <= window[1]
    ]
    react = [
        (max(max(c.answers[cob]) for cob in cobs) - outcome.sent[i]) * 1e3
        for (c, _), i in zip(itertools.pairwise(cycles), index, strict=False)
        if window[0] <= c.seen <= window[1] and cobs <= c.answers.keys()
    ]
    print(
        f"SYNC sent -> drives got it ms: p50 {percentile(delivery, 50):.3f}  "
        f"p99 {percentile(delivery, 99):.3f}  max {max(delivery, default=float('nan')):.3f}{note}"
    )
    print(
        f"SYNC sent -> last scope TPDO ms: p50 {percentile(react, 50):.3f}  "
        f"p99 {percentile(react, 99):.3f}  max {max(react, default=float('nan')):.3f}"
    )
    print(
        f"cycles without all {len(cobs)} scope TPDOs before the next SYNC: {stats.incomplete}; "
        f"TPDO answers missing altogether: {stats.unanswered}"
    )
    if stats.incomplete:
        print(f"  scope TPDOs per cycle (count: cycles): {dict(sorted(stats.per_cycle.items()))}")
    if outcome.runner is not None:
        print(f"runner: {outcome.runner.text}")
    got = capture["samples"]
    print(
        f"capture samples: {outcome.samples_at_duration} of {outcome.expected} expected after "
        f"{capture['duration_s']:g} s ({100 * outcome.samples_at_duration / outcome.expected:.1f} "
        f"%, the app flushes every 33 ms); final {got} ({100 * got / outcome.expected:.1f} %), "
        f"lost {capture['lost']}"
    )
    for note_text in capture.get("notes", []):
        print(f"  capture note: {note_text}")
    if with_load:
        print("API latency ms (p50 / p99 / max, requests, errors):")
        for label, values in outcome.load.latencies_ms.items():
            errors = outcome.load.errors.get(label, 0)
            print(
                f"  {label:<42} {percentile(values, 50):7.1f} {percentile(values, 99):7.1f} "
                f"{max(values):7.1f}  n {len(values):4d}  errors {errors}"
            )
        for text in outcome.load.notes[:10]:
            print(f"  load note: {text}")
    cores = os.cpu_count() or 1
    shares = "; ".join(
        f"{label.strip()} {100 * c / outcome.wall:.0f} %" for label, c in outcome.cpu
    )
    if outcome.app_log:
        counts = collections.Counter(outcome.app_log)
        print(f"app log, warnings and errors (start to shut-down): {len(outcome.app_log)}")
        for text, n in counts.most_common(6):
            print(f"  {n} x {text}")
    print(f"CPU over {outcome.wall:.1f} s (% of one core, {cores} cores): {shares}")
    ours = sum(c for label, c in outcome.cpu if not label.startswith(" ")) / outcome.wall
    print(
        f"machine: {outcome.machine_busy * cores * 100:.0f} % of one core busy in all "
        f"(of {cores * 100} %), of which these processes {ours * 100:.0f} %"
    )
    p99 = percentile(stats.periods.err_ms, 99)
    missed = stats.periods.over + stats.incomplete
    met = p99 <= TARGET_P99_MS and missed == 0
    verdict = (
        f"verdict {outcome.name[:2]} p99 period error (drives' side) {p99:.3f} ms / target "
        f"{TARGET_P99_MS} ms: {p99 / TARGET_P99_MS:.2f}; missed cycles {missed} "
        f"({stats.periods.over} periods > 1.5 ms + {stats.incomplete} without all TPDOs) / "
        f"target 0 -> {'MET' if met else 'NOT MET'}"
    )
    return verdict


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=20.0, help="capture length, s")
    parser.add_argument("--only", choices=["A", "B"], help="run one configuration")
    parser.add_argument(
        "--rounds", type=int, default=1, help="run A and B alternately this many times"
    )
    parser.add_argument(
        "--no-listener",
        action="store_true",
        help="A: take SYNC send times from the app's sent-frame hook instead of a second "
        "virtual bus with its Notifier thread (which itself competes for the interpreter lock)",
    )
    parser.add_argument(
        "--no-load", action="store_true", help="the capture alone: no polling, no jog"
    )
    parser.add_argument(
        "--tcp-tune",
        action="store_true",
        help="B: connect the app with python-can's socketcand tcp_tune=True (TCP_NODELAY)",
    )
    args = parser.parse_args()
    logging.getLogger(QUIET_LOGGER).setLevel(logging.ERROR)
    app_log = AppLog()
    logging.getLogger().addHandler(app_log)
    with_load = not args.no_load
    print(
        f"duration {args.duration:g} s, SYNC {PERIOD_US} us, {os.cpu_count()} cores, "
        f"Python {sys.version.split()[0]}, switch interval {sys.getswitchinterval() * 1e3:g} ms"
    )
    if with_load:
        polls = ", ".join(f"{path} {period * 1e3:g} ms" for path, period in POLLS)
        print(f"browser load: {polls}; jog keep-alive {KEEPALIVE_S * 1e3:g} ms")
    else:
        print("browser load: none (--no-load)")
    verdicts = []
    with tempfile.TemporaryDirectory(prefix="servodesk-bench-load-") as tmp:
        for round_no in range(args.rounds):
            if args.only in (None, "A"):
                app_log.lines = []
                outcome = run_in_process(
                    args.duration, Path(tmp) / f"a{round_no}", not args.no_listener, with_load
                )
                outcome.app_log = app_log.lines
                verdicts.append(report(outcome, with_load))
            if args.only in (None, "B"):
                app_log.lines = []
                outcome = run_separate(
                    args.duration, Path(tmp) / f"b{round_no}", with_load, args.tcp_tune
                )
                outcome.app_log = app_log.lines
                verdicts.append(report(outcome, with_load))
    print()
    for line in verdicts:
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
