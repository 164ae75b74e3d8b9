"""NodeSession.priority(): a stop jumps the queue and a transaction's gate, proven by the order
of the SDO requests that reach the simulated drive (never by time)."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Callable

import canopen
import pytest

from servodesk.errors import RequestInterruptedError
from servodesk.nodes.session import NodeSession
from servodesk.sdo.jobs import JobManager
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio

DEVICE_TYPE = (0x1000, 0)  # Device type
VENDOR = (0x1018, 1)  # Identity object: Vendor-ID
CONTROLWORD = (0x6040, 0)  # CiA 402 controlword


def objects(tap: SdoTap) -> list[tuple[int, int]]:
    """The (index, sub-index) of each SDO request seen, in order."""
    return [(int.from_bytes(f.data[1:3], "little"), f.data[3]) for f in tap.frames]


async def test_priority_runs_before_queued_reads(nodes: SimNodes) -> None:
    session = nodes.session(1)
    tap = SdoTap(nodes, 1)
    reads = [asyncio.create_task(session.upload(*DEVICE_TYPE)) for _ in range(20)]
    await asyncio.sleep(0)  # all twenty queued on the worker, the first one running
    await session.priority(lambda remote: remote.sdo.upload(*CONTROLWORD), what="stop")
    await asyncio.gather(*reads)
    tap.remove()
    seen = objects(tap)
    assert len(seen) == 21
    # at most the read in progress went first; the other 19 queued ones came after the stop
    assert seen.index(CONTROLWORD) <= 1


async def test_priority_passes_a_transaction(nodes: SimNodes) -> None:
    session = nodes.session(2)
    tap = SdoTap(nodes, 2)
    inside = asyncio.Event()
    release = asyncio.Event()

    async def transaction() -> str | None:
        async with session.exclusive(actor="dcf") as tx:
            await tx.upload(*DEVICE_TYPE)
            inside.set()
            await release.wait()  # the stop arrives between two steps
            await tx.upload(*VENDOR)
            return tx.interrupted

    running = asyncio.create_task(transaction())
    await inside.wait()
    queued = asyncio.create_task(session.upload(*DEVICE_TYPE))  # waits at the gate
    await session.priority(lambda remote: remote.sdo.upload(*CONTROLWORD), what="quick stop")
    release.set()
    interrupted = await running
    await queued
    tap.remove()
    assert objects(tap) == [DEVICE_TYPE, CONTROLWORD, VENDOR, DEVICE_TYPE]
    assert interrupted == "quick stop"


async def test_priority_passes_an_upload_all_and_queued_reads(nodes: SimNodes) -> None:
    """An upload-all job running and reads queued behind it: the stop is next after the
    chunk in progress, ahead of every queued read."""
    session = nodes.session(3)
    tap = SdoTap(nodes, 3)
    jobs = JobManager(nodes)
    job = jobs.start_upload_all(3)
    while not tap.frames:  # the job is reading
        await asyncio.sleep(0.001)
    reads = [asyncio.create_task(session.upload(*VENDOR)) for _ in range(20)]
    await asyncio.sleep(0)
    await session.priority(lambda remote: remote.sdo.upload(*CONTROLWORD), what="stop")
    await asyncio.gather(*reads)
    await jobs.cancel(job.id)
    tap.remove()
    seen = objects(tap)
    before = seen[: seen.index(CONTROLWORD)]
    # the job reads 1018h:01 once itself; none of the twenty queued reads went first
    assert before.count(VENDOR) <= 1
    assert seen.count(VENDOR) >= 20


PROFILE_VELOCITY = (0x6081, 0)  # Profile velocity (writable, moves nothing by itself)


def _held_call(
    first: Callable[[canopen.RemoteNode], None],
    then: Callable[[canopen.RemoteNode], None],
    started: threading.Event,
    go: threading.Event,
) -> Callable[[canopen.RemoteNode], None]:
    """A call on the worker that does `first`, waits until the test queued a stop, then `then`."""

    def call(remote: canopen.RemoteNode) -> None:
        first(remote)
        started.set()
        go.wait(5)
        then(remote)

    return call


async def _stop_while_held(
    session: NodeSession,
    first: Callable[[canopen.RemoteNode], None],
    then: Callable[[canopen.RemoteNode], None],
) -> tuple[asyncio.Task[None], asyncio.Task[object]]:
    started, go = threading.Event(), threading.Event()
    running = asyncio.create_task(
        session.run(_held_call(first, then, started, go), what="a long call")
    )
    await asyncio.to_thread(started.wait, 5)
    stop = asyncio.create_task(
        session.priority(lambda remote: remote.sdo.upload(*CONTROLWORD), what="quick stop")
    )
    await asyncio.sleep(0.01)  # queued in the urgent lane
    go.set()
    return running, stop


async def test_a_stop_cuts_into_a_long_read(nodes: SimNodes) -> None:
    """A call reading many entries (a state snapshot, a chunk of upload-all) lets a stop go
    between two of its reads instead of finishing first."""
    session = nodes.session(3)
    tap = SdoTap(nodes, 3)

    def more_reads(remote: canopen.RemoteNode) -> None:
        for _ in range(5):
            remote.sdo.upload(*VENDOR)

    running, stop = await _stop_while_held(
        session, lambda remote: remote.sdo.upload(*DEVICE_TYPE), more_reads
    )
    await asyncio.gather(running, stop)
    tap.remove()
    assert objects(tap) == [DEVICE_TYPE, CONTROLWORD] + [VENDOR] * 5


async def test_a_call_does_not_write_after_a_stop_cut_in(nodes: SimNodes) -> None:
    """What a call decided from reads made before a stop is not written after it: the call is
    refused at its first write, and nothing of it reaches the drive after the stop."""
    session = nodes.session(3)
    tap = SdoTap(nodes, 3)

    def read_then_write(remote: canopen.RemoteNode) -> None:
        value = remote.sdo.upload(*PROFILE_VELOCITY)
        remote.sdo.download(*PROFILE_VELOCITY, value)

    running, stop = await _stop_while_held(
        session, lambda remote: remote.sdo.upload(*DEVICE_TYPE), read_then_write
    )
    await stop
    with pytest.raises(RequestInterruptedError, match="before its first write"):
        await running
    tap.remove()
    assert objects(tap) == [DEVICE_TYPE, CONTROLWORD, PROFILE_VELOCITY]  # read, never written


async def test_a_call_that_wrote_runs_whole_before_the_stop(nodes: SimNodes) -> None:
    """A call that has written (a read-modify-write of a controlword, a PDO mapping) is one
    step: the stop comes after it, never in its middle."""
    session = nodes.session(3)
    tap = SdoTap(nodes, 3)

    def write(remote: canopen.RemoteNode) -> None:
        remote.sdo.download(*PROFILE_VELOCITY, remote.sdo.upload(*PROFILE_VELOCITY))

    running, stop = await _stop_while_held(
        session, write, lambda remote: remote.sdo.upload(*VENDOR)
    )
    await asyncio.gather(running, stop)
    tap.remove()
    assert objects(tap) == [PROFILE_VELOCITY, PROFILE_VELOCITY, VENDOR, CONTROLWORD]


PROFILE_ACCELERATION = (0x6083, 0)


async def test_a_command_goes_ahead_of_queued_reads_and_cuts_into_a_long_read(
    nodes: SimNodes,
) -> None:
    """A motion command (a jog's set-point) waits for no read: it goes between two reads of the
    call in progress and ahead of the reads queued before it; commands keep their order, and
    the long call's later write is not refused (a command decides nothing for it)."""
    session = nodes.session(3)
    tap = SdoTap(nodes, 3)
    started, go = threading.Event(), threading.Event()

    def long_read_then_write(remote: canopen.RemoteNode) -> None:
        remote.sdo.upload(*DEVICE_TYPE)
        started.set()
        go.wait(5)
        remote.sdo.upload(*VENDOR)
        remote.sdo.download(*PROFILE_VELOCITY, remote.sdo.upload(*PROFILE_VELOCITY))

    running = asyncio.create_task(session.run(long_read_then_write, what="a long call"))
    await asyncio.to_thread(started.wait, 5)
    reads = [asyncio.create_task(session.upload(*VENDOR)) for _ in range(3)]
    await asyncio.sleep(0)

    def command(index: tuple[int, int]) -> Callable[[canopen.RemoteNode], None]:
        return lambda remote: remote.sdo.download(*index, (1000).to_bytes(4, "little"))

    commands = [
        asyncio.create_task(session.run(command(PROFILE_ACCELERATION), what="6083h", command=True)),
        asyncio.create_task(session.run(command(PROFILE_VELOCITY), what="6081h", command=True)),
    ]
    await asyncio.sleep(0.01)  # both queued in the command lane
    go.set()
    await asyncio.gather(running, *reads, *commands)
    tap.remove()
    assert objects(tap) == [
        DEVICE_TYPE,
        PROFILE_ACCELERATION,  # between two reads of the long call, in the commands' order
        PROFILE_VELOCITY,
        VENDOR,
        PROFILE_VELOCITY,  # the long call's read and write, not refused
        PROFILE_VELOCITY,
        *[VENDOR] * 3,  # the reads queued before the commands
    ]


async def test_a_stop_goes_before_queued_commands(nodes: SimNodes) -> None:
    session = nodes.session(2)
    tap = SdoTap(nodes, 2)
    started, go = threading.Event(), threading.Event()

    def held(remote: canopen.RemoteNode) -> None:
        remote.sdo.download(*PROFILE_VELOCITY, remote.sdo.upload(*PROFILE_VELOCITY))
        started.set()
        go.wait(5)

    running = asyncio.create_task(session.run(held, what="a call that wrote"))
    await asyncio.to_thread(started.wait, 5)
    command = asyncio.create_task(
        session.run(lambda r: r.sdo.upload(*VENDOR), what="a command", command=True)
    )
    await asyncio.sleep(0)
    stop = asyncio.create_task(
        session.priority(lambda remote: remote.sdo.upload(*CONTROLWORD), what="quick stop")
    )
    await asyncio.sleep(0.01)
    go.set()
    await asyncio.gather(running, command, stop)
    tap.remove()
    assert objects(tap) == [PROFILE_VELOCITY, PROFILE_VELOCITY, CONTROLWORD, VENDOR]


@pytest.mark.parametrize("reading", [True, False])
async def test_a_command_passes_a_reading_transaction_only(nodes: SimNodes, reading: bool) -> None:
    """A transaction that only reads (every PDO's configuration as one picture) lets a jog's
    command through between its steps, not a read of another caller; a transaction that
    changes the node holds both back."""
    session = nodes.session(2)
    tap = SdoTap(nodes, 2)
    inside, release = asyncio.Event(), asyncio.Event()

    async def transaction() -> None:
        async with session.exclusive(reading=reading) as tx:
            await tx.upload(*DEVICE_TYPE)
            inside.set()
            await release.wait()
            await tx.upload(*VENDOR)

    running = asyncio.create_task(transaction())
    await inside.wait()
    read = asyncio.create_task(session.upload(*DEVICE_TYPE))
    command = asyncio.create_task(
        session.run(lambda r: r.sdo.upload(*PROFILE_VELOCITY), what="6081h", command=True)
    )
    await asyncio.sleep(0.05)  # what can go out goes now
    release.set()
    await asyncio.gather(running, read, command)
    tap.remove()
    if reading:
        assert objects(tap) == [DEVICE_TYPE, PROFILE_VELOCITY, VENDOR, DEVICE_TYPE]
    else:  # both waited for the transaction's end (their order after it is the worker's)
        assert objects(tap)[:2] == [DEVICE_TYPE, VENDOR]
        assert sorted(objects(tap)[2:]) == [DEVICE_TYPE, PROFILE_VELOCITY]
