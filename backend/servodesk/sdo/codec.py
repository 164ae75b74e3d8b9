"""Raw SDO bytes <-> typed values of one object entry, and the texts the UI shows for them.

Pure functions: the services upload/download bytes through a node session and use these to turn
them into values (CiA 301 data types, little-endian) and back, refusing bad input before any
frame is sent.
"""

from __future__ import annotations

import re
import struct

from servodesk.errors import InvalidValueError
from servodesk.models.base import Value as ApiValue
from servodesk.od import DataType, ObjectDictionaryModel, OdSub, format_value, parse_value
from servodesk.od import datatypes as dt
from servodesk.od.model import Value as OdValue

# An entry the dictionary does not know is shown as a number when it fits a 32-bit register.
UNKNOWN_INT_MAX_BYTES = 4
UNKNOWN_SIZES = (1, 2, 4)
_INT_TEXT = re.compile(r"[+-]?(0[xX][0-9A-Fa-f]+|0[bB][01]+|[0-9]+)")


def entry_name(model: ObjectDictionaryModel, sub: OdSub) -> str:
    """`Device name` for a VAR, `Identity object: Vendor-ID` for a sub-entry of a record."""
    obj = model.objects.get(sub.index)
    if obj is None or obj.object_type in ("var", "domain"):
        return sub.name
    return f"{obj.name}: {sub.name}"


def type_size(data_type: int) -> int | None:
    """Bytes an entry of this type takes on the wire; None for variable-length types."""
    if data_type == DataType.BOOLEAN:
        return 1
    bits = dt.bit_size(data_type)
    return None if bits is None else bits // 8


# ----------------------------------------------------------------------------- decoding


def decode(sub: OdSub, data: bytes) -> OdValue:
    """Uploaded bytes -> value of `sub`'s type; raw bytes when they do not fit the type."""
    data_type = sub.data_type
    if dt.is_integer(data_type):
        size = type_size(data_type) or len(data)
        if not data:
            return data
        raw = data[:size]
        # a shorter answer than the type (some drives drop zero bytes) is read as it came
        return int.from_bytes(raw, "little", signed=dt.is_signed(data_type) and len(raw) == size)
    if data_type == DataType.REAL32 and len(data) >= 4:
        return float(struct.unpack_from("<f", data)[0])
    if data_type == DataType.REAL64 and len(data) >= 8:
        return float(struct.unpack_from("<d", data)[0])
    if data_type == DataType.VISIBLE_STRING:
        # CiA 301 VISIBLE_STRING is ASCII; trailing NULs are padding some drives add
        return data.rstrip(b"\x00").decode("ascii", errors="replace")
    if data_type == DataType.UNICODE_STRING:
        return data.decode("utf-16-le", errors="replace").rstrip("\x00")
    return data


def decode_unknown(data: bytes) -> int | bytes:
    """An entry the dictionary does not know: an unsigned number up to 4 bytes, else bytes."""
    if 0 < len(data) <= UNKNOWN_INT_MAX_BYTES:
        return int.from_bytes(data, "little")
    return data


def api_value(value: OdValue | None) -> ApiValue:
    """A value as the API sends it: bytes travel as hex strings ("E8 03 00 00")."""
    if isinstance(value, bytes):
        return hex_bytes(value)
    return value


def hex_bytes(data: bytes) -> str:
    return data.hex(" ").upper()


def display_text(sub: OdSub | None, value: OdValue | None, *, size: int | None = None) -> str:
    """Text for a value: integers as "0x0240 (576)", strings as they are, bytes as hex.

    `sub` None is an entry unknown to the dictionary; `size` is then its length in bytes.
    """
    if value is None:
        return ""
    if isinstance(value, bytes):
        return hex_bytes(value) if value else "(empty)"
    if isinstance(value, str):
        return value
    if isinstance(value, float):
        return format_value(sub, value) if sub and dt.is_float(sub.data_type) else repr(value)
    if sub is not None and sub.data_type == DataType.BOOLEAN:
        return "true" if value else "false"
    width = (type_size(sub.data_type) if sub is not None else None) or size or 4
    if value < 0:
        shown = value & ((1 << (8 * width)) - 1)  # the register's two's complement bits
        return f"0x{shown:0{2 * width}X} ({value})"
    return f"0x{value:0{2 * width}X} ({value})"


# ----------------------------------------------------------------------------- encoding


