"""SimBus: simulated nodes on a python-can virtual bus, taps, injection, ticks, bus errors."""

from __future__ import annotations

import logging
import queue
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from typing import Any

import can
import pytest

from servodesk_sim.frames import Frame, frame
from servodesk_sim.runner import (
    SimBus,
    SimNode,
    TickResult,
    TickSchedule,
    frame_to_message,
    message_to_frame,
    run_drives,
)

WAIT = 2.0  # s: upper bound for anything to arrive; tests never assert how fast


class EchoNode:
    """Answers 0x600+id requests on 0x580+id with the same bytes; records what it saw."""

    def __init__(self, node_id: int) -> None:
        self._node_id = node_id
        self.seen: list[Frame] = []

    @property
    def node_id(self) -> int:
        return self._node_id

    def boot(self, now: float) -> list[Frame]:
        return [Frame(0x700 + self._node_id, b"\x00")]

    def on_frame(self, f: Frame, now: float) -> list[Frame]:
        self.seen.append(f)
        if f.can_id == 0x600 + self._node_id and not f.rtr:
            return [Frame(0x580 + self._node_id, f.data)]
        return []

    def poll(self, now: float) -> list[Frame]:
        return []


class PeriodicNode(EchoNode):
    """Counts polls and sends a heartbeat-like frame every `every` polls."""

    def __init__(self, node_id: int, every: int = 10) -> None:
        super().__init__(node_id)
        self.every = every
        self.poll_times: list[float] = []
        self.on_poll: Callable[[int], None] | None = None

    def poll(self, now: float) -> list[Frame]:
        self.poll_times.append(now)
        if self.on_poll is not None:
            self.on_poll(len(self.poll_times))
        if len(self.poll_times) % self.every == 0:
            return [Frame(0x700 + self.node_id, b"\x05")]
        return []


class PingNode(EchoNode):
    """Sends a ping at boot to node `peer` and records the peer's echo."""

    def __init__(self, node_id: int, peer: int) -> None:
        super().__init__(node_id)
        self.peer = peer

    def boot(self, now: float) -> list[Frame]:
        return [Frame(0x600 + self.peer, b"\x01\x02")]


class BrokenNode(EchoNode):
    def on_frame(self, f: Frame, now: float) -> list[Frame]:
        raise RuntimeError("bug in a node")


class FlakyBus(can.BusABC):
    """A bus whose recv/send fail on demand; frames to receive are queued by the test."""

    def __init__(self, recv_failures: int = 0) -> None:
        self.recv_failures = recv_failures
        self.fail_send_ids: set[int] = set()
        self.rx: queue.Queue[can.Message] = queue.Queue()
        self.sent: queue.Queue[can.Message] = queue.Queue()
        super().__init__(channel="flaky")

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        if self.recv_failures > 0:
            self.recv_failures -= 1
            raise can.CanOperationError("adapter unplugged")
        try:
            return self.rx.get(timeout=timeout), False
        except queue.Empty:
            return None, False

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        if msg.arbitration_id in self.fail_send_ids:
            raise can.CanOperationError("TX buffer full")
        self.sent.put(msg)


@pytest.fixture
def channel() -> str:
    return f"test-runner-{uuid.uuid4().hex}"


@pytest.fixture
def drive_bus(channel: str) -> Iterator[can.BusABC]:
    bus = can.Bus(interface="virtual", channel=channel)
    yield bus
    bus.shutdown()


@pytest.fixture
def master(channel: str) -> Iterator[can.BusABC]:
    """The other end of the virtual bus: what a CANopen master would see."""
    bus = can.Bus(interface="virtual", channel=channel)
    yield bus
    bus.shutdown()


@pytest.fixture
def make_sim(drive_bus: can.BusABC) -> Iterator[Callable[..., SimBus]]:
    """Build and start SimBuses; every one is stopped before the buses shut down."""
    sims: list[SimBus] = []

    def make(nodes: list[SimNode], bus: can.BusABC | None = None, **kwargs: Any) -> SimBus:
        sim = SimBus(bus if bus is not None else drive_bus, nodes, **kwargs)
        sims.append(sim)
        sim.start()
        return sim

    yield make
    for sim in sims:
        sim.stop()


