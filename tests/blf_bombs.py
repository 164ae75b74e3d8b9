"""Hostile BLF files, made byte by byte: a valid file header, then LOG_CONTAINER objects whose
zlib data expands far past the size each declares, the first CAN object inside claiming 4 GB.
Used by the log tests (small) and bench/hostile_inputs.py (200 MB per container)."""

from __future__ import annotations

import zlib

from can.io.blf import (
    CAN_MESSAGE,
    FILE_HEADER_SIZE,
    FILE_HEADER_STRUCT,
    LOG_CONTAINER,
    LOG_CONTAINER_STRUCT,
    OBJ_HEADER_BASE_STRUCT,
    ZLIB_DEFLATE,
)

FOUR_GB = 0xFFFFFFFF
REAL_CONTAINER = 128 * 1024  # what python-can and Vector's tools declare per container
_CHUNK = 1024 * 1024


def file_header(object_count: int = 0) -> bytes:
    fields = FILE_HEADER_STRUCT.pack(
        b"LOGG", FILE_HEADER_SIZE, 0, 0, 0, 0, 2, 6, 8, 1, 0, 0, object_count, 0, *[0] * 16
    )
    return fields + bytes(FILE_HEADER_SIZE - len(fields))


def header(size: int = FILE_HEADER_SIZE) -> bytes:
    """A file header that claims `size` bytes for itself."""
    return b"LOGG" + size.to_bytes(4, "little") + file_header()[8:]


def obj(obj_type: int, body: bytes, *, claim: int | None = None) -> bytes:
    """A top-level object: its header (claiming `claim` bytes, its true size by default)."""
    size = OBJ_HEADER_BASE_STRUCT.size + len(body)
    head = OBJ_HEADER_BASE_STRUCT.pack(b"LOBJ", 16, 1, size if claim is None else claim, obj_type)
    return head + body + bytes(size % 4)


def container(zdata: bytes, declared: int, *, claim: int | None = None) -> bytes:
    return obj(
        LOG_CONTAINER, LOG_CONTAINER_STRUCT.pack(ZLIB_DEFLATE, declared) + zdata, claim=claim
    )


def inner_claim(claim: int = FOUR_GB) -> bytes:
    """The header of a CAN object inside a container that claims `claim` bytes."""
    return OBJ_HEADER_BASE_STRUCT.pack(b"LOBJ", 32, 1, claim, CAN_MESSAGE)


def deflate(prefix: bytes, zeros: int) -> bytes:
    """zlib data of `prefix` then `zeros` zero bytes, compressed a megabyte at a time."""
    packer = zlib.compressobj(9)
    out = [packer.compress(prefix)]
    left = zeros
    block = bytes(_CHUNK)
    while left > 0:
        out.append(packer.compress(block[: min(left, _CHUNK)]))
        left -= _CHUNK
    out.append(packer.flush())
    return b"".join(out)


def zlib_bomb(expands_to: int, containers: int, declared: int = REAL_CONTAINER) -> bytes:
    """`containers` containers each declaring `declared` bytes and expanding to `expands_to`
    zeros; the first object of the first claims 4 GB."""
    first = deflate(inner_claim(), expands_to - OBJ_HEADER_BASE_STRUCT.size)
    rest = deflate(b"", expands_to)
    parts = [file_header(containers), container(first, declared)]
    parts += [container(rest, declared) for _ in range(containers - 1)]
    return b"".join(parts)
