"""NodeSession.exclusive(): a multi-step change runs with nothing from other callers in between,
proven by the order of the SDO requests that reach the simulated drive."""

from __future__ import annotations

import asyncio

import pytest

from servodesk.errors import RequestInterruptedError
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio

DEVICE_TYPE = (0x1000, 0)  # Device type
ERROR_REGISTER = (0x1001, 0)  # Error register
HEARTBEAT = (0x1017, 0)  # Producer heartbeat time
VENDOR = (0x1018, 1)  # Identity object: Vendor-ID
PRODUCT = (0x1018, 2)  # Identity object: Product code
SERIAL = (0x1018, 4)  # Identity object: Serial number


def objects(tap: SdoTap) -> list[tuple[int, int]]:
    """The (index, sub-index) of each SDO request seen, in order."""
    return [(int.from_bytes(f.data[1:3], "little"), f.data[3]) for f in tap.frames]


async def test_requests_wait_for_a_transaction(nodes: SimNodes) -> None:
    session = nodes.session(1)
    tap = SdoTap(nodes, 1)
    inside = asyncio.Event()

    async def transaction_a() -> None:
        async with session.exclusive(actor="a") as tx:
            assert tx.actor == "a"
            await tx.upload(*DEVICE_TYPE)
            inside.set()
            await asyncio.sleep(0.05)  # the others queue up meanwhile
            await tx.upload(*VENDOR)

    async def transaction_b() -> None:
        await inside.wait()
        async with session.exclusive(actor="b") as tx:
            await tx.upload(*HEARTBEAT)
            await asyncio.sleep(0.02)
            await tx.run(lambda remote: remote.sdo.upload(*PRODUCT), what="read 1018h:02")

    async def plain() -> None:
        await inside.wait()
        await asyncio.sleep(0)  # after b asked for the node
        await session.upload(*ERROR_REGISTER)

    await asyncio.gather(transaction_a(), transaction_b(), plain())
    tap.remove()
    assert objects(tap) == [DEVICE_TYPE, VENDOR, HEARTBEAT, PRODUCT, ERROR_REGISTER]


async def test_queued_requests_finish_before_the_transaction(nodes: SimNodes) -> None:
    session = nodes.session(2)
    tap = SdoTap(nodes, 2)
    early = asyncio.create_task(session.upload(*SERIAL))
    await asyncio.sleep(0)  # queued on the worker
    async with session.exclusive() as tx:
        value = await tx.write_and_read(*HEARTBEAT, (0).to_bytes(2, "little"), read_back=True)
    await early
    tap.remove()
    assert value == b"\x00\x00"
    assert objects(tap) == [SERIAL, HEARTBEAT, HEARTBEAT]


async def test_nested_use_joins_the_transaction(nodes: SimNodes) -> None:
    session = nodes.session(1)
    async with session.exclusive() as outer:
        # a helper that takes the session (not the transaction) is inside too: no deadlock
        assert await asyncio.wait_for(session.upload(*DEVICE_TYPE), 2)
        async with session.exclusive() as inner:
            assert await inner.upload(*DEVICE_TYPE) == await outer.upload(*DEVICE_TYPE)
        with pytest.raises(RuntimeError):
            await inner.upload(*DEVICE_TYPE)  # an ended transaction is not a way in
    with pytest.raises(RuntimeError):
        await outer.upload(*DEVICE_TYPE)


async def test_a_task_outliving_its_transaction_waits_like_others(nodes: SimNodes) -> None:
    session = nodes.session(1)
    tap = SdoTap(nodes, 1)
    release = asyncio.Event()
    async with session.exclusive():
        # started inside (it inherits the context) but runs after the transaction ended
        async def later() -> None:
            await release.wait()
            await session.upload(*VENDOR)

        straggler = asyncio.create_task(later())
    async with session.exclusive() as tx:
        release.set()
        await asyncio.sleep(0.02)
        await tx.upload(*DEVICE_TYPE)
    await straggler
    tap.remove()
    assert objects(tap) == [DEVICE_TYPE, VENDOR]


async def test_closed_session_ends_waiting_transactions(nodes: SimNodes) -> None:
    session = nodes.session(3)
    started = asyncio.Event()

    async def holder() -> None:
        async with session.exclusive():
            started.set()
            await asyncio.sleep(0.05)
            session.close()

    async def waiter() -> None:
        await started.wait()
        async with session.exclusive():
            pytest.fail("a closed session accepted a transaction")

    results = await asyncio.gather(holder(), waiter(), return_exceptions=True)
    assert results[0] is None
    assert isinstance(results[1], RequestInterruptedError)
