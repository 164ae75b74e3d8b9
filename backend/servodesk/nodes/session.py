"""One node's access path: a canopen RemoteNode and the single worker thread that every
blocking call to it runs on (DESIGN rule 1).

canopen's SDO client blocks (it polls and sleeps) and has no lock: two callers on one node steal
each other's replies. So all calls to a node go through `NodeSession.run`, which runs them one at
a time on that node's own thread, off the event loop, and turns canopen's exceptions into ours.

A multi-step change (PDO apply, DCF load) takes the node for itself with `exclusive()`: while
it runs, other callers' requests wait at the session's gate and none slips in between its steps
(see `Transaction`).
"""

from __future__ import annotations

import asyncio
import contextvars
import functools
from collections.abc import AsyncIterator, Callable
from concurrent.futures import ThreadPoolExecutor
from contextlib import asynccontextmanager
from typing import TypeVar

import can
import canopen
from canopen.objectdictionary import ObjectDictionary
from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

from servodesk.errors import (
    BusNotConnectedError,
    CommTimeoutError,
    RequestInterruptedError,
    SdoAbortError,
)

T = TypeVar("T")

WRITE_ONLY = 0x06010001  # SDO abort: attempt to read a write-only object
CLOSED = "the connection to it was renewed (bus reconnected or node moved) while the request waited"

# The transactions the running task (and the tasks it starts) is inside: their own requests
# pass the gate that holds everyone else's back. A task that outlives the transaction it was
# started in finds it closed and waits like everyone else.
_HELD: contextvars.ContextVar[tuple[Transaction, ...]] = contextvars.ContextVar(
    "servodesk_transactions", default=()
)


class Transaction:
    """A node taken for one multi-step change (`NodeSession.exclusive`).

    Its requests run in order with nothing from other callers in between; `actor` names who
    acts, for the audit log. Calls made through the session itself from inside the transaction
    (by helpers that take a session) pass too: being inside is a property of the running task.
    """

    def __init__(self, session: NodeSession, actor: str | None) -> None:
        self.session = session
        self.actor = actor
        self.open = True

    @property
    def node_id(self) -> int:
        return self.session.node_id

    def _live(self) -> NodeSession:
        if not self.open:
            raise RuntimeError("the transaction has ended")  # a bug of ours, not the user's
        return self.session

    async def run(
        self,
        fn: Callable[[canopen.RemoteNode], T],
        *,
        what: str,
        index: int = 0,
        subindex: int = 0,
    ) -> T:
        return await self._live().run(fn, what=what, index=index, subindex=subindex)

    async def upload(self, index: int, subindex: int) -> bytes:
        return await self._live().upload(index, subindex)

    async def download(self, index: int, subindex: int, data: bytes) -> None:
        await self._live().download(index, subindex, data)

    async def write_and_read(
        self, index: int, subindex: int, data: bytes, *, read_back: bool
    ) -> bytes | None:
        return await self._live().write_and_read(index, subindex, data, read_back=read_back)


