"""SDO frames (CiA 301 §7.2.4.3): what the app's bus listeners, its log decoder, the scan's
sweep, the IP stream and the simulated drives' SDO server all build or recognise, written once.
The abort codes themselves are in sdo_abort.py."""

from __future__ import annotations

from enum import IntEnum

# byte 0 of an abort frame, client or server (command specifier 4 in bits 5–7); bytes 1–2 are
# the index (little-endian), byte 3 the sub-index, bytes 4–7 the abort code (little-endian)
ABORT_COMMAND = 0x80
UPLOAD_COMMAND = 0x40  # initiate upload request: ccs 2, nothing else in byte 0


class Ccs(IntEnum):
    """Client command specifier: bits 7–5 of byte 0 of a request."""

    DOWNLOAD_SEGMENT = 0
    INITIATE_DOWNLOAD = 1
    INITIATE_UPLOAD = 2
    UPLOAD_SEGMENT = 3
    ABORT = 4
    BLOCK_UPLOAD = 5
    BLOCK_DOWNLOAD = 6


class Scs(IntEnum):
    """Server command specifier: bits 7–5 of byte 0 of a response."""

    UPLOAD_SEGMENT = 0
    DOWNLOAD_SEGMENT = 1
    INITIATE_UPLOAD = 2
    INITIATE_DOWNLOAD = 3
    ABORT = 4
    BLOCK_DOWNLOAD = 5
    BLOCK_UPLOAD = 6


def command_specifier(data: bytes) -> int:
    """Bits 7–5 of byte 0 (client or server)."""
    return data[0] >> 5


def address(index: int, subindex: int) -> bytes:
    """The multiplexer of an initiate or abort frame: index little-endian, then sub-index."""
    return index.to_bytes(2, "little") + bytes([subindex])


def multiplexer(data: bytes) -> tuple[int, int]:
    """(index, subindex) of an initiate or abort frame (bytes 1–3)."""
    return int.from_bytes(data[1:3], "little"), data[3]


def upload_request(index: int, subindex: int) -> bytes:
    """An expedited-or-segmented upload's initiate request (a read)."""
    return bytes([UPLOAD_COMMAND]) + address(index, subindex) + bytes(4)


def expedited_download(index: int, subindex: int, size: int) -> bytes:
    """The first 4 bytes of an expedited download of `size` (1–4) data bytes: ccs 1, e = 1,
    s = 1, n = 4 − size unused bytes (23h for 4 bytes, 2Fh for 1)."""
    if not 1 <= size <= 4:
        raise ValueError(f"an expedited download carries 1 to 4 bytes, not {size}")
    return bytes([0x23 | (4 - size) << 2]) + address(index, subindex)


def abort_frame(index: int, subindex: int, code: int) -> bytes:
    """`80 idx_lo idx_hi sub` + abort code, little-endian (CiA 301 §7.2.4.3.17)."""
    return bytes([ABORT_COMMAND]) + address(index, subindex) + code.to_bytes(4, "little")


def parse_abort(data: bytes) -> tuple[int, int, int] | None:
    """(index, subindex, abort code) of an abort frame; None for any other frame."""
    if len(data) < 8 or data[0] != ABORT_COMMAND:
        return None
    index, subindex = multiplexer(data)
    return index, subindex, int.from_bytes(data[4:8], "little")


def starts_download(data: bytes) -> bool:
    """The request starts a write: an expedited or segmented download's initiate, or a block
    download's initiate (client subcommand 0)."""
    if len(data) < 4:
        return False
    ccs = command_specifier(data)
    return ccs == Ccs.INITIATE_DOWNLOAD or (ccs == Ccs.BLOCK_DOWNLOAD and data[0] & 0x01 == 0)
