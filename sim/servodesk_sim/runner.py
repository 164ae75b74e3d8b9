"""Run simulated drives on a python-can bus: one worker thread, a fixed tick, taps and injection.

The drives are pure state machines (`SimNode`); this module is the only place where `Frame`s
become `can.Message`s and back. Everything a node does happens on the single worker thread, so
the nodes need no locks.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from types import TracebackType
from typing import ParamSpec, Protocol

import can

from servodesk_sim.frames import Frame

log = logging.getLogger(__name__)

Tap = Callable[[Frame, object | None], None]
P = ParamSpec("P")

# A tick later than this many periods is not caught up tick by tick: the schedule restarts
# from now and the miss is counted as an overrun (no burst of back-to-back polls).
RESYNC_AFTER_TICKS = 10
# At most this many queued frames are handed over before the next tick (a flood of frames
# must not starve the drives' timers; real controllers drop frames long before that).
DRAIN_MAX = 256
# The worker sleeps at least this long after a failed bus.recv so a dead bus cannot spin a core.
RECV_ERROR_PAUSE = 0.001
# bus.send waits at most this long for room in the TX queue: a full queue (nobody acknowledging
# on a real bus) drops frames instead of freezing every drive's clock.
SEND_TIMEOUT = 0.001
# How long a frame occupies the simulated wire: 500 kbit/s, 47 bits of frame around the data
# (bit stuffing left out). python-can's virtual bus stamps a frame when the sending thread gets
# to send it, so a busy interpreter spreads one burst of TPDOs over several SYNC periods, which
# a real adapter's hardware time stamps never show; a bus opened with `preserve_timestamps`
# (servodesk.bus.simulated) keeps the time a frame had on the wire instead: right after the
# frame it answers, back to back.
WIRE_BIT_S = 1 / 500_000
FRAME_OVERHEAD_BITS = 47


class SimNode(Protocol):
    """A simulated CANopen node: a pure state machine with explicit time (seconds, monotonic)."""

    @property
    def node_id(self) -> int: ...

    def boot(self, now: float) -> list[Frame]:
        """Power on: the boot-up frame and whatever else the node sends first."""
        ...

    def on_frame(self, frame: Frame, now: float) -> list[Frame]:
        """A frame seen on the bus (including other local nodes' frames, never its own)."""
        ...

    def poll(self, now: float) -> list[Frame]:
        """Called every tick: timers, heartbeats, the control loop."""
        ...


@dataclass
class SimBusStats:
    """Counters of one SimBus; read a snapshot through `SimBus.stats`."""

    ticks: int = 0
    overruns: int = 0  # resyncs after falling more than RESYNC_AFTER_TICKS behind
    max_lateness: float = 0.0  # s: worst delay of a poll behind its deadline
    frames_in: int = 0  # received from the bus
    frames_out: int = 0  # sent on the bus by the local nodes or on behalf of injectors
    frames_injected: int = 0
    frames_ignored: int = 0  # error frames, extended ids, CAN FD frames from the bus
    send_errors: int = 0
    recv_errors: int = 0
    node_errors: int = 0  # exceptions raised by a node (logged with their traceback)
    tap_errors: int = 0


@dataclass(frozen=True)
class TickResult:
    lateness: float  # s behind the deadline when the tick ran
    overrun: bool


class TickSchedule:
    """Absolute tick deadlines (no drift); resyncs after falling far behind.

    Pure: the caller passes the time, so the schedule is table-tested without a clock.
    """

    def __init__(self, tick: float, start: float, resync_after: int = RESYNC_AFTER_TICKS) -> None:
        if tick <= 0:
            raise ValueError(f"tick must be positive, got {tick}")
        self.tick = tick
        self.resync_after = resync_after
        self.deadline = start + tick

    def timeout(self, now: float) -> float:
        """Seconds until the next tick is due (0 when it is already due)."""
        return max(0.0, self.deadline - now)

    def take(self, now: float) -> TickResult | None:
        """The tick due at `now`, advancing the schedule; None while the deadline lies ahead."""
        if now < self.deadline:
            return None
        lateness = now - self.deadline
        if lateness > self.resync_after * self.tick:
            self.deadline = now + self.tick
            return TickResult(lateness, overrun=True)
        self.deadline += self.tick
        return TickResult(lateness, overrun=False)


def frame_to_message(frame: Frame) -> can.Message:
    """A Frame as python-can sends it: 11-bit id, and a remote frame keeps its DLC."""
    if frame.rtr:
        return can.Message(
            arbitration_id=frame.can_id,
            is_extended_id=False,
            is_remote_frame=True,
            dlc=frame.dlc,
        )
    return can.Message(arbitration_id=frame.can_id, is_extended_id=False, data=frame.data)


def message_to_frame(msg: can.Message) -> Frame | None:
    """The Frame a node sees, or None for what CANopen nodes here ignore (error/extended/FD)."""
    if msg.is_error_frame or msg.is_extended_id or msg.is_fd or msg.arbitration_id > 0x7FF:
        return None
    if msg.is_remote_frame:
        return Frame(msg.arbitration_id, b"", rtr=True, dlc=msg.dlc)
    data = bytes(msg.data)
    if len(data) > 8:
        return None
    return Frame(msg.arbitration_id, data)


class SimBus:
    """Simulated nodes sharing one python-can bus instance, run by one worker thread.

    Frames a node returns go on the bus, to every other local node (python-can buses do not
    hand an instance its own frames back) and to the taps.
    """

    def __init__(
        self,
        bus: can.BusABC,
        nodes: Sequence[SimNode],
        *,
        tick: float = 0.001,
        clock: Callable[[], float] = time.perf_counter,
    ) -> None:
        if tick <= 0:
            raise ValueError(f"tick must be positive, got {tick}")
        self.bus = bus
        self.nodes: tuple[SimNode, ...] = tuple(nodes)
        self.tick = tick
        self._clock = clock
        self._stats = SimBusStats()
        # Copy-on-write tuple: the worker iterates it without a lock while others add/remove.
        self._taps: tuple[tuple[Tap, object | None], ...] = ()
        self._taps_lock = threading.Lock()
        self._inject: queue.SimpleQueue[tuple[Frame, object | None]] = queue.SimpleQueue()
        self._stop = threading.Event()
        self._booted = threading.Event()
        self._thread: threading.Thread | None = None
        self._failure: BaseException | None = None
        self._recv_error_streak = 0
        self._wire = 0.0  # UNIX time at which the wire is free for this segment's next frame
        self._earliest = 0.0  # UNIX time the frames being sent now were made at

    # ------------------------------------------------------------------------ public API

    @property
    def stats(self) -> SimBusStats:
        """A copy of the counters (updated by the worker thread)."""
        return replace(self._stats)

    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    @property
    def failure(self) -> BaseException | None:
        """The unexpected exception that ended the worker thread, if any (it was logged)."""
        return self._failure

    def start(self) -> None:
        """Boot every node (boot frames are sent before this returns) and start the worker."""
        if self._thread is not None:
            raise RuntimeError("a SimBus can be started only once")
        self._thread = threading.Thread(target=self._run, name="servodesk-sim-bus", daemon=True)
        self._thread.start()
        # Booting happens on the worker so that every node call is on that one thread.
        self._booted.wait()
        if self._failure is not None:
            raise RuntimeError(
                "the simulated bus failed while booting its nodes"
            ) from self._failure

    def stop(self) -> None:
        """Stop the worker and wait for it; the bus stays open (the caller owns it)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()

    def __enter__(self) -> SimBus:
        if self._thread is None:
            self.start()
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()

    def add_tap(self, fn: Tap, *, origin: object | None = None) -> Callable[[], None]:
        """Call `fn(frame, origin)` for every frame on this segment; returns its remover.

        `fn` runs on the worker thread and must not block. A tap registered with an `origin`
        does not get the frames injected with that same origin (a client's own frames).
        """
        entry = (fn, origin)
        with self._taps_lock:
            self._taps = (*self._taps, entry)

        def remove() -> None:
            with self._taps_lock:
                self._taps = tuple(t for t in self._taps if t is not entry)

        return remove

    def inject(self, frame: Frame, origin: object | None = None) -> None:
        """Thread-safe: a frame from another client, for every node, the bus and the taps."""
        self._inject.put((frame, origin))

    # ------------------------------------------------------------------------ worker

    def _run(self) -> None:
        try:
            self._boot()
            self._booted.set()
            self._loop()
        except BaseException as exc:
            log.critical("simulated bus stopped by an unexpected error", exc_info=True)
            self._failure = exc
        finally:
            self._booted.set()

    def _boot(self) -> None:
        self._earliest = time.time()
        for node in self.nodes:
            self._emit(self._guarded(node, node.boot, self._clock()), node)

    def _loop(self) -> None:
        schedule = TickSchedule(self.tick, self._clock())
        while not self._stop.is_set():
            msg = self._recv(schedule.timeout(self._clock()))
            # A drive's CAN controller takes frames as they arrive: after a stall of this
            # thread, hand over everything queued before the timers run, or a heartbeat
            # waiting in the queue would count as missing (a false 8130h on a busy PC).
            drained = 0
            while msg is not None:
                self._on_message(msg)
                drained += 1
                msg = self._recv(0.0) if drained < DRAIN_MAX else None
            self._drain_injected()
            now = self._clock()
            result = schedule.take(now)
            if result is None:
                continue
            self._earliest = time.time()  # what the timers send goes out now
            stats = self._stats
            stats.ticks += 1
            stats.max_lateness = max(stats.max_lateness, result.lateness)
            if result.overrun:
                stats.overruns += 1
            for node in self.nodes:
                self._emit(self._guarded(node, node.poll, now), node)

    def _recv(self, timeout: float) -> can.Message | None:
        try:
            msg = self.bus.recv(timeout)
        except can.CanError:
            self._stats.recv_errors += 1
            self._recv_error_streak += 1
            if self._recv_error_streak == 1:
                log.exception("bus receive failed; the drives keep running")
            # Wait out the tick instead of spinning on a bus that fails at once.
            self._stop.wait(max(timeout, RECV_ERROR_PAUSE))
            return None
        if self._recv_error_streak:
            log.warning("bus receive works again after %d errors", self._recv_error_streak)
            self._recv_error_streak = 0
        return msg

    def _on_message(self, msg: can.Message) -> None:
        frame = message_to_frame(msg)
        if frame is None:
            self._stats.frames_ignored += 1
            return
        self._stats.frames_in += 1
        self._earliest = msg.timestamp  # the answers follow the frame on the wire
        self._tap(frame, self.bus)
        self._deliver(frame, exclude=None)

    def _drain_injected(self) -> None:
        while True:
            try:
                frame, origin = self._inject.get_nowait()
            except queue.Empty:
                return
            self._stats.frames_injected += 1
            self._earliest = time.time()
            self._send(frame)
            self._tap(frame, origin)
            self._deliver(frame, exclude=None)

    def _deliver(self, frame: Frame, exclude: SimNode | None) -> None:
        """Hand a frame to every local node except its sender, then emit their answers."""
        now = self._clock()
        for node in self.nodes:
            if node is not exclude:
                self._emit(self._guarded(node, node.on_frame, frame, now), node)

    def _emit(self, frames: list[Frame], sender: SimNode) -> None:
        """Frames of one node: bus, taps, other nodes; their answers follow in bus order."""
        pending: deque[tuple[Frame, SimNode]] = deque((f, sender) for f in frames)
        while pending:
            frame, origin = pending.popleft()
            self._send(frame)
            self._tap(frame, origin)
            now = self._clock()
            for node in self.nodes:
                if node is not origin:
                    answers = self._guarded(node, node.on_frame, frame, now)
                    pending.extend((f, node) for f in answers)

    def _guarded(
        self,
        node: SimNode,
        method: Callable[P, list[Frame]],
        *args: P.args,
        **kwargs: P.kwargs,
    ) -> list[Frame]:
        try:
            return method(*args, **kwargs)
        except Exception:
            # One faulty frame handler must not stop every other drive on the bus.
            self._stats.node_errors += 1
            log.exception("simulated node %d raised", node.node_id)
            return []

    def _send(self, frame: Frame) -> None:
        msg = frame_to_message(frame)
        # on the wire once it is made and the frame before it has gone
        msg.timestamp = max(self._wire, self._earliest)
        self._wire = msg.timestamp + (FRAME_OVERHEAD_BITS + 8 * len(frame.data)) * WIRE_BIT_S
        try:
            self.bus.send(msg, timeout=SEND_TIMEOUT)
        except can.CanError:
            self._stats.send_errors += 1
            log.warning("could not send %s", frame, exc_info=True)
            return
        self._stats.frames_out += 1

    def _tap(self, frame: Frame, origin: object | None) -> None:
        for fn, tap_origin in self._taps:
            if tap_origin is not None and tap_origin is origin:
                continue
            try:
                fn(frame, origin)
            except Exception:
                self._stats.tap_errors += 1
                log.exception("frame tap raised")


def build_drives(
    bus: can.BusABC, specs: Sequence[tuple[int, str]], *, bus_bitrate: int | None = None
) -> SimBus:
    """Simulated drives (node id, profile name) on `bus`, not yet powered on: `start()` boots
    them, so a listener that joins the bus first sees their boot-up frames."""
    from servodesk_sim.drive import create_drive  # the drives pull in the whole simulator

    nodes = [create_drive(node_id, profile, bus_bitrate=bus_bitrate) for node_id, profile in specs]
    return SimBus(bus, nodes)


def run_drives(
    bus: can.BusABC, specs: Sequence[tuple[int, str]], *, bus_bitrate: int | None = None
) -> SimBus:
    """Start simulated drives (node id, profile name) on `bus`; the caller stops the result."""
    sim = build_drives(bus, specs, bus_bitrate=bus_bitrate)
    sim.start()
    return sim
