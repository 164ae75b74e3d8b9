"""An expedited SDO upload sent and answered on the event loop, for the single reads that live
views poll (`NodeSession.upload`).

Through the node's worker thread a read wakes four threads in turn (loop, worker, the bus's
listener, worker, loop); each wake of an idle thread costs a tenth of a millisecond on a busy
laptop, more than everything else the API does for the read. Here the loop sends the request
and the listener thread hands the answer straight back to the loop. canopen's SDO client has no
way to be awaited, so this one request/response pair is written by hand (CiA 301 §7.2.4.3.3);
anything else (a segmented answer, every write) stays with canopen on the worker.

Only where sending cannot block the loop: python-can's `virtual` bus puts the frame in a queue,
and `socketcan` sends with a zero timeout (a full transmit queue raises at once). The session
serializes it with the worker (`NodeWorker.claim`): it runs only while no transfer runs or waits,
and the worker starts none until it has its answer.
"""

from __future__ import annotations

import asyncio
import contextlib
from typing import Any

import can
import canopen

from servodesk.errors import (
    BusNotConnectedError,
    CommTimeoutError,
    SdoAbortError,
    SdoProtocolError,
)

UPLOAD_REQUEST = 0x40  # ccs 2: initiate upload
UPLOAD_RESPONSE = 0x40  # scs 2 in the top three bits
ABORT = 0x80
EXPEDITED = 0x02
SIZE_GIVEN = 0x01
NOT_EXPEDITED_HERE = 0x05040001  # abort: command specifier not valid (we asked for no segments)
# python-can bus classes whose send never waits (see the module docstring)
NEVER_BLOCK = frozenset({"VirtualBus", "SocketcanBus"})


def sends_without_blocking(bus: can.BusABC | None) -> bool:
    """True for a bus (or a wrapper with `.inner`, bus/monitored.py) whose send never waits."""
    inner = getattr(bus, "inner", bus)
    return type(inner).__name__ in NEVER_BLOCK


class LoopUpload:
    """One node's expedited uploads on the loop; `close()` stops listening."""

    def __init__(self, remote: canopen.RemoteNode) -> None:
        if remote.id is None or remote.network is None:
            raise ValueError("a loop upload needs a node on a network")
        self._node: int = remote.id
        self._network = remote.network
        self._request_id: int = remote.sdo.rx_cobid
        self._response_id: int = remote.sdo.tx_cobid
        self._pending: asyncio.Future[bytes] | None = None
        self._network.subscribe(self._response_id, self._on_response)

    def close(self) -> None:
        # the network may have forgotten its subscribers when it disconnected
        with contextlib.suppress(KeyError, ValueError):
            self._network.unsubscribe(self._response_id, self._on_response)

    def _on_response(self, can_id: int, data: Any, timestamp: float) -> None:
        # the bus listener's thread: hand the answer over, nothing else
        pending = self._pending
        if pending is not None:
            pending.get_loop().call_soon_threadsafe(_answer, pending, bytes(data))

    async def upload(self, index: int, subindex: int, timeout: float) -> bytes | None:
        """The entry's bytes; None when the drive answered with a segmented transfer (aborted
        here: read it through canopen). Domain errors as `NodeSession._call` raises them."""
        what = f"read {index:04X}h:{subindex:02X}h"
        pending: asyncio.Future[bytes] = asyncio.get_running_loop().create_future()
        self._pending = pending
        request = bytes((UPLOAD_REQUEST, index & 0xFF, index >> 8, subindex, 0, 0, 0, 0))
        try:
            try:
                self._network.send_message(self._request_id, request)
            except can.CanError as error:
                raise BusNotConnectedError(f"CAN adapter error during {what}: {error}") from error
            try:
                response = await asyncio.wait_for(pending, timeout)
            except TimeoutError:
                raise CommTimeoutError(self._node, what) from None
        finally:
            self._pending = None
        return self._decode(response, index, subindex, what)

    def _decode(self, data: bytes, index: int, subindex: int, what: str) -> bytes | None:
        if len(data) < 8:
            raise SdoProtocolError(self._node, what, f"a {len(data)}-byte SDO answer")
        command = data[0]
        answered = (int.from_bytes(data[1:3], "little"), data[3])
        if command == ABORT:
            code = int.from_bytes(data[4:8], "little")
            raise SdoAbortError(code, self._node, index, subindex)
        if command & 0xE0 != UPLOAD_RESPONSE:
            raise SdoProtocolError(self._node, what, f"unexpected SDO command {command:#04x}")
        if answered != (index, subindex):
            raise SdoProtocolError(
                self._node,
                what,
                f"the answer is for {answered[0]:04X}h:{answered[1]:02X}h",
            )
        if not command & EXPEDITED:
            abort = bytes((ABORT, index & 0xFF, index >> 8, subindex))
            self._network.send_message(
                self._request_id, abort + NOT_EXPEDITED_HERE.to_bytes(4, "little")
            )
            return None
        size = 4 - ((command >> 2) & 0x3) if command & SIZE_GIVEN else 4
        return data[4 : 4 + size]


def _answer(pending: asyncio.Future[bytes], data: bytes) -> None:
    if not pending.done():  # a second answer (a late one) goes nowhere
        pending.set_result(data)
