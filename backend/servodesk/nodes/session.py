"""One node's access path: a canopen RemoteNode and the single worker thread that every
blocking call to it runs on (DESIGN rule 1).

canopen's SDO client blocks (it polls and sleeps) and has no lock: two callers on one node steal
each other's replies. So all calls to a node go through `NodeSession.run`, which runs them one at
a time on that node's own thread, off the event loop, and turns canopen's exceptions into ours.

A multi-step change (PDO apply, DCF load) takes the node for itself with `exclusive()`: while
it runs, other callers' requests wait at the session's gate and none slips in between its steps
(see `Transaction`).

A transaction that only reads (`exclusive(reading=True)`: every PDO's configuration as one
picture) holds back other reads and writes, but not motion commands, which change nothing it
reads: a jog does not wait out a hundred transfers.

A stop must not wait behind any of that: `priority()` bypasses the gate and goes to the front of
the worker's queue. A motion command (a jog's set-point, ramp, mode, controlword: `run(...,
command=True)`) waits at the gate like any request, then goes ahead of the reads queued before
it (a page's poll, an upload-all, a scan's identification) and behind every stop.

Nor does a stop wait for a long call in progress (a chunk of an upload-all, a state snapshot of
ten reads): while that call has only read so far, the stop runs on the same thread between two
of its SDO transfers (never two transfers at once, never inside a segmented one). A call that
would write after such a stop is refused instead (RequestInterruptedError): it wrote nothing,
and nothing it decided before the stop is sent after it. A call that has written runs to its end
before the stop, as a whole step. If a transaction is open it then sees its step interrupted:
the stop ran between two of its steps (`Transaction.interrupted` names it), and the drive it was
configuring has been stopped. Commands cut into a normal call's reads the same way (after the
stops, in their order), without refusing its later writes: a command decides nothing for it.
"""

from __future__ import annotations

import asyncio
import contextvars
import functools
import threading
import time
from collections import deque
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager, suppress
from typing import Any, Literal, TypeVar

import can
import canopen
from canopen.objectdictionary import ObjectDictionary
from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

from servodesk.errors import (
    BusNotConnectedError,
    CommTimeoutError,
    RequestInterruptedError,
    SdoAbortError,
    SdoProtocolError,
)
from servodesk.nodes.write_step import WriteStep, write_step

T = TypeVar("T")

NO_RESPONSE = "No SDO response received"  # canopen's SdoCommunicationError on a timeout

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
        # What priority call (a stop) ran between this transaction's steps, if any.
        self.interrupted: str | None = None

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


class StopCutInError(Exception):
    """Raised in a call that would write after a stop ran between its reads."""


# A call for the worker and the event-loop future its caller awaits (None: nobody waits).
# the worker's lanes, taken in this order: stops, motion commands, everything else
Lane = Literal["urgent", "command", "normal"]
LANES: tuple[Lane, ...] = ("urgent", "command", "normal")
_Item = tuple[Callable[[], Any], "asyncio.Future[Any] | None"]


