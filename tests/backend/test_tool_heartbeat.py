"""The tool's heartbeat keeps held drives alive while the event loop is busy, and stops when the
loop hangs, so the drives still stop themselves (motion/heartbeat.py)."""

from __future__ import annotations

import asyncio
import itertools
import threading
import time
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import can
import pytest

from servodesk.motion.safety import MotionSafety
from servodesk.motion.service import MotionService
from tests.backend.motion_rig import CIA402, NODES, motion_settings
from tests.backend.network_rig import Rig, sim_rig
from tests.backend.safety_rig import PAGE

pytestmark = pytest.mark.anyio

CONSUMER_MS = 300  # the default heartbeat consumer time
LIVENESS_MS = 500  # the default: the heartbeat is withheld from a loop silent this long
TOOL_HEARTBEAT = 0x700 + 127


class Ear:
    """Frames of the bus with the monotonic time they arrived, heard on a thread of its own
    (the loop is blocked on purpose in these tests)."""

    def __init__(self, channel: str) -> None:
        self._bus = can.Bus(interface="virtual", channel=channel)
        self.frames: list[tuple[float, can.Message]] = []
        self._run = True
        self._thread = threading.Thread(target=self._listen, daemon=True)
        self._thread.start()

    def _listen(self) -> None:
        while self._run:
            msg = self._bus.recv(timeout=0.05)
            if msg is not None:
                self.frames.append((time.monotonic(), msg))

    def times(self, can_id: int, since: float) -> list[float]:
        return [at for at, msg in list(self.frames) if msg.arbitration_id == can_id and at >= since]

    def faults(self, node: int, since: float) -> list[tuple[float, bytes]]:
        return [
            (at, bytes(msg.data))
            for at, msg in list(self.frames)
            if msg.arbitration_id == 0x80 + node and at >= since and msg.data[:2] != b"\0\0"
        ]

    def close(self) -> None:
        self._run = False
        self._thread.join()
        self._bus.shutdown()


@asynccontextmanager
async def held_drive() -> AsyncIterator[tuple[Rig, Ear, MotionSafety]]:
    """Node 3 controlled by a page, watching the tool's heartbeat with the default times."""
    settings = motion_settings().model_copy(
        update={"heartbeat_consumer_ms": CONSUMER_MS, "tool_heartbeat_liveness_ms": LIVENESS_MS}
    )
    async with sim_rig(settings=settings) as rig:
        await rig.registry.settled()
        for node in NODES:
            if not rig.registry.known(node):
                await rig.registry.add(node)
        safety = MotionSafety(
            MotionService(rig.registry, settings), rig.bus, rig.registry, settings
        )
        safety.start()
        ear = Ear(rig.channel)
        try:
            info = await safety.take(CIA402, PAGE, take_over=False)
            assert info.protection.active, info.protection.message
            yield rig, ear, safety
        finally:
            ear.close()
            await safety.close()


async def test_a_busy_loop_does_not_trip_a_held_drive() -> None:
    """The loop stalls longer than the drive's consumer time (a large upload, a busy host): the
    heartbeat goes on from its own thread and the drive does not fault."""
    async with held_drive() as (_, ear, _safety):
        start = time.monotonic()
        time.sleep(0.45)  # the loop does nothing else meanwhile
        await asyncio.sleep(0.4)  # it runs again; the drive's consumer time passes once more
        beats = [*ear.times(TOOL_HEARTBEAT, start), time.monotonic()]
        gaps = [b - a for a, b in itertools.pairwise(beats)]
        assert len(beats) >= 8, beats
        assert max(gaps) < CONSUMER_MS / 1000, gaps
        assert ear.faults(CIA402, start) == []


async def test_a_hung_loop_lets_the_held_drive_stop_itself() -> None:
    """A loop silent for longer than the liveness bound can stop no jog: the heartbeat stops,
    and the drive raises its heartbeat fault (8130h) by itself, within the bound plus its
    consumer time. When the loop runs again, so does the heartbeat."""
    async with held_drive() as (_, ear, _safety):
        start = time.monotonic()
        time.sleep(1.5)  # hung
        faults = ear.faults(CIA402, start)
        assert faults, "the drive did not stop by itself"
        at, data = faults[0]
        assert int.from_bytes(data[:2], "little") == 0x8130
        # the heartbeat stopped after the bound, and the drive noticed after its consumer time
        assert LIVENESS_MS / 1000 < at - start < (LIVENESS_MS + 100 + CONSUMER_MS + 300) / 1000
        last_beat = max(ear.times(TOOL_HEARTBEAT, start))
        assert last_beat - start < (LIVENESS_MS + 150) / 1000
        resumed = time.monotonic()
        for _ in range(40):
            if ear.times(TOOL_HEARTBEAT, resumed):
                break
            await asyncio.sleep(0.05)
        assert ear.times(TOOL_HEARTBEAT, resumed), "the heartbeat did not come back"


def sdo_requests(ear: Ear, node: int, since: float) -> list[tuple[int, int, int]]:
    """(command, index, sub-index) of each SDO request to `node` heard since `since`."""
    return [
        (msg.data[0], int.from_bytes(msg.data[1:3], "little"), msg.data[3])
        for at, msg in list(ear.frames)
        if msg.arbitration_id == 0x600 + node and at >= since
    ]


async def test_a_closed_page_releases_its_drive_ahead_of_queued_requests() -> None:
    """The controlling page's socket closes while the drive's queue is full (the page's own
    polls, an upload-all): the drive's 1016h entry is restored next, not after the queue."""
    async with held_drive() as (rig, ear, safety):
        session = rig.registry.session(CIA402)
        safety.socket_opened(PAGE.id)
        start = time.monotonic()
        reads = [asyncio.create_task(session.upload(0x1000, 0)) for _ in range(30)]
        await asyncio.sleep(0)  # queued
        safety.socket_closed(PAGE.id)
        await asyncio.gather(*reads)
        assert safety.controller(CIA402, PAGE).holder is None
        assert not safety.controller(CIA402, PAGE).protection.active
        requests = sdo_requests(ear, CIA402, start)
        restore = next(i for i, r in enumerate(requests) if r[1] == 0x1016 and r[0] & 0xE0 == 0x20)
        # ahead of the queue (behind it, it would be the 31st); the release task starts on the
        # loop's next turn, while the node's thread already reads
        assert restore < len(reads) // 2, requests