def coerce(sub: OdSub, value: int | float | str, where: str) -> OdValue:
    """User input -> a value of `sub`'s type, range-checked against the type and the
    dictionary's limits. InvalidValueError (naming `where`, e.g. "2006h:0Bh") if it cannot be.
    """
    data_type = sub.data_type
    try:
        if isinstance(value, str):
            return parse_value(sub, value)
        if dt.is_text(data_type):
            raise ValueError(f"{dt.type_name(data_type)} takes text, not a number")
        if dt.is_bytes(data_type) or not dt.is_known(data_type):
            raise ValueError(
                f"{dt.type_name(data_type)} takes hex bytes as a string, e.g. 'E8 03 00 00'"
            )
        if isinstance(value, float) and not dt.is_float(data_type):
            if not value.is_integer():
                raise ValueError(f"{dt.type_name(data_type)} takes whole numbers, not {value}")
            value = int(value)
        if isinstance(value, float):
            return parse_value(sub, repr(value))
        # decimal text of the number: parse_value then applies the type's and the file's limits
        return parse_value(sub, str(int(value)))
    except ValueError as error:
        raise InvalidValueError(f"{where}: {error}") from None


def encode(sub: OdSub, value: OdValue) -> bytes:
    """A value of `sub`'s type -> the bytes to download."""
    data_type = sub.data_type
    if isinstance(value, bytes):
        return value
    if isinstance(value, str):
        if data_type == DataType.UNICODE_STRING:
            return value.encode("utf-16-le")
        return value.encode("ascii", errors="strict")
    if dt.is_float(data_type):
        return struct.pack("<f" if data_type == DataType.REAL32 else "<d", float(value))
    if isinstance(value, float):
        raise ValueError(f"{dt.type_name(data_type)} cannot hold {value}")
    size = type_size(data_type)
    if size is None:
        raise ValueError(f"{dt.type_name(data_type)} cannot hold the number {value}")
    return int(value).to_bytes(size, "little", signed=value < 0)


def coerce_unknown(value: int | float | str, size: int | None, where: str) -> bytes:
    """Input for an entry the dictionary does not know: an integer with `size` 1/2/4, or a
    string of hex bytes (or decimal/hex text with `size`)."""
    if isinstance(value, str):
        text = value.strip()
        if size is None:
            digits = re.sub(r"[\s:_-]", "", text)
            digits = digits[2:] if digits[:2].lower() == "0x" else digits
            try:
                return bytes.fromhex(digits)
            except ValueError:
                raise InvalidValueError(
                    f"{where} is not in the object dictionary: give raw hex bytes such as "
                    f"'E8 03 00 00', or a number with a size of 1, 2 or 4 bytes"
                ) from None
        if _INT_TEXT.fullmatch(text) is None:
            raise InvalidValueError(f"{where}: '{value}' is not a whole number")
        value = _int_text(text)
    if isinstance(value, float):
        if not value.is_integer():
            raise InvalidValueError(f"{where}: only whole numbers can be written without a type")
        value = int(value)
    if size not in UNKNOWN_SIZES:
        raise InvalidValueError(
            f"{where} is not in the object dictionary: give the size (1, 2 or 4 bytes) "
            f"of the number, or the value as raw hex bytes"
        )
    bits = 8 * size
    if not -(1 << (bits - 1)) <= value < (1 << bits):
        raise InvalidValueError(f"{where}: {value} does not fit in {size} byte(s)")
    return (value & ((1 << bits) - 1)).to_bytes(size, "little")


def _int_text(text: str) -> int:
    """`31`, `0x1F`, `0b11`, `-0x10`, `007` (int(x, 0) refuses leading zeros)."""
    sign = -1 if text.startswith("-") else 1
    digits = text.lstrip("+-")
    base = {"0x": 16, "0b": 2}.get(digits[:2].lower(), 10)
    return sign * int(digits[2:] if base != 10 else digits, base)


# ----------------------------------------------------------------------------- comparing


def same_value(sub: OdSub, expected: OdValue | None, actual: OdValue | None) -> bool:
    """Whether a read-back value is the value that was meant (REAL32 at its own precision)."""
    if expected is None or actual is None:
        return expected is actual
    if isinstance(expected, int | float) and isinstance(actual, int | float):
        if sub.data_type == DataType.REAL32:
            return dt.as_real32(float(expected)) == dt.as_real32(float(actual))
        return expected == actual
    if isinstance(expected, str) and isinstance(actual, str):
        return expected.rstrip("\x00") == actual.rstrip("\x00")
    return expected == actual