class _Worker:
    """One thread running submitted calls one at a time, with three lanes: priority items
    (stops) are taken before everything queued so far, then commands, then normal items; each
    lane is FIFO. A normal call in progress lets stops, then commands, run between its SDO
    transfers while it has only read (`between`); a later write of that call is refused after a
    stop, not after a command (a command decides nothing the call had decided).
    A caller awaits a loop future settled by one `call_soon_threadsafe` (a wrapped concurrent
    Future cost a condition and two more callbacks per call, both sides of the hop)."""

    def __init__(self, name: str) -> None:
        self._lanes: dict[Lane, deque[_Item]] = {lane: deque() for lane in LANES}
        self._ready = threading.Condition()
        self._shutdown = False
        # what the call in progress did (worker thread only)
        self._lane: Lane = "normal"  # of the call in progress: "urgent" (a stop) runs whole
        self._wrote = False
        self._cut_in = False
        self._thread = threading.Thread(target=self._loop, name=name, daemon=True)
        self._thread.start()

    def submit(
        self,
        fn: Callable[[], T],
        future: asyncio.Future[T] | None = None,
        *,
        lane: Lane = "normal",
    ) -> None:
        """Queue `fn`; its result or exception goes to `future` (a cancelled one: not run)."""
        with self._ready:
            if self._shutdown:
                raise RuntimeError("the node's worker has stopped")
            self._lanes[lane].append((fn, future))
            self._ready.notify()

    def shutdown(self) -> None:
        """Stop after the items already queued (each of which ends at once: the session is
        closed, so `_call` refuses them)."""
        with self._ready:
            self._shutdown = True
            self._ready.notify()

    def between(self, writing: bool) -> None:
        """Called before each SDO transfer of the running call. A read lets the stops queued
        meanwhile run first; a write after such a stop raises StopCutInError."""
        if threading.get_ident() != self._thread.ident or self._lane == "urgent":
            return  # not a worker's call, or a stop itself: it runs whole
        if writing:
            if self._cut_in:
                raise StopCutInError
            self._wrote = True
            return
        if self._wrote:
            return  # a call that wrote runs to its end: the stop comes after it
        # commands keep their order: none cuts into another command
        lanes: tuple[Lane, ...] = ("urgent", "command") if self._lane == "normal" else ("urgent",)
        while True:
            with self._ready:
                taken = self._take(lanes)
            if taken is None:
                return
            (fn, future), lane = taken
            outer = (self._lane, self._wrote, self._cut_in)
            self._wrote = self._cut_in = False  # the cutting call's own
            self._execute(fn, future, lane=lane)
            self._lane, self._wrote, self._cut_in = outer
            if lane == "urgent":
                self._cut_in = True

    def _loop(self) -> None:
        while True:
            with self._ready:
                while not any(self._lanes.values()) and not self._shutdown:
                    self._ready.wait()
                taken = self._take(LANES)
            if taken is None:
                return  # shut down and drained
            (fn, future), lane = taken
            self._wrote = self._cut_in = False
            self._execute(fn, future, lane=lane)

    def _take(self, lanes: tuple[Lane, ...]) -> tuple[_Item, Lane] | None:
        """The next item of the first of `lanes` that has one (the caller holds `_ready`)."""
        for lane in lanes:
            if self._lanes[lane]:
                return self._lanes[lane].popleft(), lane
        return None

    def _execute(
        self, fn: Callable[[], Any], future: asyncio.Future[Any] | None, *, lane: Lane
    ) -> None:
        if future is not None and future.cancelled():
            return  # its caller stopped waiting before it started
        self._lane = lane
        try:
            result = fn()
        except BaseException as error:  # handed to the awaiting caller
            _settle_from_thread(future, None, error)
        else:
            _settle_from_thread(future, result, None)
        finally:
            self._lane = "normal"


def _settle_from_thread(
    future: asyncio.Future[Any] | None, result: Any, error: BaseException | None
) -> None:
    if future is not None:
        with suppress(RuntimeError):  # the loop has closed: nobody waits any more
            future.get_loop().call_soon_threadsafe(_settle, future, result, error)


def _settle(future: asyncio.Future[Any], result: Any, error: BaseException | None) -> None:
    if future.done():  # cancelled while the call ran: its result goes nowhere
        return
    if error is None:
        future.set_result(result)
    else:
        future.set_exception(error)