def recv_frame(bus: can.BusABC, can_id: int, timeout: float = WAIT) -> can.Message:
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        msg = bus.recv(left)
        if msg is not None and msg.arbitration_id == can_id:
            return msg
    pytest.fail(f"no frame {can_id:03X} within {timeout} s")


def wait_for(condition: Callable[[], bool], timeout: float = WAIT) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail("condition not met in time")
        time.sleep(0.005)


def msg(can_id: int, hex_bytes: str = "") -> can.Message:
    return can.Message(arbitration_id=can_id, data=bytes.fromhex(hex_bytes), is_extended_id=False)


# --------------------------------------------------------------------------- pure parts


@pytest.mark.parametrize(
    ("times", "expected"),
    [
        # on time: one tick per period, lateness measured against the absolute deadline
        ([0.0005, 0.001, 0.0021], [None, TickResult(0.0, False), TickResult(0.0001, False)]),
        # a late tick does not shift the next deadline (no drift)
        ([0.0015, 0.002], [TickResult(0.0005, False), TickResult(0.0, False)]),
        # 5 ticks behind: caught up tick by tick
        ([0.006, 0.006], [TickResult(0.005, False), TickResult(0.004, False)]),
        # more than 10 ticks behind: resync from now and count an overrun
        ([0.0125, 0.013, 0.0136], [TickResult(0.0115, True), None, TickResult(0.0001, False)]),
    ],
)
def test_tick_schedule(times: list[float], expected: list[TickResult | None]) -> None:
    schedule = TickSchedule(0.001, start=0.0)
    results = [schedule.take(t) for t in times]
    rounded = [TickResult(round(r.lateness, 9), r.overrun) if r else None for r in results]
    assert rounded == expected


def test_tick_schedule_timeout_counts_down_to_the_deadline() -> None:
    schedule = TickSchedule(0.001, start=10.0)
    assert schedule.timeout(10.0004) == pytest.approx(0.0006)
    assert schedule.timeout(10.5) == 0.0


@pytest.mark.parametrize(
    ("f", "arbitration_id", "data", "remote", "dlc"),
    [
        (frame(0x604, "40 41 60 00"), 0x604, b"\x40\x41\x60\x00", False, 4),
        (Frame(0x080), 0x080, b"", False, 0),
        (Frame(0x704, rtr=True, dlc=1), 0x704, b"", True, 1),
    ],
)
def test_frame_to_message(
    f: Frame, arbitration_id: int, data: bytes, remote: bool, dlc: int
) -> None:
    m = frame_to_message(f)
    assert (m.arbitration_id, bytes(m.data), m.is_remote_frame, m.dlc, m.is_extended_id) == (
        arbitration_id,
        data,
        remote,
        dlc,
        False,
    )
    assert message_to_frame(m) == f


@pytest.mark.parametrize(
    "message",
    [
        can.Message(arbitration_id=0x704, is_error_frame=True, is_extended_id=False),
        can.Message(arbitration_id=0x604, data=b"\x40", is_extended_id=True),
        can.Message(arbitration_id=0x604, data=bytes(12), is_fd=True, is_extended_id=False),
    ],
    ids=["error-frame", "extended-id", "can-fd"],
)
def test_frames_nodes_cannot_see_are_dropped(message: can.Message) -> None:
    assert message_to_frame(message) is None


# --------------------------------------------------------------------------- on a bus