class NodeSession:
    """Serialized, off-loop access to one remote node."""

    def __init__(self, remote: canopen.RemoteNode, *, sdo_timeout: float) -> None:
        if remote.id is None:
            raise ValueError("a node session needs a node id")
        self._node_id: int = remote.id
        self.remote = remote
        remote.sdo.RESPONSE_TIMEOUT = sdo_timeout
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix=f"node{remote.id}")
        self._closed = False
        # Held by a transaction for its whole run; every other request passes it only to be
        # queued (FIFO, so requests keep their order). A priority stop (a later issue) must
        # not wait here nor behind the worker's queue: it would bypass this gate, go to the
        # front of the worker's queue (a two-lane queue instead of ThreadPoolExecutor's FIFO),
        # run between two steps of a transaction, and mark the transaction interrupted so it
        # restores what it changed instead of continuing.
        self._gate = asyncio.Lock()

    @property
    def node_id(self) -> int:
        return self._node_id

    def _inside(self) -> bool:
        return any(tx.session is self and tx.open for tx in _HELD.get())

    @asynccontextmanager
    async def exclusive(self, actor: str | None = None) -> AsyncIterator[Transaction]:
        """Take the node for a multi-step change: requests already queued finish first, later
        ones from other callers wait until the block ends. Nested use inside the same
        transaction (a DCF load applying PDOs) joins it instead of waiting for itself."""
        if self._inside():
            nested = Transaction(self, actor)
            try:
                yield nested
            finally:
                nested.open = False
            return
        async with self._gate:
            if self._closed:
                raise RequestInterruptedError(self.node_id, CLOSED)
            tx = Transaction(self, actor)
            token = _HELD.set((*_HELD.get(), tx))
            try:
                yield tx
            finally:
                tx.open = False
                _HELD.reset(token)

    async def run(
        self,
        fn: Callable[[canopen.RemoteNode], T],
        *,
        what: str,
        index: int = 0,
        subindex: int = 0,
    ) -> T:
        """Run `fn(remote)` on this node's worker thread; canopen errors become domain errors.

        `what` names the request in a timeout message ("read 1008h:00"); `index`/`subindex` say
        which object an SDO abort is about (canopen's abort exception does not carry it).
        """
        if self._closed:
            raise RequestInterruptedError(self.node_id, CLOSED)
        loop = asyncio.get_running_loop()
        call = functools.partial(self._call, fn, what, index, subindex)
        if self._inside():
            return await loop.run_in_executor(self._executor, call)
        # Outside a transaction: wait while one holds the node, then queue (without holding
        # the gate while the call runs, so requests still pipeline on the worker).
        async with self._gate:
            if self._closed:
                raise RequestInterruptedError(self.node_id, CLOSED)
            pending = loop.run_in_executor(self._executor, call)
        return await pending

    async def upload(self, index: int, subindex: int) -> bytes:
        """SDO upload (read) of one entry's raw bytes."""
        return await self.run(
            lambda remote: bytes(remote.sdo.upload(index, subindex)),
            what=f"read {index:04X}h:{subindex:02X}h",
            index=index,
            subindex=subindex,
        )

    async def download(self, index: int, subindex: int, data: bytes) -> None:
        """SDO download (write) of one entry's raw bytes (expedited or segmented by size)."""
        await self.run(
            lambda remote: remote.sdo.download(index, subindex, data),
            what=f"write {index:04X}h:{subindex:02X}h",
            index=index,
            subindex=subindex,
        )

    async def write_and_read(
        self, index: int, subindex: int, data: bytes, *, read_back: bool
    ) -> bytes | None:
        """Download `data` and upload the entry again as one step on the node's thread, so no
        other request's write can land between the two. None when there is nothing to read
        back (`read_back` false, or the drive calls the entry write-only)."""

        def step(remote: canopen.RemoteNode) -> bytes | None:
            remote.sdo.download(index, subindex, data)
            if not read_back:
                return None
            try:
                return bytes(remote.sdo.upload(index, subindex))
            except SdoAbortedError as abort:
                if int(abort.code) == WRITE_ONLY:
                    return None
                raise

        return await self.run(
            step, what=f"write {index:04X}h:{subindex:02X}h", index=index, subindex=subindex
        )

    def replace_dictionary(
        self, od: ObjectDictionary, *, then: Callable[[], None] | None = None
    ) -> None:
        """Use `od` for every call queued from now on, then run `then` (e.g. release the old
        dictionary).

        Queued as a step on the node's thread: calls already waiting complete with the old
        dictionary, later ones with the new one. The RemoteNode itself stays (its SDO and PDO
        helpers look the dictionary up when they need it)."""
        if self._closed:
            raise RequestInterruptedError(self.node_id, CLOSED)

        def swap() -> None:
            remote = self.remote
            remote.object_dictionary = od
            for channel in remote.sdo_channels:
                channel.od = od
            if then is not None:
                then()

        self._executor.submit(swap)

    def _call(
        self, fn: Callable[[canopen.RemoteNode], T], what: str, index: int, subindex: int
    ) -> T:
        if self._closed:
            # queued before the connection was renewed: its remote is gone, send nothing
            raise RequestInterruptedError(self.node_id, CLOSED)
        try:
            return fn(self.remote)
        except SdoAbortedError as abort:
            raise SdoAbortError(int(abort.code), self.node_id, index, subindex) from abort
        except SdoCommunicationError as error:
            if self._closed:  # the answer went to the old connection's listeners
                raise RequestInterruptedError(self.node_id, CLOSED) from error
            raise CommTimeoutError(self.node_id, what) from error
        except RuntimeError as error:
            # canopen's "Not connected to CAN bus": the connection closed during the call
            if self._closed or not _on_a_bus(self.remote):
                raise RequestInterruptedError(self.node_id, CLOSED) from error
            raise
        except can.CanError as error:
            # The adapter itself failed (unplugged, bus-off): the bus manager reconnects.
            raise BusNotConnectedError(f"CAN adapter error during {what}: {error}") from error

    def close(self) -> None:
        """Stop the worker thread after the call in progress. Calls still queued are not
        cancelled (their callers would see a bare CancelledError): each ends at once with
        RequestInterruptedError, and no new calls are accepted."""
        self._closed = True
        self._executor.shutdown(wait=False, cancel_futures=False)


def _on_a_bus(remote: canopen.RemoteNode) -> bool:
    try:
        return remote.network.bus is not None
    except RuntimeError:  # canopen's placeholder network of a node taken off its network
        return False