class NodeSession:
    """Serialized, off-loop access to one remote node."""

    def __init__(self, remote: canopen.RemoteNode, *, sdo_timeout: float) -> None:
        if remote.id is None:
            raise ValueError("a node session needs a node id")
        self._node_id: int = remote.id
        self.remote = remote
        remote.sdo.RESPONSE_TIMEOUT = sdo_timeout
        self._worker = _Worker(f"node{remote.id}")
        _announce_transfers(remote, self._worker)
        self._closed = False
        # Held by a transaction for its whole run; every other request passes it only to be
        # queued (FIFO, so requests keep their order). `priority()` does not wait here.
        self._gate = asyncio.Lock()
        self._transactions: list[Transaction] = []  # open ones, told when a stop cuts in
        self._held_reading = False  # the gate's holder only reads: commands pass (exclusive)
        # A timed-out request may still be answered late (a slow drive, a busy bus). SDO
        # answers carry no request id and canopen drops only what arrived before it sends, so a
        # late answer would be taken for the next request's (a PUT read back the value of an
        # earlier GET). After a failed exchange the next call first lets one more response
        # time pass on this node's thread (worker-thread only, no lock needed).
        self._quiet_until: float | None = None

    @property
    def node_id(self) -> int:
        return self._node_id

    def _inside(self) -> bool:
        return any(tx.session is self and tx.open for tx in _HELD.get())

    @asynccontextmanager
    async def exclusive(
        self, actor: str | None = None, *, reading: bool = False
    ) -> AsyncIterator[Transaction]:
        """Take the node for a multi-step change: requests already queued finish first, later
        ones from other callers wait until the block ends. Nested use inside the same
        transaction (a DCF load applying PDOs) joins it instead of waiting for itself.
        `reading`: the block only reads, for one consistent picture (every PDO's
        configuration); motion commands, which change nothing such a picture holds, pass its
        gate instead of waiting out a hundred transfers."""
        if self._inside():
            nested = Transaction(self, actor)
            try:
                yield nested
            finally:
                nested.open = False
            return
        async with self._gate:
            if self._closed:
                raise RequestInterruptedError(self.node_id)
            tx = Transaction(self, actor)
            token = _HELD.set((*_HELD.get(), tx))
            self._transactions.append(tx)
            self._held_reading = reading
            try:
                yield tx
            finally:
                self._held_reading = False
                tx.open = False
                self._transactions.remove(tx)
                _HELD.reset(token)

    async def run(
        self,
        fn: Callable[[canopen.RemoteNode], T],
        *,
        what: str,
        index: int = 0,
        subindex: int = 0,
        command: bool = False,
    ) -> T:
        """Run `fn(remote)` on this node's worker thread; canopen errors become domain errors.

        `what` names the request in a timeout message ("read 1008h:00"); `index`/`subindex` say
        which object an SDO abort is about (canopen's abort exception does not carry it).
        `command`: a motion command, ahead of the reads queued before it (module docstring).
        """
        if self._closed:
            raise RequestInterruptedError(self.node_id)
        call = functools.partial(self._call, fn, what, index, subindex)
        if self._inside() or (command and self._held_reading):
            return await self._queue(call, "command" if command else "normal")
        # Outside a transaction: wait while one holds the node, then queue (without holding
        # the gate while the call runs, so requests still pipeline on the worker).
        async with self._gate:
            if self._closed:
                raise RequestInterruptedError(self.node_id)
            pending = self._queue(call, "command" if command else "normal")
        return await pending

    async def priority(self, fn: Callable[[canopen.RemoteNode], T], *, what: str) -> T:
        """Run `fn(remote)` ahead of every queued call and past a transaction's gate: for
        stopping a drive, which must not wait behind an upload or a DCF load. The call in
        progress finishes first (never two SDO transfers at once). An open transaction is
        marked interrupted (see the module docstring)."""
        if self._closed:
            raise RequestInterruptedError(self.node_id)
        for tx in self._transactions:
            tx.interrupted = what
        # a stop does not wait for late answers to settle (see _quiet_until)
        call = functools.partial(self._call, fn, what, 0, 0, urgent=True)
        return await self._queue(call, "urgent")

    def _queue(self, call: Callable[[], T], lane: Lane = "normal") -> asyncio.Future[T]:
        future: asyncio.Future[T] = asyncio.get_running_loop().create_future()
        self._worker.submit(call, future, lane=lane)
        return future

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
        self,
        index: int,
        subindex: int,
        data: bytes,
        *,
        read_back: bool,
        read_first: bool = False,
        seen: WriteStep | None = None,
    ) -> bytes | None:
        """Download `data` and upload the entry again as one step on the node's thread, so no
        other request's write can land between the two; with `read_first`, the value before is
        uploaded in the same step (into `seen.before`). None when there is nothing to read
        back (`read_back` false, or the drive calls the entry write-only)."""
        step = functools.partial(
            write_step,
            index=index,
            subindex=subindex,
            data=data,
            read_first=read_first,
            read_back=read_back,
            seen=seen if seen is not None else WriteStep(),
        )
        done = await self.run(
            step, what=f"write {index:04X}h:{subindex:02X}h", index=index, subindex=subindex
        )
        return done.after

    def replace_dictionary(
        self, od: ObjectDictionary, *, then: Callable[[], None] | None = None
    ) -> None:
        """Use `od` for every call queued from now on, then run `then` (e.g. release the old
        dictionary).

        Queued as a step on the node's thread: calls already waiting complete with the old
        dictionary, later ones with the new one. The RemoteNode itself stays (its SDO and PDO
        helpers look the dictionary up when they need it)."""
        if self._closed:
            raise RequestInterruptedError(self.node_id)

        def swap() -> None:
            remote = self.remote
            remote.object_dictionary = od
            for channel in remote.sdo_channels:
                channel.od = od
            if then is not None:
                then()

        self._worker.submit(swap)

    def _call(
        self,
        fn: Callable[[canopen.RemoteNode], T],
        what: str,
        index: int,
        subindex: int,
        *,
        urgent: bool = False,
    ) -> T:
        if self._closed:
            # queued before the connection was renewed: its remote is gone, send nothing
            raise RequestInterruptedError(self.node_id)
        if not urgent:
            self._let_late_answers_pass()
        try:
            return fn(self.remote)
        except StopCutInError:
            raise RequestInterruptedError(self.node_id, stopped_during=what) from None
        except SdoAbortedError as abort:
            raise SdoAbortError(int(abort.code), self.node_id, index, subindex) from abort
        except SdoCommunicationError as error:
            if self._closed:  # the answer went to the old connection's listeners
                raise RequestInterruptedError(self.node_id) from error
            self._quiet_until = time.monotonic() + self.remote.sdo.RESPONSE_TIMEOUT
            if str(error) != NO_RESPONSE:
                # it did answer, out of protocol (toggle bit, command): say so, not "no answer"
                raise SdoProtocolError(self.node_id, what, str(error)) from error
            raise CommTimeoutError(self.node_id, what) from error
        except RuntimeError as error:
            # canopen's "Not connected to CAN bus": the connection closed during the call
            if self._closed or not _on_a_bus(self.remote):
                raise RequestInterruptedError(self.node_id) from error
            raise
        except can.CanError as error:
            # The adapter itself failed (unplugged, bus-off): the bus manager reconnects.
            raise BusNotConnectedError(f"CAN adapter error during {what}: {error}") from error

    def _let_late_answers_pass(self) -> None:
        """After a failed exchange, wait until a late answer to it would have arrived; canopen
        then drops it when the next request starts (see `_quiet_until`)."""
        until, self._quiet_until = self._quiet_until, None
        if until is not None:
            delay = until - time.monotonic()
            if delay > 0:
                time.sleep(delay)

    def close(self) -> None:
        """Stop the worker thread after the call in progress. Calls still queued are not
        cancelled (their callers would see a bare CancelledError): each ends at once with
        RequestInterruptedError, and no new calls are accepted."""
        self._closed = True
        self._worker.shutdown()


def _announce_transfers(remote: canopen.RemoteNode, worker: _Worker) -> None:
    """Every SDO transfer of the node opens a stream (upload and download do too): the worker
    hears of each before it starts, to let a stop cut in or refuse a write after one."""
    sdo = remote.sdo
    open_stream = sdo.open

    @functools.wraps(open_stream)
    def announced(
        index: int, subindex: int = 0, mode: str = "rb", *args: Any, **kwargs: Any
    ) -> Any:
        worker.between(writing="w" in mode)
        return open_stream(index, subindex, mode, *args, **kwargs)

    sdo.open = announced


def _on_a_bus(remote: canopen.RemoteNode) -> bool:
    try:
        return remote.network.bus is not None
    except RuntimeError:  # canopen's placeholder network of a node taken off its network
        return False
