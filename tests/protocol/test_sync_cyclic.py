"""The tool's SYNC producer keeps time without bursts (bus/cyclic.py), scripted frame by frame.

The task's clock and sleep are replaced by a scripted clock: a sleep advances it by exactly what
was asked, plus a stall where the script says so. Each SYNC is recorded at the scripted time it
was sent, so the expected frames do not depend on the host's load.
"""

from __future__ import annotations

import itertools
import threading
from typing import Any, cast

import can
import canopen

from servodesk.bus.counters import BusCounters
from servodesk.bus.cyclic import CATCH_UP_S, SteadyCyclicSendTask
from servodesk.bus.monitored import MonitoredBus

SYNC = can.Message(arbitration_id=0x080, data=b"", is_extended_id=False)
PERIOD_NS = 10_000_000  # 10 ms
MS = 1_000_000


class ScriptedTime:
    """A clock in ns that moves only when the task sleeps or sends; `stalls[k]` ns are added to
    the sleep that follows frame k (the thread was not scheduled, or waited for the GIL), and
    `held[k]` ns pass inside the send of frame k before the frame leaves."""

    def __init__(self, stalls: dict[int, int], held: dict[int, int] | None = None) -> None:
        self.now = 1_000 * MS
        self.stalls = stalls
        self.held = held or {}
        self.frames = 0

    def clock(self) -> int:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += round(seconds * 1e9) + self.stalls.pop(self.frames - 1, 0)


class RecordingBus(can.BusABC):
    """Keeps (scripted time, frame) of each send; stops the task after `count` frames."""

    def __init__(self, time: ScriptedTime, count: int) -> None:
        super().__init__(channel="scripted")
        self.time = time
        self.count = count
        self.sent: list[tuple[int, can.Message]] = []
        self.task: SteadyCyclicSendTask | None = None

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        self.time.now += self.time.held.pop(self.time.frames, 0)
        self.sent.append((self.time.now, msg))
        self.time.frames += 1
        if len(self.sent) >= self.count and self.task is not None:
            self.task.stop()

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        return None, False


def run_scripted(
    stalls: dict[int, int], count: int, held: dict[int, int] | None = None
) -> list[int]:
    """Send times (ns from the first frame) of `count` SYNCs under the scripted stalls."""
    time = ScriptedTime(stalls, held)
    bus = RecordingBus(time, count)
    task = SteadyCyclicSendTask(
        bus,
        threading.Lock(),
        SYNC,
        PERIOD_NS / 1e9,
        autostart=False,
        clock=time.clock,
        sleep=time.sleep,
    )
    bus.task = task
    try:
        task.start()
        assert task.thread is not None
        task.thread.join(5)
        assert not task.thread.is_alive(), "the task did not stop"
    finally:
        task.stop()
        bus.shutdown()
    assert all(msg.arbitration_id == 0x080 and not msg.data for _, msg in bus.sent)
    first = bus.sent[0][0]
    return [at - first for at, _ in bus.sent]


def test_on_time_frames_keep_the_period() -> None:
    assert run_scripted({}, 5) == [k * PERIOD_NS for k in range(5)]


def test_a_short_stall_is_made_up_half_a_period_apart() -> None:
    """Held for 2 periods after SYNC 2: SYNC 3 goes when the thread runs again, the missed ones
    follow 5 ms apart until the schedule is met; python-can's own task would send them back to
    back. Every SYNC is sent: 9 in 80 ms as on time."""
    sent = [at // MS for at in run_scripted({2: 2 * PERIOD_NS}, 9)]
    assert sent == [0, 10, 20, 50, 55, 60, 65, 70, 80]
    intervals = [b - a for a, b in itertools.pairwise(sent)]
    assert min(intervals) >= PERIOD_NS // MS // 2  # never closer than half a period


def test_a_long_stall_is_not_made_up() -> None:
    """Held for 15 periods (beyond CATCH_UP_S = 100 ms): the late SYNC goes once, the next on
    the schedule; the drives have counted the SYNC lost meanwhile."""
    assert CATCH_UP_S < 0.15
    sent = [at // MS for at in run_scripted({2: 15 * PERIOD_NS}, 6)]
    assert sent == [0, 10, 20, 180, 190, 200]


def test_a_sync_held_inside_the_send_keeps_half_a_period_to_the_next() -> None:
    """The thread woke on time but SYNC 2 left only 7 ms later (held for the interpreter lock
    inside the send): SYNC 3 follows half a period after it, SYNC 4 is on time again."""
    sent = [at // MS for at in run_scripted({}, 5, held={2: 7 * MS})]
    assert sent == [0, 10, 27, 32, 40]


def test_a_little_late_sync_keeps_the_schedule() -> None:
    """Less than half a period late: the next SYNC is still due on the original schedule."""
    sent = run_scripted({1: 3 * MS}, 4)
    assert sent == [0, PERIOD_NS, 2 * PERIOD_NS + 3 * MS, 3 * PERIOD_NS]


def test_the_sync_producer_rides_on_the_steady_task_and_ends_with_the_bus() -> None:
    """canopen's SyncProducer on the tool's bus wrapper: frames 80h on the bus, sent by the
    steady task; closing the bus stops it."""
    channel = "servodesk-test-sync-cyclic"
    inner = can.Bus(interface="virtual", channel=channel)
    ear = can.Bus(interface="virtual", channel=channel)
    bus = MonitoredBus(inner, BusCounters(), lambda _: None)
    try:
        network = canopen.Network(bus)
        network.sync.start(0.002)
        # canopen's PeriodicMessageTask holds python-can's task
        task = cast(Any, network.sync)._task._task
        assert isinstance(task, SteadyCyclicSendTask)
        frame = ear.recv(2)
        assert frame is not None
        assert (frame.arbitration_id, bytes(frame.data)) == (0x080, b"")
        bus.shutdown()
        assert task.stopped
    finally:
        bus.shutdown()
        ear.shutdown()
