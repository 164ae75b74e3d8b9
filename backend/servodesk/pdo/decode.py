"""Received PDO payload -> typed values, using the PDO's mapping and the node's dictionary.

Built once per mapping, used per frame: the scope decodes every TPDO of a running drive with it,
so all the lookups (type, sign bit, mask, float layout) happen in the constructor and `decode`
only shifts, masks and converts.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum

from servodesk.od import datatypes as dt
from servodesk.od.model import ObjectDictionaryModel
from servodesk.pdo.model import MappedObject
from servodesk.pdo.validate import object_label
from servodesk_protocol import cia402
from servodesk_protocol.pdo import DUMMY_BITS

_REAL32 = struct.Struct("<f")
_REAL64 = struct.Struct("<d")


@dataclass(frozen=True)
class Field:
    """Where one mapped object sits in the payload and what it is."""

    index: int
    subindex: int
    name: str | None
    bit_offset: int
    bits: int
    data_type: int | None  # None when the dictionary does not know the object
    unit: str


@dataclass(frozen=True)
class Decoded:
    index: int
    subindex: int
    name: str | None
    value: int | float | bool
    raw: int  # the field's bits as an unsigned number
    unit: str
    bits: int  # the field's length in the frame

    @property
    def raw_bytes(self) -> bytes:
        """The field's bytes in frame order (little-endian; a bit field padded to whole bytes)."""
        return self.raw.to_bytes((self.bits + 7) // 8, "little")


class _Kind(Enum):
    UNSIGNED = "unsigned"
    SIGNED = "signed"
    BOOLEAN = "boolean"
    REAL32 = "real32"
    REAL64 = "real64"


class PdoDecoder:
    """Decodes the payloads of one PDO mapping; `od` None decodes every field raw unsigned."""

    def __init__(self, mapping: Sequence[MappedObject], od: ObjectDictionaryModel | None) -> None:
        fields: list[Field] = []
        offset = 0
        for obj in mapping:
            if obj.index not in DUMMY_BITS:  # dummies only fill a gap
                sub = od.get(obj.index, obj.subindex) if od is not None else None
                name = obj.name if obj.name is not None else sub.name if sub else None
                data_type = sub.data_type if sub else None
                fields.append(
                    Field(
                        obj.index,
                        obj.subindex,
                        name,
                        offset,
                        obj.bits,
                        data_type,
                        sub.unit if sub else "",
                    )
                )
            offset += obj.bits
        self.fields: tuple[Field, ...] = tuple(fields)
        self.total_bits = offset
        self.length = (offset + 7) // 8  # bytes a frame must carry at least
        # per field: (offset, mask, kind, sign bit) — what decode needs, nothing else
        self._plan = tuple(
            (f.bit_offset, (1 << f.bits) - 1, _kind(f.data_type, f.bits), 1 << (f.bits - 1))
            for f in self.fields
        )

    def values(self, data: bytes) -> list[int | float | bool]:
        """The fields' values in mapping order (the scope's fast path: no Decoded objects)."""
        self._check(data)
        payload = int.from_bytes(data[: self.length], "little")
        out: list[int | float | bool] = []
        for offset, mask, kind, sign in self._plan:
            out.append(_convert((payload >> offset) & mask, kind, sign))
        return out

    def decode(self, data: bytes) -> list[Decoded]:
        """Every mapped object of `data` (a frame may be longer than the mapping)."""
        self._check(data)
        payload = int.from_bytes(data[: self.length], "little")
        out: list[Decoded] = []
        for field, (offset, mask, kind, sign) in zip(self.fields, self._plan, strict=True):
            raw = (payload >> offset) & mask
            value = _convert(raw, kind, sign)
            out.append(
                Decoded(field.index, field.subindex, field.name, value, raw, field.unit, field.bits)
            )
        return out

    def _check(self, data: bytes) -> None:
        if len(data) < self.length:
            objects = ", ".join(object_label(f.index, f.subindex, f.name) for f in self.fields)
            raise ValueError(
                f"PDO frame has {len(data)} byte(s) but its mapping needs {self.length}"
                f" ({self.total_bits} bits: {objects})"
            )


def _kind(data_type: int | None, bits: int) -> _Kind:
    if data_type is None:
        return _Kind.UNSIGNED
    if data_type == dt.DataType.BOOLEAN:
        return _Kind.BOOLEAN
    if dt.is_signed(data_type):
        return _Kind.SIGNED
    # a float mapped with another length than its own cannot be read as a float
    if data_type == dt.DataType.REAL32 and bits == 32:
        return _Kind.REAL32
    if data_type == dt.DataType.REAL64 and bits == 64:
        return _Kind.REAL64
    return _Kind.UNSIGNED


def _convert(raw: int, kind: _Kind, sign: int) -> int | float | bool:
    if kind is _Kind.UNSIGNED:
        return raw
    if kind is _Kind.SIGNED:
        return raw - (sign << 1) if raw & sign else raw
    if kind is _Kind.BOOLEAN:
        return bool(raw)
    if kind is _Kind.REAL32:
        value: float = _REAL32.unpack(raw.to_bytes(4, "little"))[0]
        return value
    value = _REAL64.unpack(raw.to_bytes(8, "little"))[0]
    return value


# statusword bits worth naming beside the state (bits 0–3, 5, 6 are the state; bit 9 remote is
# set on every drive the master controls, and naming it in every frame would only be noise)
_STATUS_BITS = (
    (cia402.SW_VOLTAGE_ENABLED, "voltage enabled"),
    (cia402.SW_WARNING, "warning"),
    (cia402.SW_TARGET_REACHED, "target reached"),
    (cia402.SW_INTERNAL_LIMIT, "internal limit active"),
    (cia402.SW_MODE_BIT12, "mode bit 12"),
    (cia402.SW_MODE_BIT13, "mode bit 13"),
)


def statusword_text(statusword: int) -> str:
    """6041h in words: the CiA 402 state, then the notable bits set
    ("Switch on disabled · voltage enabled")."""
    try:
        state = cia402.decode_state(statusword).name.replace("_", " ").capitalize()
    except ValueError:
        state = "no CiA 402 state"
    return " · ".join([state, *(words for bit, words in _STATUS_BITS if statusword & bit)])


def value_text(index: int, subindex: int, value: int | float | bool) -> str | None:
    """A decoded value in words where CiA 402 gives it one: 6041h the state and notable bits,
    6060h/6061h the mode; None for everything else."""
    if subindex != 0 or not isinstance(value, int) or isinstance(value, bool):
        return None
    if index == cia402.STATUSWORD:
        return statusword_text(value)
    if index in (cia402.MODES_OF_OPERATION, cia402.MODES_DISPLAY):
        return cia402.mode_name(value)
    return None
