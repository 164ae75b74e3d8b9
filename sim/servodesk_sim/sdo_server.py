"""SDO server of a simulated drive: a pure state machine over 8-byte requests (CiA 301 §7.2.4).

Hand-written instead of canopen's SdoServer, which checks no toggle bit, has no server-side
timeout and cannot refuse block transfer per device: the simulated drives must show all three.
The caller routes frames from COB-ID 600h+id here and sends the answers on 580h+id.
"""

from __future__ import annotations

import binascii
from dataclasses import dataclass, field
from enum import Enum, IntEnum
from typing import Protocol

from servodesk_protocol.sdo import ABORT_COMMAND, Ccs, abort_frame
from servodesk_protocol.sdo import address as _address
from servodesk_protocol.sdo_abort import (
    COMMAND_NOT_VALID,
    CRC_ERROR,
    INVALID_BLOCK_SIZE,
    INVALID_SEQUENCE,
    LENGTH_TOO_HIGH,
    OUT_OF_MEMORY,
    PROTOCOL_TIMED_OUT,
    TOGGLE_NOT_ALTERNATED,
    TYPE_MISMATCH,
)
from servodesk_sim.abort_codes import SdoAbort

FRAME_LENGTH = 8
SEGMENT_DATA = 7  # data bytes in one segment of a segmented or block transfer
MAX_BLOCK_SIZE = 127  # segments per block (CiA 301 block transfer, blksize 1–127)
MAX_TRANSFER = 0x10000  # bytes a simulated drive buffers for one transfer
TOGGLE = 0x10
EXPEDITED = 0x02
SIZE_INDICATED = 0x01
CRC_SUPPORTED = 0x04
LAST_SEGMENT = 0x01  # c bit of segmented transfer
LAST_BLOCK_SEGMENT = 0x80  # c bit of block transfer


class BlockUploadCs(IntEnum):
    """Client subcommand of a block upload request (byte 0 bits 1–0)."""

    INITIATE = 0
    END = 1
    ACK = 2
    START = 3


class ObjectAccess(Protocol):
    def read_bytes(self, index: int, subindex: int) -> bytes: ...

    def write_bytes(self, index: int, subindex: int, data: bytes) -> None: ...


class _Phase(Enum):
    SEGMENT_DOWNLOAD = "segment download"
    SEGMENT_UPLOAD = "segment upload"
    BLOCK_DOWNLOAD = "block download: receiving a block"
    BLOCK_DOWNLOAD_END = "block download: waiting for the end request"
    BLOCK_UPLOAD_START = "block upload: waiting for the start request"
    BLOCK_UPLOAD_ACK = "block upload: waiting for the block acknowledge"
    BLOCK_UPLOAD_END = "block upload: waiting for the end response"


@dataclass
class _Transfer:
    phase: _Phase
    index: int
    subindex: int
    last: float  # time of the client's last frame, for the server-side timeout
    data: bytearray = field(default_factory=bytearray)
    size: int | None = None  # size the client indicated (downloads)
    toggle: int = 0  # toggle bit expected in the next segment request
    crc: bool = False  # block transfer: the client asked for a CRC
    blksize: int = MAX_BLOCK_SIZE
    seqno: int = 0  # block download: last sequence number received in this block
    offset: int = 0  # uploads: first byte not yet acknowledged
    sent: int = 0  # block upload: segments sent in the current block
    final_sent: bool = False  # block upload: the current block holds the last segment


def crc16(data: bytes) -> int:
    """CRC-16-CCITT (poly 1021h, init 0) of block transfers; canopen.sdo's CrcXmodem computes it
    with the same call."""
    return binascii.crc_hqx(data, 0)


def _requested(data: bytes) -> tuple[int, int]:
    """Index and sub-index of an initiate request (bytes 1–3)."""
    return int.from_bytes(data[1:3], "little"), data[3]


def _frame(command: int, index: int, subindex: int, payload: bytes = b"") -> bytes:
    return (bytes([command]) + _address(index, subindex) + payload).ljust(FRAME_LENGTH, b"\0")


