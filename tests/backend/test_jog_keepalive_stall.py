"""The jog's keep-alive timer on a busy host: a stall of the server's loop past the deadline does
not stop an axis whose keep-alives all came in time (they wait unread in the socket until the
loop turns again), and an axis whose keep-alives really stopped still stops, the stall no
excuse. The watchdog on a real event loop with a real socket pair as the page's connection;
the loop is stalled the way a busy host stalls it, by a step that does not yield."""

from __future__ import annotations

import asyncio
import socket
import time
from pathlib import Path

import pytest

from servodesk.motion.jog import LISTEN_S, JogWatchdog
from servodesk.settings import Settings

KEEPALIVE_MS = 300


class AtRest:
    """The motion side the watchdog stops through: records each stop; the axis reads at rest."""

    def __init__(self) -> None:
        self.stops: list[str] = []

    async def stop(
        self,
        node: int,
        *,
        reason: str,
        quick: bool = False,
        deceleration_rpm_s: float | None = None,
        drive_deceleration: bool = False,
    ) -> str:
        self.stops.append(reason)
        return "stopping"

    async def velocity_rpm(self, node: int) -> float:
        return 0.0

    async def reading(self, node: int) -> tuple[float, float]:
        return 0.0, 0.0

    def travel(self, node: int) -> tuple[float | None, float | None]:
        return None, None


@pytest.fixture
def anyio_backend() -> str:
    return "asyncio"


@pytest.mark.anyio
async def test_a_stall_past_the_deadline_reads_the_keepalive_that_came_during_it(
    tmp_path: Path,
) -> None:
    motion = AtRest()
    watchdog = JogWatchdog(motion, Settings(simulated=True, data_dir=tmp_path))
    jog = watchdog.register(1, "pv", 100, KEEPALIVE_MS, "page", principal="local")
    loop = asyncio.get_running_loop()
    page, server = socket.socketpair()
    server.setblocking(False)
    received: asyncio.Queue[bytes] = asyncio.Queue()
    loop.add_reader(server, lambda: received.put_nowait(server.recv(64)))

    async def connection() -> None:
        """The page's socket handler: a keep-alive is handled a turn after it is read."""
        while await received.get():
            watchdog.keepalive(jog.jog_id, client_id="page", principal="local")

    handler = asyncio.create_task(connection())
    try:
        page.send(b"keepalive")  # in time, right after the start ...
        time.sleep(0.45)  # ... but the loop does not turn until 150 ms past the deadline
        await asyncio.sleep(0.02)
        assert watchdog.get(jog.jog_id).state == "running", motion.stops
        assert motion.stops == []

        # the page is gone for good: the next stall is no excuse
        time.sleep(0.45)
        await asyncio.sleep(LISTEN_S + 0.05)
        info = watchdog.get(jog.jog_id)
        assert info.state != "running"
        assert info.stop_reason == f"keep-alive missed for {KEEPALIVE_MS} ms"
        assert motion.stops == [info.stop_reason]
    finally:
        loop.remove_reader(server)
        handler.cancel()
        page.close()
        server.close()
        watchdog.stop_all("test over")
        await watchdog.settled()
