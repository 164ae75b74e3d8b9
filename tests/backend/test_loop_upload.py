"""Short reads sent and answered on the event loop (nodes/loop_upload.py): the same bytes and
errors as canopen's upload on the node's thread, one transfer at a time with it, and canopen
again for what is not expedited. Proven on the bus of the simulated drives."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator

import canopen
import pytest

from servodesk.errors import CommTimeoutError, SdoAbortError
from servodesk.nodes.loop_upload import sends_without_blocking
from servodesk.nodes.session import NodeSession
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio

UPLOAD = 0x40
ABORT = 0x80
ENTRIES = [  # (node, index, sub): 1-, 2- and 4-byte entries of each drive
    (1, 0x1000, 0),
    (1, 0x1018, 1),
    (1, 0x2006, 8),
    (1, 0x6041, 0),
    (1, 0x6060, 0),
    (2, 0x1017, 0),
    (2, 0x6041, 0),
    (2, 0x6081, 0),
    (3, 0x1001, 0),
    (3, 0x6064, 0),
    (3, 0x6061, 0),
]


@pytest.fixture
def loop_nodes() -> Iterator[SimNodes]:
    with SimNodes(loop_reads=True) as access:
        yield access


def objects(tap: SdoTap) -> list[tuple[int, int, int]]:
    return [(f.data[0], int.from_bytes(f.data[1:3], "little"), f.data[3]) for f in tap.frames]


async def test_the_same_bytes_as_canopen(loop_nodes: SimNodes) -> None:
    for node, index, sub in ENTRIES:
        session = loop_nodes.session(node)
        tap = SdoTap(loop_nodes, node)
        on_loop = await session.upload(index, sub)
        tap.remove()
        by_canopen = await asyncio.to_thread(session.remote.sdo.upload, index, sub)
        assert on_loop == by_canopen, (node, hex(index), sub)
        assert objects(tap) == [(UPLOAD, index, sub)]  # one request, nothing else


async def test_an_abort_is_the_drives_own(loop_nodes: SimNodes) -> None:
    with pytest.raises(SdoAbortError) as refused:
        await loop_nodes.session(3).upload(0x6041, 7)  # no such sub-index
    assert (refused.value.code, refused.value.index, refused.value.subindex) == (
        0x06090011,
        0x6041,
        7,
    )


async def test_a_segmented_answer_goes_to_canopen(loop_nodes: SimNodes) -> None:
    """An entry the dictionary calls short but the drive sends in segments: the loop's request
    is aborted and canopen reads it whole."""
    session = loop_nodes.session(1)
    name = session.remote.object_dictionary.get_variable(0x1008, 0)  # device name, a string
    assert name is not None
    name.data_type = canopen.objectdictionary.UNSIGNED32  # as a wrong EDS would say
    tap = SdoTap(loop_nodes, 1)
    data = await session.upload(0x1008, 0)
    tap.remove()
    seen = objects(tap)
    assert seen[:3] == [(UPLOAD, 0x1008, 0), (ABORT, 0x1008, 0), (UPLOAD, 0x1008, 0)]
    assert len(seen) > 3  # canopen's segments
    # what canopen makes of it for that dictionary (it cuts the string to the 4 bytes)
    assert data == await asyncio.to_thread(session.remote.sdo.upload, 0x1008, 0) == b"DVS_"


async def test_a_read_waits_for_the_call_in_progress(loop_nodes: SimNodes) -> None:
    session = loop_nodes.session(2)
    tap = SdoTap(loop_nodes, 2)
    started, go = threading.Event(), threading.Event()

    def long_call(remote: canopen.RemoteNode) -> None:
        remote.sdo.upload(0x1000, 0)
        started.set()
        go.wait(5)
        remote.sdo.upload(0x1018, 1)

    running = asyncio.create_task(session.run(long_call, what="a long call"))
    await asyncio.to_thread(started.wait, 5)
    read = asyncio.create_task(session.upload(0x6041, 0))
    await asyncio.sleep(0.02)
    go.set()
    await asyncio.gather(running, read)
    tap.remove()
    assert [o[1:] for o in objects(tap)] == [(0x1000, 0), (0x1018, 1), (0x6041, 0)]


async def test_a_stop_goes_after_the_read_on_the_loop(loop_nodes: SimNodes) -> None:
    session = loop_nodes.session(3)
    tap = SdoTap(loop_nodes, 3)
    read = asyncio.create_task(session.upload(0x6064, 0))
    await asyncio.sleep(0)  # the request is out; the worker is held until its answer
    stop = asyncio.create_task(
        session.priority(lambda remote: remote.sdo.upload(0x6040, 0), what="quick stop")
    )
    await asyncio.gather(read, stop)
    tap.remove()
    assert [o[1:] for o in objects(tap)] == [(0x6064, 0), (0x6040, 0)]


async def test_a_node_that_does_not_answer_times_out(loop_nodes: SimNodes) -> None:
    """Node 5 is not on the bus: the read says so after the SDO timeout, not sooner or never."""
    od = loop_nodes.session(1).remote.object_dictionary
    remote = canopen.RemoteNode(5, od)
    loop_nodes.network.add_node(remote)
    ghost = NodeSession(remote, sdo_timeout=0.05, loop_reads=True)
    try:
        for _ in range(2):  # the second through the node's thread, after waiting out the first
            with pytest.raises(CommTimeoutError) as silent:
                await ghost.upload(0x6041, 0)
            assert "node 5" in str(silent.value)
    finally:
        ghost.close()


def test_only_buses_that_never_block_send_from_the_loop(loop_nodes: SimNodes) -> None:
    assert sends_without_blocking(loop_nodes.network.bus)  # python-can's virtual bus
    assert not sends_without_blocking(None)
