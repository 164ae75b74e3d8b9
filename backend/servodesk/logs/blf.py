"""BLF files read with bounds: a damaged or hostile file is refused, never expanded in memory.

A BLF file is a header, then objects; a LOG_CONTAINER object holds zlib data that expands to
the CAN objects (usually 128 kB per container). python-can's BLFReader trusts every size it
reads: it decompresses a container whole, however far it expands (a 0.8 MB file can claim
gigabytes), and keeps an object that claims to continue into the next container in a tail
that grows by each container. `BoundedBlfReader` refuses a size beyond any real file's and
stops decompressing at the size a container declares.
"""

from __future__ import annotations

import struct
import zlib
from collections.abc import Generator
from pathlib import Path
from typing import Any, BinaryIO

from can import Message
from can.io.blf import (
    FILE_HEADER_STRUCT,
    LOG_CONTAINER,
    LOG_CONTAINER_STRUCT,
    NO_COMPRESSION,
    OBJ_HEADER_BASE_STRUCT,
    ZLIB_DEFLATE,
    BLFParseError,
    BLFReader,
)

# Vector's tools and python-can write containers of 128 kB; 32 times that is no real file.
MAX_CONTAINER = 4 * 1024 * 1024
MAX_OBJECT = MAX_CONTAINER + 64 * 1024  # a top-level object: a container's zlib data + header
MAX_FILE_HEADER = 64 * 1024  # the header is 144 bytes in every known version
_HEADER_PREFIX = struct.Struct("<4sL")  # signature, header size


class LogBoundsError(ValueError):
    """The file declares (or expands to) sizes no real log has: damaged or made to hurt."""

    def __init__(self, what: str) -> None:
        super().__init__(f"damaged or hostile BLF file: {what}; nothing was decoded")


def check_file_header(file: BinaryIO) -> int:
    """The file header's size; refused beyond any real one (python-can reads that much to skip
    it, and all of the file for a size below its own). The file is left at its start."""
    prefix = file.read(_HEADER_PREFIX.size)
    file.seek(0)
    if len(prefix) < _HEADER_PREFIX.size or prefix[:4] != b"LOGG":
        return FILE_HEADER_STRUCT.size  # not a BLF file: python-can says so
    size = int(_HEADER_PREFIX.unpack(prefix)[1])
    if not FILE_HEADER_STRUCT.size <= size <= MAX_FILE_HEADER:
        raise LogBoundsError(f"its header claims {size} bytes")
    return size


class BoundedBlfReader(BLFReader):
    """python-can's BLFReader with every size bounded. A subclass, not a new reader: the object
    parsing (`_parse_container`) is python-can's; only its loop over the file's objects is done
    again here, because that loop is where the sizes are trusted and it has no hook."""

    def __init__(self, file: Path | BinaryIO, **kwargs: Any) -> None:
        if isinstance(file, Path):
            with file.open("rb") as peek:
                header_size = check_file_header(peek)
        else:
            header_size = check_file_header(file)
        super().__init__(file, **kwargs)
        self._offset = header_size  # where the next object starts, for the messages

    def __iter__(self) -> Generator[Message, None, None]:
        container = 0
        while True:
            start = self._offset
            head = self.file.read(OBJ_HEADER_BASE_STRUCT.size)
            if not head:
                break
            if len(head) < OBJ_HEADER_BASE_STRUCT.size:
                raise BLFParseError(f"the file ends inside an object header at byte {start}")
            signature, _, _, obj_size, obj_type = OBJ_HEADER_BASE_STRUCT.unpack(head)
            if signature != b"LOBJ":
                raise BLFParseError(f"no object at byte {start}")
            where = f"object at byte {start}"
            if obj_type == LOG_CONTAINER:
                container += 1
                where = f"container {container} (byte {start})"
            if not OBJ_HEADER_BASE_STRUCT.size <= obj_size <= MAX_OBJECT:
                raise LogBoundsError(f"{where} claims {obj_size} bytes")
            body = self.file.read(obj_size - OBJ_HEADER_BASE_STRUCT.size)
            padding = self.file.read(obj_size % 4)
            self._offset += len(head) + len(body) + len(padding)
            if obj_type != LOG_CONTAINER:
                continue
            data = _unpack_container(body, where)
            if data is not None:
                yield from self._parse_container(data)
                _check_tail(self._tail, where)
        self.stop()


def _unpack_container(body: bytes, where: str) -> bytes | None:
    """The container's objects, decompressed to at most the size it declares (None: a
    compression this reader does not know, skipped as python-can skips it)."""
    method, declared = LOG_CONTAINER_STRUCT.unpack_from(body)
    if declared > MAX_CONTAINER:
        raise LogBoundsError(f"{where} declares {declared} bytes uncompressed")
    payload = body[LOG_CONTAINER_STRUCT.size :]
    if method == NO_COMPRESSION:
        return payload
    if method != ZLIB_DEFLATE:
        return None
    data = zlib.decompressobj().decompress(payload, declared + 1)
    if len(data) > declared:
        raise LogBoundsError(f"{where} expands past the {declared} bytes it declares")
    return data


def _check_tail(tail: bytes, where: str) -> None:
    """An object that goes on into the next container: refused once it claims more than a
    container holds (python-can would keep joining containers to it)."""
    at = tail.find(b"LOBJ", 0, 8)  # objects start 4-byte aligned: up to 8 bytes of padding
    if at >= 0 and len(tail) >= at + OBJ_HEADER_BASE_STRUCT.size:
        claimed = OBJ_HEADER_BASE_STRUCT.unpack_from(tail, at)[3]
        if claimed > MAX_CONTAINER:
            raise LogBoundsError(f"an object in {where} claims {claimed} bytes")
    if len(tail) > MAX_CONTAINER:
        raise LogBoundsError(f"an object in {where} runs on past {MAX_CONTAINER} bytes")
