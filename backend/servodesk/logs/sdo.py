"""SDO transfers reassembled from the frames of one SDO channel (CiA 301 §7.2.4.3): expedited,
segmented and block, up- and download, aborts from either side.

A pure state machine per channel (request COB-ID 600h + node, response 580h + node): feed it
every frame of the channel in bus order, it returns a finished `SdoTransfer` on the frame that
ends one. Memory is bounded: only the first `KEEP_BYTES` of a transfer's data are kept.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum, StrEnum

from servodesk_protocol.sdo import Ccs, Scs

KEEP_BYTES = 64  # enough for identity objects, names and PDO parameters
_SEQ_MASK = 0x7F  # block segments: bit 7 = last segment, bits 0–6 = sequence number
_LAST = 0x80
# abort codes that only one direction can meet (CiA 301 §7.2.4.3.17): True = upload (read)
ABORT_DIRECTION = {
    0x06010001: True,  # Attempt to read a write-only object
    0x06010002: False,  # Attempt to write a read-only object
    0x06090030: False,  # Invalid value for parameter (download only)
    0x06090031: False,  # Value of parameter written too high (download only)
    0x06090032: False,  # Value of parameter written too low (download only)
    0x06090036: False,  # Maximum value is less than minimum value
}


class SdoMode(StrEnum):
    EXPEDITED = "expedited"
    SEGMENTED = "segmented"
    BLOCK = "block"


class _State(IntEnum):
    IDLE = 0
    DOWNLOAD = 1  # initiate or segments of a download, waiting for the server
    UPLOAD = 2  # initiate or segments of an upload
    BLOCK_DOWNLOAD = 3  # after the initiate, before the client's sub-block segments
    BLOCK_DOWNLOAD_SEGMENTS = 4  # client segments (no command byte) until the server's ack
    BLOCK_DOWNLOAD_END = 5  # the client's end request and the server's end response
    BLOCK_UPLOAD = 6  # initiate and start, before the server's segments
    BLOCK_UPLOAD_SEGMENTS = 7  # server segments until the client's ack
    BLOCK_UPLOAD_END = 8  # the server's end and the client's end response


@dataclass(frozen=True, slots=True)
class SdoTransfer:
    """One finished (or aborted, or interrupted) transfer."""

    upload: bool  # True: the client read the object
    index: int
    subindex: int
    mode: SdoMode
    size: int  # data bytes transferred
    data: bytes  # the first KEEP_BYTES of them
    abort: int | None = None  # abort code, None when it completed
    aborted_by_client: bool = False
    start: float = 0.0  # time of the initiate frame
    first_frame: int = 0  # frame number of the initiate (the caller's numbering)
    error: str | None = None  # the frames did not follow the protocol (in words)
    # an abort whose initiate is not in the log: `upload` is a guess from the abort code,
    # and only when `direction_known`
    began_before_log: bool = False
    direction_known: bool = True


class SdoChannel:
    """The transfer state of one client/server pair. `feed(...)` returns the transfer a frame
    ends; `cs` holds the command specifier of the last frame (None for a block segment)."""

    __slots__ = (
        "_block_last",
        "_data",
        "_expedited",
        "_first_frame",
        "_last_segment",
        "_size",
        "_start",
        "_state",
        "_upload",
        "cs",
        "index",
        "subindex",
    )

    def __init__(self) -> None:
        self._state = _State.IDLE
        self.cs: int | None = None
        self.index = 0
        self.subindex = 0
        self._upload = False
        self._expedited = False
        self._data = bytearray()
        self._size = 0
        self._last_segment = False
        self._block_last = False
        self._start = 0.0
        self._first_frame = 0

    @property
    def busy(self) -> bool:
        return self._state is not _State.IDLE

    def request(self, data: bytes, time: float, frame: int) -> SdoTransfer | None:
        """A client -> server frame (COB-ID 600h + node)."""
        if not data:
            return None
        b0 = data[0]
        state = self._state
        if state is _State.BLOCK_DOWNLOAD_SEGMENTS and b0 & _SEQ_MASK:
            self.cs = None  # a segment: sequence number, no command specifier
            self._take(data[1:8])
            if b0 & _LAST:
                self._block_last = True
            return None
        ccs = self.cs = b0 >> 5
        if ccs == Ccs.ABORT:
            return self._abort(data, by_client=True, time=time, frame=frame)
        if ccs == Ccs.INITIATE_DOWNLOAD:
            interrupted = self._interrupted()
            self._begin(data, time, frame, upload=False)
            self._expedited = bool(b0 & 0x02)
            if self._expedited:
                size = 4 - ((b0 >> 2) & 0x03) if b0 & 0x01 else 4
                self._take(data[4 : 4 + size])
            self._state = _State.DOWNLOAD
            return interrupted
        if ccs == Ccs.DOWNLOAD_SEGMENT and state is _State.DOWNLOAD:
            unused = (b0 >> 1) & 0x07
            self._take(data[1 : 8 - unused])
            self._last_segment = bool(b0 & 0x01)
            return None
        if ccs == Ccs.INITIATE_UPLOAD:
            interrupted = self._interrupted()
            self._begin(data, time, frame, upload=True)
            self._state = _State.UPLOAD
            return interrupted
        if ccs == Ccs.UPLOAD_SEGMENT and state is _State.UPLOAD:
            return None
        if ccs == Ccs.BLOCK_DOWNLOAD:  # initiate (cs 0) or end (cs 1)
            if b0 & 0x01 == 0:
                interrupted = self._interrupted()
                self._begin(data, time, frame, upload=False)
                self._state = _State.BLOCK_DOWNLOAD
                return interrupted
            if state is _State.BLOCK_DOWNLOAD_END:
                self._trim((b0 >> 2) & 0x07)
            return None
        if ccs == Ccs.BLOCK_UPLOAD:  # initiate 0, end response 1, ack 2, start 3
            cs = b0 & 0x03
            if cs == 0:
                interrupted = self._interrupted()
                self._begin(data, time, frame, upload=True)
                self._state = _State.BLOCK_UPLOAD
                return interrupted
            if cs == 3 and state is _State.BLOCK_UPLOAD:
                self._state = _State.BLOCK_UPLOAD_SEGMENTS
            elif cs == 2 and state is _State.BLOCK_UPLOAD_SEGMENTS:
                self._state = (
                    _State.BLOCK_UPLOAD_END if self._block_last else _State.BLOCK_UPLOAD_SEGMENTS
                )
            elif cs == 1 and state is _State.BLOCK_UPLOAD_END:
                return self._finish(SdoMode.BLOCK)
            return None
        return self._unexpected(f"client command specifier {ccs} in state {state.name}")

    def response(self, data: bytes, time: float, frame: int) -> SdoTransfer | None:
        """A server -> client frame (COB-ID 580h + node)."""
        if not data:
            return None
        b0 = data[0]
        state = self._state
        if state is _State.BLOCK_UPLOAD_SEGMENTS and b0 & _SEQ_MASK:
            self.cs = None
            self._take(data[1:8])
            if b0 & _LAST:
                self._block_last = True
            return None
        scs = self.cs = b0 >> 5
        if scs == Scs.ABORT:
            return self._abort(data, by_client=False, time=time, frame=frame)
        if scs == Scs.INITIATE_DOWNLOAD and state is _State.DOWNLOAD:
            return self._finish(SdoMode.EXPEDITED) if self._expedited else None
        if scs == Scs.DOWNLOAD_SEGMENT and state is _State.DOWNLOAD:
            return self._finish(SdoMode.SEGMENTED) if self._last_segment else None
        if scs == Scs.INITIATE_UPLOAD:  # also without a request in the log
            if state is not _State.UPLOAD:
                self._begin(data, time, frame, upload=True)
            self._state = _State.UPLOAD
            if b0 & 0x02:  # expedited
                size = 4 - ((b0 >> 2) & 0x03) if b0 & 0x01 else 4
                self._take(data[4 : 4 + size])
                return self._finish(SdoMode.EXPEDITED)
            return None
        if scs == Scs.UPLOAD_SEGMENT and state is _State.UPLOAD:
            unused = (b0 >> 1) & 0x07
            self._take(data[1 : 8 - unused])
            return self._finish(SdoMode.SEGMENTED) if b0 & 0x01 else None
        if scs == Scs.BLOCK_DOWNLOAD:  # initiate response 0, end response 1, ack 2
            ss = b0 & 0x03
            if ss == 0 and state is _State.BLOCK_DOWNLOAD:
                self._state = _State.BLOCK_DOWNLOAD_SEGMENTS
            elif ss == 2 and state is _State.BLOCK_DOWNLOAD_SEGMENTS:
                self._state = (
                    _State.BLOCK_DOWNLOAD_END
                    if self._block_last
                    else _State.BLOCK_DOWNLOAD_SEGMENTS
                )
            elif ss == 1 and state is _State.BLOCK_DOWNLOAD_END:
                return self._finish(SdoMode.BLOCK)
            return None
        if scs == Scs.BLOCK_UPLOAD:  # initiate response 0, end 1 (unused bytes in bits 2–4)
            if b0 & 0x01 and state is _State.BLOCK_UPLOAD_END:
                self._trim((b0 >> 2) & 0x07)
            return None
        return self._unexpected(f"server command specifier {scs} in state {state.name}")

    def flush(self) -> SdoTransfer | None:
        """The transfer still open at the end of a log, as interrupted."""
        return self._interrupted("the log ends during the transfer")

    # ------------------------------------------------------------------ helpers

    def _begin(self, data: bytes, time: float, frame: int, *, upload: bool) -> None:
        self.index = data[1] | data[2] << 8 if len(data) >= 3 else 0
        self.subindex = data[3] if len(data) >= 4 else 0
        self._upload = upload
        self._expedited = False
        self._data = bytearray()
        self._size = 0
        self._last_segment = False
        self._block_last = False
        self._start = time
        self._first_frame = frame

    def _take(self, chunk: bytes) -> None:
        self._size += len(chunk)
        room = KEEP_BYTES - len(self._data)
        if room > 0:
            self._data += chunk[:room]

    def _trim(self, unused: int) -> None:
        """Block transfers say at the end how many bytes of the last segment were padding."""
        self._size = max(0, self._size - unused)
        del self._data[self._size :]

    def _transfer(self, mode: SdoMode, **extra: object) -> SdoTransfer:
        self._state = _State.IDLE
        return SdoTransfer(
            upload=self._upload,
            index=self.index,
            subindex=self.subindex,
            mode=mode,
            size=self._size,
            data=bytes(self._data),
            start=self._start,
            first_frame=self._first_frame,
            **extra,  # type: ignore[arg-type]
        )

    def _mode(self) -> SdoMode:
        if self._state >= _State.BLOCK_DOWNLOAD:
            return SdoMode.BLOCK
        return SdoMode.EXPEDITED if self._expedited else SdoMode.SEGMENTED

    def _finish(self, mode: SdoMode) -> SdoTransfer:
        return self._transfer(mode)

    def _abort(self, data: bytes, *, by_client: bool, time: float, frame: int) -> SdoTransfer:
        code = int.from_bytes(data[4:8], "little") if len(data) >= 8 else 0
        if self._state is _State.IDLE:  # the transfer began before the log: the abort names it
            upload = ABORT_DIRECTION.get(code)
            self._begin(data, time, frame, upload=bool(upload))
            return self._transfer(
                self._mode(), abort=code, aborted_by_client=by_client,
                began_before_log=True, direction_known=upload is not None,
            )  # fmt: skip
        if len(data) >= 4:
            self.index, self.subindex = data[1] | data[2] << 8, data[3]
        return self._transfer(self._mode(), abort=code, aborted_by_client=by_client)

    def _interrupted(self, why: str = "a new transfer started first") -> SdoTransfer | None:
        if self._state is _State.IDLE:
            return None
        return self._transfer(self._mode(), error=f"incomplete: {why}")

    def _unexpected(self, what: str) -> SdoTransfer | None:
        """A frame that fits no open transfer (the log started mid-transfer, or a frame was
        lost): the open transfer, if any, ends as broken; a lone frame is ignored."""
        if self._state is _State.IDLE:
            return None
        return self._transfer(self._mode(), error=f"protocol error: {what}")