class SdoServer:
    """One SDO server channel: expedited, segmented and (optionally) block transfers."""

    def __init__(
        self, objects: ObjectAccess, *, block_transfer: bool, timeout: float = 1.0
    ) -> None:
        self._objects = objects
        self._block_transfer = block_transfer
        self._timeout = timeout
        self._transfer: _Transfer | None = None
        self._abort_at = (0, 0)  # object an abort raised while handling a request refers to

    def on_request(self, data: bytes, now: float) -> list[bytes]:
        """Handle one request from the client; returns the 8-byte payloads to send."""
        if len(data) < FRAME_LENGTH:
            # CiA 301 §7.2.4.3: SDO frames always carry 8 bytes; a shorter one is not an SDO
            # request (a misconfigured client or another protocol on this id), so say nothing.
            return []
        data = bytes(data[:FRAME_LENGTH])
        transfer = self._transfer
        # Aborts name the object in transfer; segment requests carry no index of their own.
        self._abort_at = (0, 0) if transfer is None else (transfer.index, transfer.subindex)
        try:
            return self._dispatch(data, now)
        except SdoAbort as exc:
            self._transfer = None
            return [abort_frame(*self._abort_at, exc.code)]

    def poll(self, now: float) -> list[bytes]:
        """Abort (05040000) a segmented or block transfer the client left idle for > timeout."""
        transfer = self._transfer
        if transfer is None or now - transfer.last <= self._timeout:
            return []
        self._transfer = None
        return [abort_frame(transfer.index, transfer.subindex, PROTOCOL_TIMED_OUT)]

    def reset(self) -> None:
        """Drop any transfer in progress (NMT reset)."""
        self._transfer = None

    # ------------------------------------------------------------------------------- dispatch

    def _dispatch(self, data: bytes, now: float) -> list[bytes]:
        transfer = self._transfer
        if transfer is not None and transfer.phase is _Phase.BLOCK_DOWNLOAD:
            # Inside a block every frame is a segment (byte 0 = c | seqno), except an abort.
            if data[0] == ABORT_COMMAND:
                self._transfer = None
                return []
            return self._block_segment(transfer, data, now)
        ccs = data[0] >> 5
        if ccs == Ccs.ABORT:
            self._transfer = None  # the client gave up: no answer (CiA 301 §7.2.4.3.17)
            return []
        if ccs == Ccs.INITIATE_DOWNLOAD:
            return self._initiate_download(data, now)
        if ccs == Ccs.DOWNLOAD_SEGMENT:
            return self._download_segment(data, now)
        if ccs == Ccs.INITIATE_UPLOAD:
            return self._initiate_upload(data, now)
        if ccs == Ccs.UPLOAD_SEGMENT:
            return self._upload_segment(data, now)
        if ccs in (Ccs.BLOCK_UPLOAD, Ccs.BLOCK_DOWNLOAD) and self._block_transfer:
            if ccs == Ccs.BLOCK_UPLOAD:
                return self._block_upload(data, now)
            return self._block_download(data, now)
        # Unknown specifier, or block transfer on a drive without it (MDi-S1-C manual §2.4.2
        # supports
        # only expedited and segmented transfer; table 2.32 echoes the request's object).
        if transfer is None:
            self._abort_at = _requested(data)
        raise SdoAbort(COMMAND_NOT_VALID)

    def _start(self, data: bytes) -> tuple[int, int]:
        """An initiate request replaces any transfer in progress; aborts now name its object."""
        self._transfer = None
        self._abort_at = _requested(data)
        return self._abort_at

    def _expect(self, phase: _Phase, now: float) -> _Transfer:
        transfer = self._transfer
        if transfer is None or transfer.phase is not phase:
            raise SdoAbort(COMMAND_NOT_VALID, f"not in {phase.value}")
        transfer.last = now
        return transfer

    # ---------------------------------------------------------------------- expedited/segmented

    def _initiate_download(self, data: bytes, now: float) -> list[bytes]:
        index, sub = self._start(data)
        command = data[0]
        if command & EXPEDITED:
            if command & SIZE_INDICATED:
                unused = (command >> 2) & 0x3
                self._objects.write_bytes(index, sub, data[4 : 8 - unused])
            else:
                self._write_unsized(index, sub, data[4:8])
            return [_frame(0x60, index, sub)]
        size = int.from_bytes(data[4:8], "little") if command & SIZE_INDICATED else None
        if size is not None and size > MAX_TRANSFER:
            raise SdoAbort(OUT_OF_MEMORY)
        self._transfer = _Transfer(_Phase.SEGMENT_DOWNLOAD, index, sub, now, size=size)
        return [_frame(0x60, index, sub)]

    def _write_unsized(self, index: int, sub: int, data: bytes) -> None:
        """Expedited download without size (22h): the object's own size decides (CiA 301).

        ObjectAccess cannot be asked for a size, so offer 4, 3, 2, 1 bytes: a refused length
        changes nothing (the length is checked before anything is stored).
        """
        first: SdoAbort | None = None
        for length in (4, 3, 2, 1):
            try:
                self._objects.write_bytes(index, sub, data[:length])
            except SdoAbort as exc:
                if exc.code not in (TYPE_MISMATCH, LENGTH_TOO_HIGH):
                    raise
                first = first or exc
            else:
                return
        if first is not None:
            raise first

    def _download_segment(self, data: bytes, now: float) -> list[bytes]:
        transfer = self._expect(_Phase.SEGMENT_DOWNLOAD, now)
        toggle = data[0] & TOGGLE
        if toggle != transfer.toggle:
            raise SdoAbort(TOGGLE_NOT_ALTERNATED)
        transfer.toggle ^= TOGGLE
        unused = (data[0] >> 1) & 0x7
        transfer.data += data[1 : FRAME_LENGTH - unused]
        if len(transfer.data) > MAX_TRANSFER:
            raise SdoAbort(OUT_OF_MEMORY)
        if data[0] & LAST_SEGMENT:
            self._transfer = None
            if transfer.size is not None and len(transfer.data) != transfer.size:
                raise SdoAbort(TYPE_MISMATCH, "segments do not add up to the indicated size")
            self._objects.write_bytes(transfer.index, transfer.subindex, bytes(transfer.data))
        return [bytes([0x20 | toggle]).ljust(FRAME_LENGTH, b"\0")]

    def _initiate_upload(self, data: bytes, now: float) -> list[bytes]:
        index, sub = self._start(data)
        payload = self._objects.read_bytes(index, sub)
        if 0 < len(payload) <= 4:
            command = 0x43 | (4 - len(payload)) << 2  # e=1, s=1, n = unused bytes
            return [_frame(command, index, sub, payload)]
        # Segmented (MDi-S1-C manual table 2.33): 41h with the size in bytes 4–7.
        self._transfer = _Transfer(_Phase.SEGMENT_UPLOAD, index, sub, now, data=bytearray(payload))
        return [_frame(0x41, index, sub, len(payload).to_bytes(4, "little"))]

    def _upload_segment(self, data: bytes, now: float) -> list[bytes]:
        transfer = self._expect(_Phase.SEGMENT_UPLOAD, now)
        toggle = data[0] & TOGGLE
        if toggle != transfer.toggle:
            raise SdoAbort(TOGGLE_NOT_ALTERNATED)
        transfer.toggle ^= TOGGLE
        chunk = bytes(transfer.data[transfer.offset : transfer.offset + SEGMENT_DATA])
        transfer.offset += len(chunk)
        last = transfer.offset >= len(transfer.data)
        if last:
            self._transfer = None
        # MDi-S1-C manual tables 2.34/2.35: t bit, n = unused bytes, c = last segment
        command = toggle | (SEGMENT_DATA - len(chunk)) << 1 | (LAST_SEGMENT if last else 0)
        return [(bytes([command]) + chunk).ljust(FRAME_LENGTH, b"\0")]

    # ----------------------------------------------------------------------------------- block

    def _block_download(self, data: bytes, now: float) -> list[bytes]:
        if (data[0] & 0x01) == 0:  # initiate block download
            index, sub = self._start(data)
            size = int.from_bytes(data[4:8], "little") if data[0] & SIZE_INDICATED else None
            if size is not None and size > MAX_TRANSFER:
                raise SdoAbort(OUT_OF_MEMORY)
            crc = bool(data[0] & CRC_SUPPORTED)
            self._transfer = _Transfer(_Phase.BLOCK_DOWNLOAD, index, sub, now, size=size, crc=crc)
            return [_frame(0xA0 | CRC_SUPPORTED, index, sub, bytes([MAX_BLOCK_SIZE]))]
        # end block download: n = bytes of the last segment without data, then the CRC
        transfer = self._expect(_Phase.BLOCK_DOWNLOAD_END, now)
        self._transfer = None
        unused = (data[0] >> 2) & 0x7
        payload = bytes(transfer.data[: len(transfer.data) - unused])
        if transfer.size is not None and len(payload) != transfer.size:
            raise SdoAbort(TYPE_MISMATCH, "block data does not match the indicated size")
        if transfer.crc and int.from_bytes(data[1:3], "little") != crc16(payload):
            raise SdoAbort(CRC_ERROR)
        self._objects.write_bytes(transfer.index, transfer.subindex, payload)
        return [bytes([0xA1]).ljust(FRAME_LENGTH, b"\0")]

    def _block_segment(self, transfer: _Transfer, data: bytes, now: float) -> list[bytes]:
        seqno = data[0] & 0x7F
        if seqno != transfer.seqno + 1:
            raise SdoAbort(INVALID_SEQUENCE, f"segment {seqno} after {transfer.seqno}")
        transfer.last = now
        transfer.seqno = seqno
        transfer.data += data[1:FRAME_LENGTH]
        if len(transfer.data) > MAX_TRANSFER + SEGMENT_DATA:
            raise SdoAbort(OUT_OF_MEMORY)
        last = bool(data[0] & LAST_BLOCK_SEGMENT)
        if not last and seqno < transfer.blksize:
            return []
        transfer.seqno = 0
        if last:
            transfer.phase = _Phase.BLOCK_DOWNLOAD_END
        # block acknowledge: ackseq = last good segment, blksize for the next block
        return [bytes([0xA2, seqno, transfer.blksize]).ljust(FRAME_LENGTH, b"\0")]

    def _block_upload(self, data: bytes, now: float) -> list[bytes]:
        cs = data[0] & 0x03
        if cs == BlockUploadCs.INITIATE:
            index, sub = self._start(data)
            blksize = data[4]
            if not 1 <= blksize <= MAX_BLOCK_SIZE:
                raise SdoAbort(INVALID_BLOCK_SIZE)
            payload = self._objects.read_bytes(index, sub)
            # Byte 5 (protocol switch threshold) is ignored: the server always uses block upload.
            self._transfer = _Transfer(
                _Phase.BLOCK_UPLOAD_START,
                index,
                sub,
                now,
                data=bytearray(payload),
                blksize=blksize,
            )
            command = 0xC0 | CRC_SUPPORTED | EXPEDITED  # sc = 1, s = 1 (size indicated)
            return [_frame(command, index, sub, len(payload).to_bytes(4, "little"))]
        if cs == BlockUploadCs.START:
            transfer = self._expect(_Phase.BLOCK_UPLOAD_START, now)
            transfer.phase = _Phase.BLOCK_UPLOAD_ACK
            return self._send_block(transfer)
        if cs == BlockUploadCs.ACK:
            transfer = self._expect(_Phase.BLOCK_UPLOAD_ACK, now)
            return self._block_acknowledged(transfer, ackseq=data[1], blksize=data[2])
        self._expect(_Phase.BLOCK_UPLOAD_END, now)  # the client confirms the end: done
        self._transfer = None
        return []

    def _block_acknowledged(self, transfer: _Transfer, *, ackseq: int, blksize: int) -> list[bytes]:
        if ackseq > transfer.sent:
            raise SdoAbort(INVALID_SEQUENCE, f"ack of segment {ackseq} of {transfer.sent}")
        if not 1 <= blksize <= MAX_BLOCK_SIZE:
            raise SdoAbort(INVALID_BLOCK_SIZE)
        transfer.blksize = blksize
        if transfer.final_sent and ackseq == transfer.sent:
            transfer.phase = _Phase.BLOCK_UPLOAD_END
            size = len(transfer.data)
            in_last = size - SEGMENT_DATA * ((size - 1) // SEGMENT_DATA) if size else 0
            # Always a real CRC: canopen's client checks it whenever the server announced sc=1.
            crc = crc16(bytes(transfer.data))
            command = 0xC1 | (SEGMENT_DATA - in_last) << 2  # end, n = unused bytes
            return [bytes([command]) + crc.to_bytes(2, "little") + bytes(5)]
        # Segments after ackseq were lost: the next block starts right after the last good one.
        transfer.offset += ackseq * SEGMENT_DATA
        return self._send_block(transfer)

    def _send_block(self, transfer: _Transfer) -> list[bytes]:
        segments: list[bytes] = []
        position = transfer.offset
        final = False
        while len(segments) < transfer.blksize and not final:
            chunk = bytes(transfer.data[position : position + SEGMENT_DATA])
            position += len(chunk)
            final = position >= len(transfer.data)
            command = (len(segments) + 1) | (LAST_BLOCK_SEGMENT if final else 0)
            segments.append((bytes([command]) + chunk).ljust(FRAME_LENGTH, b"\0"))
        transfer.sent = len(segments)
        transfer.final_sent = final
        return segments
