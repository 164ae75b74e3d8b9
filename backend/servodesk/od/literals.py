"""Values as EDS/DCF/XDD files write them, read per data type, with a note for every guess.

CiA 306 allows decimal and 0x-hex integers, `$NODEID+offset` for node-relative values,
and REAL values as the integer of their bit pattern. Field files add decimal floats, leading
zeros, raw-hex signed limits and the offset written first (SOURCES.md); each is read the way its
author evidently meant and noted.
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass, field

from servodesk.od import datatypes as dt
from servodesk.od.lint import Code, Severity
from servodesk.od.model import Value

_NODEID = re.compile(r"\$NODEID", re.IGNORECASE)
_INT = re.compile(r"([+-]?)(0[xX][0-9A-Fa-f]+|[0-9]+)")
_FLOAT = re.compile(r"[+-]?(\d+\.\d*|\.\d+|\d+)([eE][+-]?\d+)?")


@dataclass(frozen=True)
class Note:
    code: Code
    message: str
    severity: Severity
    detail: str = ""  # the odd spelling, for per-file summaries


@dataclass
class Parsed:
    value: Value | None
    relative: bool = False
    notes: list[Note] = field(default_factory=list)

    def note(
        self, code: Code, message: str, severity: Severity = "warning", *, detail: str = ""
    ) -> None:
        self.notes.append(Note(code, message, severity, detail))


def decimal(text: str) -> int | None:
    """ASCII decimal digits as an int, else None: str.isdigit() also takes "²" and "٣", which
    int() refuses, as it refuses more than 4300 digits."""
    if text.isascii() and text.isdigit() and len(text) <= 100:
        return int(text)
    return None


def parse_int(text: str) -> tuple[int, bool]:
    """Decimal or 0x-hex integer with an optional sign -> (value, written_in_hex).

    A leading zero is decimal here ("010" is 10): vendor files mean decimal, and Python's int(x, 0)
    refuses such text outright (python-canopen#313). Raises ValueError for anything else.
    """
    match = _INT.fullmatch(text.strip())
    if match is None:
        raise ValueError(text)
    sign, digits = match.groups()
    is_hex = digits[:2] in ("0x", "0X")
    value = int(digits[2:], 16) if is_hex else int(digits, 10)
    return (-value if sign == "-" else value), is_hex


def parse_literal(
    text: str, data_type: int, *, key: str, node_id: int | None, decimal_floats: bool = False
) -> Parsed:
    """Read `text` (already stripped) for a `data_type` entry. `key` names it in messages.

    `decimal_floats`: the format writes REAL values as decimals (XDD does, CiA 306 EDS does not).
    """
    if dt.is_text(data_type):
        return Parsed(text)
    text = text.strip()
    if dt.is_bytes(data_type) or not dt.is_known(data_type):
        return _parse_bytes(text, key)  # empty is a valid, empty octet string
    if not text:
        return Parsed(None)
    if dt.is_float(data_type):
        return _parse_float(text, data_type, key, decimal_floats)
    return _parse_integer(text, data_type, key, node_id)


def _parse_integer(text: str, data_type: int, key: str, node_id: int | None) -> Parsed:
    result = Parsed(None)
    body = text
    if _NODEID.search(text):
        offset = _strip_nodeid(text, key, result)
        if offset is None:
            return result
        body = offset
        result.relative = True
    if data_type == dt.DataType.BOOLEAN and body.lower() in ("true", "false"):
        result.value = int(body.lower() == "true")
        return result
    try:
        value, is_hex = parse_int(body) if body else (0, False)
    except ValueError:
        result.note(Code.BAD_INTEGER, f"{key} '{text}' is not a number; left empty")
        return result
    if not is_hex and len(body.lstrip("+-")) > 1 and body.lstrip("+-")[0] == "0":
        octal = _as_octal(body.lstrip("+-"))
        also = (
            f"; a C-style reader would take it as octal {octal}"
            if octal not in (None, value)
            else ""
        )
        result.note(
            Code.LEADING_ZERO,
            f"{key} '{body}' has a leading zero; read as decimal {value}{also}",
            "info",
        )
    fitted = _fit(value, is_hex, data_type, key, text, result)
    result.value = fitted + node_id if result.relative and node_id is not None else fitted
    return result


def _strip_nodeid(text: str, key: str, result: Parsed) -> str | None:
    """`$NODEID+0x180`, `0x180+$NODEID`, `$NodeID + 0x80` -> "0x180" / "0x80"."""
    token = _NODEID.search(text)
    if token is None or len(_NODEID.findall(text)) > 1:
        result.note(Code.BAD_INTEGER, f"{key} '{text}' is not a $NODEID+offset formula; left empty")
        return None
    before, after = text[: token.start()].strip(), text[token.end() :].strip()
    if before and after:
        result.note(Code.BAD_INTEGER, f"{key} '{text}' is not a $NODEID+offset formula; left empty")
        return None
    if token.group() != "$NODEID":
        result.note(
            Code.NODEID_CASE,
            f"{key} '{text}' spells '{token.group()}'; CiA 306 writes $NODEID. "
            "Read as node-relative",
            "info",
            detail=token.group(),
        )
    if before:
        if not before.endswith("+"):
            result.note(
                Code.BAD_INTEGER, f"{key} '{text}' is not a $NODEID+offset formula; left empty"
            )
            return None
        result.note(
            Code.NODEID_FORMULA,
            f"{key} '{text}' puts the offset before $NODEID; read as $NODEID+{before[:-1].strip()}",
            "info",
        )
        return before[:-1].strip()
    if after and not after.startswith("+"):
        result.note(Code.BAD_INTEGER, f"{key} '{text}' is not a $NODEID+offset formula; left empty")
        return None
    return after[1:].strip()


def _fit(value: int, is_hex: bool, data_type: int, key: str, text: str, result: Parsed) -> int:
    """Bring `value` into the type's range: two's complement for raw hex, else clamp and warn."""
    low, high = dt.int_range(data_type)
    name = dt.type_name(data_type)
    bits = dt.int_bits(data_type)
    if dt.is_signed(data_type) and is_hex and high < value < (1 << bits):
        signed = value - (1 << bits)
        result.note(
            Code.SIGNED_HEX,
            f"{key} '{text}' on {name} is raw hex; read as two's complement {signed}",
            "info",
        )
        return signed
    if low <= value <= high:
        return value
    clamped = min(max(value, low), high)
    result.note(
        Code.OUT_OF_TYPE_RANGE,
        f"{key} '{text}' does not fit {name} ({low}..{high}); using {clamped}",
    )
    return clamped


def _as_octal(digits: str) -> int | None:
    try:
        return int(digits, 8)
    except ValueError:
        return None


def _parse_float(text: str, data_type: int, key: str, decimal_floats: bool) -> Parsed:
    result = Parsed(None)
    name = dt.type_name(data_type)
    if text[:2].lower() == "0x" and _INT.fullmatch(text):
        # CiA 306: the bit pattern, as an integer
        raw = int(text, 16)
        size = 4 if data_type == dt.DataType.REAL32 else 8
        if raw >= 1 << (8 * size):
            result.note(Code.BAD_FLOAT, f"{key} '{text}' is wider than {name}; left empty")
            return result
        fmt = "<f" if size == 4 else "<d"
        result.value = struct.unpack(fmt, raw.to_bytes(size, "little"))[0]
        return result
    if _FLOAT.fullmatch(text) is None:
        result.note(Code.BAD_FLOAT, f"{key} '{text}' is not a number; left empty")
        return result
    number = float(text)
    if data_type == dt.DataType.REAL32:
        if abs(number) > dt.REAL32_MAX:
            result.note(
                Code.OUT_OF_TYPE_RANGE, f"{key} '{text}' is too large for REAL32; left empty"
            )
            return result
        number = dt.as_real32(number)
    result.value = number
    if number != 0.0 and not decimal_floats:
        result.note(
            Code.FLOAT_LITERAL,
            f"{key} '{text}' is a decimal number; CiA 306 writes {name} values as their bit "
            f"pattern ({_bits_hex(number, data_type)}). Read as {text}",
            "info",
        )
    return result


def _bits_hex(value: float, data_type: int) -> str:
    if data_type == dt.DataType.REAL32:
        return "0x" + struct.pack(">f", value).hex().upper()
    return "0x" + struct.pack(">d", value).hex().upper()


def _parse_bytes(text: str, key: str) -> Parsed:
    """OCTET_STRING / DOMAIN: hex digits, optionally spaced ("C8 3D BB") or 0x-prefixed."""
    digits = "".join(text.split())
    if digits[:2].lower() == "0x":
        digits = digits[2:]
        if len(digits) % 2:
            digits = "0" + digits
    try:
        return Parsed(bytes.fromhex(digits))
    except ValueError:
        result = Parsed(None)
        result.note(Code.BAD_BYTES, f"{key} '{text}' is not hex bytes; left empty")
        return result