def test_boot_frames_are_on_the_bus_when_start_returns(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    make_sim([EchoNode(4), EchoNode(5)])
    # start() returned, so both boot-up frames are already queued for the master
    first, second = master.recv(0), master.recv(0)
    assert first is not None
    assert second is not None
    assert [(m.arbitration_id, bytes(m.data)) for m in (first, second)] == [
        (0x704, b"\x00"),
        (0x705, b"\x00"),
    ]


def test_a_request_from_the_bus_gets_the_nodes_answer(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    node = EchoNode(4)
    sim = make_sim([node])
    master.send(msg(0x604, "40 00 10 00 00 00 00 00"))
    answer = recv_frame(master, 0x584)
    assert bytes(answer.data) == bytes.fromhex("40 00 10 00 00 00 00 00")
    assert not answer.is_extended_id
    assert frame(0x604, "40 00 10 00 00 00 00 00") in node.seen
    assert sim.stats.frames_in == 1


def test_remote_frames_keep_their_dlc_both_ways(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    node = EchoNode(4)
    make_sim([node])
    master.send(
        can.Message(arbitration_id=0x704, is_remote_frame=True, dlc=1, is_extended_id=False)
    )
    wait_for(lambda: Frame(0x704, rtr=True, dlc=1) in node.seen)


def test_extended_and_error_frames_from_the_bus_do_not_reach_nodes(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    node = EchoNode(4)
    sim = make_sim([node])
    master.send(can.Message(arbitration_id=0x604, data=b"\x40", is_extended_id=True))
    master.send(msg(0x123, "01"))  # a marker that does arrive, after the ignored frame
    wait_for(lambda: frame(0x123, "01") in node.seen)
    assert node.seen == [frame(0x123, "01")]
    assert sim.stats.frames_ignored == 1


def test_local_nodes_hear_each_other_but_never_themselves(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    target = EchoNode(5)
    pinger = PingNode(4, peer=5)
    make_sim([target, pinger])
    # pinger's boot frame reached target inside the SimBus, target's echo reached pinger...
    assert frame(0x605, "01 02") in target.seen
    assert frame(0x585, "01 02") in pinger.seen
    # ...and both went on the bus in the order they happened
    ids = [recv_frame(master, i).arbitration_id for i in (0x705, 0x605, 0x585)]
    assert ids == [0x705, 0x605, 0x585]
    assert all(f.can_id != 0x705 for f in target.seen)
    assert all(f.can_id not in (0x704, 0x605) for f in pinger.seen)


def test_polls_happen_every_tick(make_sim: Callable[..., SimBus], master: can.BusABC) -> None:
    node = PeriodicNode(4, every=10)
    sim = make_sim([node])
    time.sleep(0.05)
    recv_frame(master, 0x704)  # the periodic frame, sent from poll()
    sim.stop()
    polls = len(node.poll_times)
    assert polls >= 5  # ~50 expected; only "it ticks" is asserted, not timing precision
    assert node.poll_times == sorted(node.poll_times)
    assert sim.stats.ticks == polls


def test_a_clock_jump_counts_an_overrun_and_resyncs(make_sim: Callable[..., SimBus]) -> None:
    offset = [0.0]
    node = PeriodicNode(4)

    def jump(polls: int) -> None:
        if polls == 3:
            offset[0] += 1.0  # the host froze for a second after the 3rd tick

    node.on_poll = jump
    sim = make_sim([node], clock=lambda: time.perf_counter() + offset[0])
    wait_for(lambda: len(node.poll_times) >= 8)
    sim.stop()
    stats = sim.stats
    assert stats.overruns == 1
    assert stats.max_lateness >= 0.99
    # resynced: no burst of 1000 catch-up polls right after the jump
    assert len(node.poll_times) < 500


def test_frames_queued_during_a_stall_are_all_heard_before_the_next_tick(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    """The worker stalls inside a tick while five frames arrive (heartbeats, say): the next
    tick runs only after the node heard all five, as a drive's CAN controller would have."""
    node = PeriodicNode(4, every=1_000_000)
    stalled, sent = threading.Event(), threading.Event()
    heard_at_poll: list[int] = []

    def stall(polls: int) -> None:
        heard_at_poll.append(len(node.seen))
        if polls == 3:
            stalled.set()
            sent.wait(WAIT)

    node.on_poll = stall
    sim = make_sim([node])
    assert stalled.wait(WAIT)
    for k in range(5):
        master.send(msg(0x77F, "05") if k else msg(0x123, "01"))
    time.sleep(0.05)  # the frames are in the worker's receive queue
    sent.set()
    wait_for(lambda: len(heard_at_poll) >= 4)
    sim.stop()
    assert heard_at_poll[3] - heard_at_poll[2] == 5, heard_at_poll


def test_taps_see_every_frame_with_its_origin(
    make_sim: Callable[..., SimBus], drive_bus: can.BusABC, master: can.BusABC
) -> None:
    node = EchoNode(4)
    seen: list[tuple[Frame, object | None]] = []
    sim = SimBus(drive_bus, [node])
    sim.add_tap(lambda f, origin: seen.append((f, origin)))
    with sim:
        client = object()
        sim.inject(frame(0x604, "01"), origin=client)
        wait_for(lambda: len(seen) >= 3)
        master.send(msg(0x604, "02"))
        wait_for(lambda: len(seen) >= 5)
    assert seen == [
        (frame(0x704, "00"), node),  # boot frame
        (frame(0x604, "01"), client),  # injected
        (frame(0x584, "01"), node),
        (frame(0x604, "02"), drive_bus),  # received from the bus
        (frame(0x584, "02"), node),
    ]


def test_inject_reaches_nodes_and_the_bus_but_not_the_injectors_own_tap(
    make_sim: Callable[..., SimBus], master: can.BusABC
) -> None:
    node = EchoNode(4)
    sim = make_sim([node])
    client_a, client_b = object(), object()
    got_a: list[Frame] = []
    got_b: list[Frame] = []
    sim.add_tap(lambda f, _o: got_a.append(f), origin=client_a)
    remove_b = sim.add_tap(lambda f, _o: got_b.append(f), origin=client_b)
    sim.inject(frame(0x604, "AA"), origin=client_a)
    assert bytes(recv_frame(master, 0x604).data) == b"\xaa"  # sent on the bus
    assert bytes(recv_frame(master, 0x584).data) == b"\xaa"  # the node answered it
    wait_for(lambda: len(got_b) >= 2)
    assert got_a == [frame(0x584, "AA")]  # the answer, but not its own request
    assert got_b == [frame(0x604, "AA"), frame(0x584, "AA")]
    remove_b()
    sim.inject(frame(0x604, "BB"), origin=client_a)
    wait_for(lambda: len(got_a) >= 2)
    assert got_b == [frame(0x604, "AA"), frame(0x584, "AA")]  # removed: nothing new


def test_inject_is_safe_from_many_threads(make_sim: Callable[..., SimBus]) -> None:
    node = EchoNode(6)
    sim = make_sim([node])

    def burst(k: int) -> None:
        for i in range(50):
            sim.inject(Frame(0x606, bytes([k, i])))

    threads = [threading.Thread(target=burst, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wait_for(lambda: sim.stats.frames_injected == 200)
    sim.stop()
    received = [f.data for f in node.seen if f.can_id == 0x606]
    assert len(received) == 200
    for k in range(4):  # each injector's frames arrive complete and in its order
        assert [d[1] for d in received if d[0] == k] == list(range(50))


def test_a_failing_node_is_logged_and_the_others_keep_working(
    make_sim: Callable[..., SimBus], master: can.BusABC, caplog: pytest.LogCaptureFixture
) -> None:
    with caplog.at_level(logging.ERROR, logger="servodesk_sim.runner"):
        sim = make_sim([BrokenNode(3), EchoNode(4)])
        master.send(msg(0x604, "11"))
        assert bytes(recv_frame(master, 0x584).data) == b"\x11"
    assert sim.stats.node_errors >= 1
    assert "simulated node 3 raised" in caplog.text
    assert sim.running


@pytest.fixture
def flaky_bus() -> Iterator[FlakyBus]:
    bus = FlakyBus(recv_failures=5)
    yield bus
    bus.shutdown()


def test_bus_errors_are_counted_logged_and_survived(
    make_sim: Callable[..., SimBus], flaky_bus: FlakyBus, caplog: pytest.LogCaptureFixture
) -> None:
    bus = flaky_bus
    bus.fail_send_ids.add(0x704)  # the boot frame cannot be sent
    node = EchoNode(4)
    with caplog.at_level(logging.WARNING, logger="servodesk_sim.runner"):
        sim = make_sim([node], bus=bus)
        bus.rx.put(msg(0x604, "22"))
        answer = bus.sent.get(timeout=WAIT)
    assert (answer.arbitration_id, bytes(answer.data)) == (0x584, b"\x22")
    stats = sim.stats
    assert (stats.recv_errors, stats.send_errors) == (5, 1)
    assert "bus receive failed" in caplog.text
    assert "could not send 704" in caplog.text
    assert sim.running
    sim.stop()
    assert not sim.running


def test_stop_ends_the_thread_and_leaves_the_bus_open(
    make_sim: Callable[..., SimBus], drive_bus: can.BusABC, master: can.BusABC
) -> None:
    node = PeriodicNode(4)
    sim = make_sim([node])
    wait_for(lambda: len(node.poll_times) > 0)
    sim.stop()
    polls = len(node.poll_times)
    time.sleep(0.02)
    assert not sim.running
    assert len(node.poll_times) == polls
    drive_bus.send(msg(0x123, "01"))  # the caller still owns a working bus
    assert bytes(recv_frame(master, 0x123).data) == b"\x01"


def test_start_twice_is_refused(make_sim: Callable[..., SimBus]) -> None:
    sim = make_sim([EchoNode(4)])
    with pytest.raises(RuntimeError, match="only once"):
        sim.start()


def test_context_manager_starts_and_stops(drive_bus: can.BusABC, master: can.BusABC) -> None:
    with SimBus(drive_bus, [EchoNode(4)]) as sim:
        assert sim.running
        assert recv_frame(master, 0x704).data == b"\x00"
    assert not sim.running


def test_run_drives_boots_real_drives(drive_bus: can.BusABC, master: can.BusABC) -> None:
    with run_drives(drive_bus, [(4, "mdi-s1c"), (5, "kinco"), (6, "cia402")]) as sim:
        assert sim.running
        boot = [recv_frame(master, 0x700 + node) for node in (4, 5, 6)]
        assert [bytes(m.data) for m in boot] == [b"\x00"] * 3  # CiA 301 boot-up
    assert not sim.running


class BurstNode(EchoNode):
    """Answers a SYNC with two 8-byte TPDOs, as a drive's synchronous TPDOs do."""

    def on_frame(self, f: Frame, now: float) -> list[Frame]:
        if f.can_id == 0x080:
            return [Frame(0x180 + self.node_id, bytes(8)), Frame(0x280 + self.node_id, bytes(8))]
        return super().on_frame(f, now)


def sent_frame(bus: FlakyBus, can_id: int) -> can.Message:
    deadline = time.monotonic() + WAIT
    while (left := deadline - time.monotonic()) > 0:
        try:
            msg = bus.sent.get(timeout=left)
        except queue.Empty:
            break
        if msg.arbitration_id == can_id:
            return msg
    pytest.fail(f"no frame {can_id:03X} sent within {WAIT} s")


def test_a_burst_keeps_its_time_on_the_wire_however_late_the_worker_takes_the_sync(
    make_sim: Callable[..., SimBus],
) -> None:
    """A real adapter stamps the TPDOs answering a SYNC right after it, back to back: the
    frames keep that time however late the worker thread got to the SYNC."""
    bus = FlakyBus()
    make_sim([BurstNode(5)], bus=bus)
    time.sleep(0.01)  # the boot-up is off the wire
    sync_at = time.time()
    time.sleep(0.05)  # the SYNC waited in the queue: the worker takes it 50 ms late
    bus.rx.put(can.Message(arbitration_id=0x080, is_extended_id=False, timestamp=sync_at))
    first, second = sent_frame(bus, 0x185), sent_frame(bus, 0x285)
    frame_time = (47 + 64) / 500_000  # an 8-byte frame at 500 kbit/s
    assert first.timestamp == pytest.approx(sync_at, abs=1e-9)
    assert second.timestamp == pytest.approx(sync_at + frame_time, abs=1e-9)


def test_what_the_timers_send_is_stamped_when_it_goes_out(make_sim: Callable[..., SimBus]) -> None:
    bus = FlakyBus()
    before = time.time()
    make_sim([PeriodicNode(6, every=5)], bus=bus)
    beat = sent_frame(bus, 0x706)
    assert before <= beat.timestamp <= time.time()
