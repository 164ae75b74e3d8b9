"""CiA 301 basic data types: codes, sizes and value ranges (CiA 301 data type codes)."""

from __future__ import annotations

import struct
from enum import IntEnum


class DataType(IntEnum):
    BOOLEAN = 0x01
    INTEGER8 = 0x02
    INTEGER16 = 0x03
    INTEGER32 = 0x04
    UNSIGNED8 = 0x05
    UNSIGNED16 = 0x06
    UNSIGNED32 = 0x07
    REAL32 = 0x08
    VISIBLE_STRING = 0x09
    OCTET_STRING = 0x0A
    UNICODE_STRING = 0x0B
    TIME_OF_DAY = 0x0C
    TIME_DIFFERENCE = 0x0D
    DOMAIN = 0x0F
    INTEGER24 = 0x10
    REAL64 = 0x11
    INTEGER40 = 0x12
    INTEGER48 = 0x13
    INTEGER56 = 0x14
    INTEGER64 = 0x15
    UNSIGNED24 = 0x16
    UNSIGNED40 = 0x18
    UNSIGNED48 = 0x19
    UNSIGNED56 = 0x1A
    UNSIGNED64 = 0x1B


_SIGNED_BITS: dict[int, int] = {
    DataType.INTEGER8: 8,
    DataType.INTEGER16: 16,
    DataType.INTEGER24: 24,
    DataType.INTEGER32: 32,
    DataType.INTEGER40: 40,
    DataType.INTEGER48: 48,
    DataType.INTEGER56: 56,
    DataType.INTEGER64: 64,
}
_UNSIGNED_BITS: dict[int, int] = {
    DataType.BOOLEAN: 1,
    DataType.UNSIGNED8: 8,
    DataType.UNSIGNED16: 16,
    DataType.UNSIGNED24: 24,
    DataType.UNSIGNED32: 32,
    DataType.UNSIGNED40: 40,
    DataType.UNSIGNED48: 48,
    DataType.UNSIGNED56: 56,
    DataType.UNSIGNED64: 64,
}
FLOAT_TYPES = frozenset({DataType.REAL32, DataType.REAL64})
TEXT_TYPES = frozenset({DataType.VISIBLE_STRING, DataType.UNICODE_STRING})
# TIME_OF_DAY / TIME_DIFFERENCE are 6-byte structures: handled as raw bytes like OCTET_STRING
BYTES_TYPES = frozenset(
    {DataType.OCTET_STRING, DataType.DOMAIN, DataType.TIME_OF_DAY, DataType.TIME_DIFFERENCE}
)
REAL32_MAX = 3.4028234663852886e38


def is_integer(data_type: int) -> bool:
    return data_type in _SIGNED_BITS or data_type in _UNSIGNED_BITS


def is_signed(data_type: int) -> bool:
    return data_type in _SIGNED_BITS


def is_float(data_type: int) -> bool:
    return data_type in FLOAT_TYPES


def is_text(data_type: int) -> bool:
    return data_type in TEXT_TYPES


def is_bytes(data_type: int) -> bool:
    return data_type in BYTES_TYPES


def is_known(data_type: int) -> bool:
    return data_type in DataType._value2member_map_


def int_bits(data_type: int) -> int:
    """Width in bits of an integer type (BOOLEAN counts as 1); 0 for anything else."""
    return _SIGNED_BITS.get(data_type, 0) or _UNSIGNED_BITS.get(data_type, 0)


def bit_size(data_type: int) -> int | None:
    """Size in a PDO, in bits; None for variable-length types (strings, domains)."""
    if data_type == DataType.BOOLEAN:
        return 1
    if is_integer(data_type):
        return int_bits(data_type)
    if data_type == DataType.REAL32:
        return 32
    if data_type == DataType.REAL64:
        return 64
    if data_type in (DataType.TIME_OF_DAY, DataType.TIME_DIFFERENCE):
        return 48
    return None


def int_range(data_type: int) -> tuple[int, int]:
    """Inclusive range of an integer type. Raises ValueError for non-integer types."""
    if data_type in _SIGNED_BITS:
        bits = _SIGNED_BITS[data_type]
        return -(1 << (bits - 1)), (1 << (bits - 1)) - 1
    if data_type in _UNSIGNED_BITS:
        return 0, (1 << _UNSIGNED_BITS[data_type]) - 1
    raise ValueError(f"data type 0x{data_type:04X} is not an integer type")


def as_real32(value: float) -> float:
    """The nearest value a REAL32 can hold (what the drive stores for 12.345)."""
    return float(struct.unpack("<f", struct.pack("<f", value))[0])


def type_name(data_type: int) -> str:
    """`UNSIGNED16` for 0x0006; `0x0040` for codes that are not CiA 301 basic types."""
    if is_known(data_type):
        return DataType(data_type).name
    return f"0x{data_type:04X}"
