"""Value codec for user input: text typed into the UI <-> the value of one object entry.

Accepts what commissioning engineers type: `31`, `0x1F`, `0b11111`, `-5`, `1.5`, `true`, hex
bytes `C8 3D BB`. Every refusal is a ValueError whose message can be shown to the user as is.
Hex input on a signed type is a raw register value: `0xFFFF` on INTEGER16 is -1.
"""

from __future__ import annotations

import math
import re
import struct

from servodesk.od import datatypes as dt
from servodesk.od.model import OdSub, Value

_INT_INPUT = re.compile(r"([+-]?)(0[xX][0-9A-Fa-f]+|0[bB][01]+|[0-9]+)")
_TRUE = frozenset({"1", "true", "on", "yes"})
_FALSE = frozenset({"0", "false", "off", "no"})
_TIME_BYTES = 6  # TIME_OF_DAY / TIME_DIFFERENCE (CiA 301)


def parse_value(sub: OdSub, text: str) -> Value:
    """User text -> value for `sub`. Raises ValueError naming the type and the allowed range."""
    data_type = sub.data_type
    if data_type == dt.DataType.VISIBLE_STRING:
        bad = sorted({c for c in text if not 0x20 <= ord(c) <= 0x7E})
        if bad:
            shown = ", ".join(repr(c) for c in bad[:3])
            raise ValueError(f"VISIBLE_STRING takes printable ASCII only; remove {shown}")
        return text
    if data_type == dt.DataType.UNICODE_STRING:
        return text
    if dt.is_bytes(data_type) or not dt.is_known(data_type):
        return _parse_bytes(text, data_type)
    stripped = text.strip()
    if not stripped:
        raise ValueError(f"Enter a value for {dt.type_name(data_type)}")
    if data_type == dt.DataType.BOOLEAN:
        return _parse_bool(stripped)
    if dt.is_float(data_type):
        return _check_limits(sub, _parse_float(stripped, data_type))
    return _check_limits(sub, _parse_integer(stripped, data_type))


def format_value(sub: OdSub, value: object) -> str:
    """Value -> text that `parse_value` reads back to the same value."""
    data_type = sub.data_type
    if value is None:
        return ""
    if dt.is_text(data_type):
        if not isinstance(value, str):
            raise TypeError(
                f"{dt.type_name(data_type)} value must be str, not {type(value).__name__}"
            )
        return value
    if dt.is_bytes(data_type) or not dt.is_known(data_type):
        if not isinstance(value, bytes | bytearray):
            raise TypeError(
                f"{dt.type_name(data_type)} value must be bytes, not {type(value).__name__}"
            )
        return bytes(value).hex(" ").upper()
    if dt.is_float(data_type):
        if not isinstance(value, int | float) or isinstance(value, bool):
            raise TypeError(f"{dt.type_name(data_type)} value must be a number")
        return shortest_float(float(value), data_type)
    if not isinstance(value, int):
        raise TypeError(f"{dt.type_name(data_type)} value must be int, not {type(value).__name__}")
    return str(int(value))


def shortest_float(value: float, data_type: int) -> str:
    """Fewest digits that give back the same REAL32/REAL64 (12.345, not 12.345000267028809)."""
    if data_type != dt.DataType.REAL32 or not math.isfinite(value):
        return repr(value)
    target = struct.pack("<f", value)
    for digits in range(1, 10):
        text = f"{value:.{digits}g}"
        if struct.pack("<f", float(text)) == target:
            return repr(float(text))  # "20.0", not "2e+01"
    return repr(value)


def _parse_integer(text: str, data_type: int) -> int:
    name = dt.type_name(data_type)
    low, high = dt.int_range(data_type)
    match = _INT_INPUT.fullmatch(text)
    if match is None:
        raise ValueError(
            f"'{text}' is not a whole number; {name} takes {low}..{high}, in decimal or hex (0x1F)"
        )
    sign, digits = match.groups()
    base = {"0x": 16, "0b": 2}.get(digits[:2].lower(), 10)
    magnitude = int(digits[2:] if base != 10 else digits, base)
    value = -magnitude if sign == "-" else magnitude
    bits = dt.int_bits(data_type)
    if dt.is_signed(data_type) and base != 10 and not sign and high < value < (1 << bits):
        value -= 1 << bits  # raw register value, two's complement
    if not low <= value <= high:
        raise ValueError(f"{value} is out of range for {name} ({low}..{high})")
    return value


def _parse_float(text: str, data_type: int) -> float:
    name = dt.type_name(data_type)
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"'{text}' is not a number; {name} takes e.g. 1.5 or -2e3") from None
    if not math.isfinite(value):
        raise ValueError(f"'{text}' is not a finite number")
    if data_type == dt.DataType.REAL32:
        if abs(value) > dt.REAL32_MAX:
            raise ValueError(f"{text} is too large for REAL32 (at most {dt.REAL32_MAX:.7g})")
        return dt.as_real32(value)
    return value


def _check_limits(sub: OdSub, value: int | float) -> int | float:
    low, high = sub.low, sub.high
    if low is not None and high is not None and low > high:
        return value  # inverted limits in the file: reported at import, not enforced
    if low is not None and value < low:
        raise ValueError(
            f"{value} is below the minimum {low} of {sub.index:04X}h sub {sub.subindex}"
        )
    if high is not None and value > high:
        raise ValueError(
            f"{value} is above the maximum {high} of {sub.index:04X}h sub {sub.subindex}"
        )
    return value


def _parse_bool(text: str) -> int:
    lowered = text.lower()
    if lowered in _TRUE:
        return 1
    if lowered in _FALSE:
        return 0
    raise ValueError(f"'{text}' is not a BOOLEAN; enter 1/0 or true/false")


def _parse_bytes(text: str, data_type: int) -> bytes:
    digits = re.sub(r"[\s:_-]", "", text)
    if digits[:2].lower() == "0x":
        digits = digits[2:]
    try:
        data = bytes.fromhex(digits)
    except ValueError:
        raise ValueError(
            f"'{text}' is not hex bytes; {dt.type_name(data_type)} takes e.g. 'C8 3D BB'"
        ) from None
    if (
        data_type in (dt.DataType.TIME_OF_DAY, dt.DataType.TIME_DIFFERENCE)
        and len(data) != _TIME_BYTES
    ):
        raise ValueError(f"{dt.type_name(data_type)} is {_TIME_BYTES} bytes; got {len(data)}")
    return data
