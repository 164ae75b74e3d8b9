"""Typed SDO read and write of single entries (GET/PUT /api/nodes/{node}/sdo/{index}/{sub}).

Values are decoded and checked with the node's object dictionary; input that cannot be written
is refused before a frame is sent. SDO aborts arrive as SdoAbortError from the node session.
"""

from __future__ import annotations

import struct
from collections.abc import Callable

from servodesk.audit.entry import current_entry
from servodesk.errors import InvalidValueError
from servodesk.models.sdo import SdoValue
from servodesk.nodes.access import NodeAccess
from servodesk.nodes.heartbeat_floor import check_heartbeat_time
from servodesk.nodes.identity import PRODUCER_HEARTBEAT
from servodesk.nodes.write_step import WriteStep
from servodesk.od import ObjectDictionaryModel
from servodesk.od import datatypes as dt
from servodesk.sdo import codec


def where(index: int, subindex: int) -> str:
    return f"{index:04X}h:{subindex:02X}h"


def sdo_value(
    node: int, model: ObjectDictionaryModel, index: int, subindex: int, data: bytes
) -> SdoValue:
    """The API view of bytes uploaded from (or downloaded to) one entry."""
    sub = model.get(index, subindex)
    if sub is None:
        unknown = codec.decode_unknown(data)
        return SdoValue(
            node=node,
            index=index,
            subindex=subindex,
            value=codec.api_value(unknown),
            raw_hex=codec.hex_bytes(data),
            text=codec.display_text(None, unknown, size=len(data)),
        )
    value = codec.decode(sub, data)
    return SdoValue(
        node=node,
        index=index,
        subindex=subindex,
        name=codec.entry_name(model, sub),
        data_type_name=dt.type_name(sub.data_type),
        value=codec.api_value(value),
        raw_hex=codec.hex_bytes(data),
        text=codec.display_text(sub, value, size=len(data)),
    )


WriteListener = Callable[[int, int, int], None]  # (node, index, sub-index)


class SdoService:
    def __init__(self, access: NodeAccess, *, on_write: WriteListener | None = None) -> None:
        self._access = access
        # told of every write that may have reached the device (the PDO cache drops a node's
        # PDOs on a write to 1400h–1BFFh), also when it failed part-way
        self._on_write = on_write

    async def read(self, node: int, index: int, subindex: int) -> SdoValue:
        session = self._access.session(node)
        data = await session.upload(index, subindex)
        return sdo_value(node, self._access.od(node), index, subindex, data)

    async def write(
        self,
        node: int,
        index: int,
        subindex: int,
        value: int | float | str,
        size: int | None = None,
        *,
        confirm: bool = False,
    ) -> SdoValue:
        """Check and encode `value`, download it, and return the entry as read back.

        An entry unknown to the dictionary takes raw hex bytes ("E8 03 00 00") or an integer
        with `size` 1, 2 or 4; `size` is ignored for known entries (their type decides).
        A heartbeat time (1017h) below the floor needs `confirm`, as on the heartbeat route.
        """
        session = self._access.session(node)
        model = self._access.od(node)
        data = self.encode(model, index, subindex, value, size)
        if (index, subindex) == (PRODUCER_HEARTBEAT, 0):
            check_heartbeat_time(node, int.from_bytes(data[:2], "little"), confirm=confirm)
        sub = model.get(index, subindex)
        readable = sub is None or sub.access != "wo"
        # The audit entry of a single write names its object and the value it replaces (what
        # an undo writes back), read in the same step as the write and its read-back: a
        # parallel write cannot land in between, so entries chain old → new without gaps.
        entry = current_entry()
        if entry is None or not entry.records_object():
            entry = None
        seen = WriteStep()
        read_first = entry is not None and readable
        try:
            back = await session.write_and_read(
                index, subindex, data, read_back=readable, read_first=read_first, seen=seen
            )
        finally:
            if self._on_write is not None:
                self._on_write(node, index, subindex)
            if entry is not None:
                old = self._decoded(node, model, index, subindex, seen.before)
                entry.set_object(index, subindex, old)
                if entry.action == "sdo-write":  # a parameter or an undo words its own entry
                    was = f"{old} → " if old is not None else ""
                    entry.what = f"write node {node} {where(index, subindex)}: {was}{value}"
        written = sdo_value(node, model, index, subindex, data if back is None else back)
        if entry is not None:
            entry.new = written.value
            if entry.action == "sdo-write":
                was = f"{entry.old} → " if entry.old is not None else ""
                entry.what = f"write node {node} {where(index, subindex)}: {was}{written.text}"
        return written

    @staticmethod
    def _decoded(
        node: int, model: ObjectDictionaryModel, index: int, subindex: int, data: bytes | None
    ) -> int | float | str | None:
        if data is None:
            return None  # unreadable before the write: the entry says old unknown
        try:
            return sdo_value(node, model, index, subindex, data).value
        except (ValueError, struct.error):
            return None  # bytes the dictionary cannot decode: old unknown, as unreadable

    @staticmethod
    def encode(
        model: ObjectDictionaryModel,
        index: int,
        subindex: int,
        value: int | float | str,
        size: int | None = None,
    ) -> bytes:
        """The bytes to download for `value`; InvalidValueError if it cannot be written."""
        place = where(index, subindex)
        sub = model.get(index, subindex)
        if sub is None:
            return codec.coerce_unknown(value, size, place)
        typed = codec.coerce(sub, value, place)
        try:
            return codec.encode(sub, typed)
        except (ValueError, UnicodeEncodeError) as error:
            raise InvalidValueError(f"{place}: {error}") from None
