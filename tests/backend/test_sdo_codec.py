"""SDO value codec: bytes <-> typed values, display texts, input checks (pure, table-tested)."""

from __future__ import annotations

import pytest

from servodesk.errors import InvalidValueError
from servodesk.od import DataType, OdSub
from servodesk.od.model import Value
from servodesk.sdo import codec


def entry(data_type: int, *, low: int | None = None, high: int | None = None) -> OdSub:
    return OdSub(0x2000, 1, "Test", data_type, "rw", False, low=low, high=high)


@pytest.mark.parametrize(
    ("data_type", "data", "value", "text"),
    [
        (DataType.UNSIGNED16, "40 02", 576, "0x0240 (576)"),
        (DataType.INTEGER16, "FB FF", -5, "0xFFFB (-5)"),
        (DataType.INTEGER8, "80", -128, "0x80 (-128)"),
        (DataType.UNSIGNED32, "53 56 44 00", 0x00445653, "0x00445653 (4478547)"),
        (DataType.INTEGER32, "00 00 00 80", -(2**31), "0x80000000 (-2147483648)"),
        (DataType.UNSIGNED8, "05", 5, "0x05 (5)"),
        (DataType.BOOLEAN, "01", 1, "true"),
        (DataType.REAL32, "00 00 C0 3F", 1.5, "1.5"),
        (DataType.VISIBLE_STRING, "44 56 53 00 00", "DVS", "DVS"),
        (DataType.OCTET_STRING, "C8 3D BB", b"\xc8\x3d\xbb", "C8 3D BB"),
        # some drives answer 4 bytes for an UNSIGNED16: the type's size wins
        (DataType.UNSIGNED16, "40 02 00 00", 576, "0x0240 (576)"),
    ],
)
def test_decode_and_display(data_type: int, data: str, value: Value, text: str) -> None:
    sub = entry(data_type)
    decoded = codec.decode(sub, bytes.fromhex(data))
    assert decoded == value
    assert codec.display_text(sub, decoded) == text


@pytest.mark.parametrize(
    ("data", "value", "api", "text"),
    [
        ("40 02", 576, 576, "0x0240 (576)"),
        ("E8 03 00 00", 1000, 1000, "0x000003E8 (1000)"),
        ("01 02 03 04 05", b"\x01\x02\x03\x04\x05", "01 02 03 04 05", "01 02 03 04 05"),
    ],
)
def test_unknown_entries_are_numbers_up_to_four_bytes(
    data: str, value: Value, api: object, text: str
) -> None:
    raw = bytes.fromhex(data)
    decoded = codec.decode_unknown(raw)
    assert decoded == value
    assert codec.api_value(decoded) == api
    assert codec.display_text(None, decoded, size=len(raw)) == text


@pytest.mark.parametrize(
    ("sub", "value", "data"),
    [
        (entry(DataType.UNSIGNED16), "0x1F", "1F 00"),
        (entry(DataType.UNSIGNED16), 576, "40 02"),
        (entry(DataType.INTEGER16), -5, "FB FF"),
        (entry(DataType.INTEGER16), "-5", "FB FF"),
        (entry(DataType.INTEGER16), "0xFFFB", "FB FF"),  # hex on a signed type: raw register
        (entry(DataType.INTEGER32), 7.0, "07 00 00 00"),
        (entry(DataType.REAL32), 1.5, "00 00 C0 3F"),
        (entry(DataType.VISIBLE_STRING), "abc", "61 62 63"),
        (entry(DataType.OCTET_STRING), "C8 3D BB", "C8 3D BB"),
    ],
)
def test_coerce_and_encode(sub: OdSub, value: int | float | str, data: str) -> None:
    assert codec.encode(sub, codec.coerce(sub, value, "2000h:01h")) == bytes.fromhex(data)


@pytest.mark.parametrize(
    ("sub", "value", "message"),
    [
        (entry(DataType.UNSIGNED8), 256, "out of range for UNSIGNED8 (0..255)"),
        (entry(DataType.UNSIGNED16), -1, "out of range for UNSIGNED16"),
        (entry(DataType.INTEGER16), 40000, "out of range for INTEGER16 (-32768..32767)"),
        (entry(DataType.UNSIGNED16, low=1, high=127), 128, "above the maximum 127"),
        (entry(DataType.UNSIGNED16, low=1, high=127), "0", "below the minimum 1"),
        (entry(DataType.UNSIGNED16), "twelve", "not a whole number"),
        (entry(DataType.UNSIGNED16), 1.5, "whole numbers"),
        (entry(DataType.VISIBLE_STRING), 5, "takes text"),
        (entry(DataType.OCTET_STRING), 5, "hex bytes"),
    ],
)
def test_coerce_refuses_with_a_clear_message(
    sub: OdSub, value: int | float | str, message: str
) -> None:
    with pytest.raises(InvalidValueError, match="2000h:01h") as refused:
        codec.coerce(sub, value, "2000h:01h")
    assert message in str(refused.value)


@pytest.mark.parametrize(
    ("value", "size", "data"),
    [
        (1000, 4, "E8 03 00 00"),
        (-1, 2, "FF FF"),
        ("0x1F", 1, "1F"),
        ("E8 03 00 00", None, "E8 03 00 00"),
        ("0xE803", None, "E8 03"),
    ],
)
def test_unknown_entry_input(value: int | str, size: int | None, data: str) -> None:
    assert codec.coerce_unknown(value, size, "5000h:00h") == bytes.fromhex(data)


@pytest.mark.parametrize(
    ("value", "size", "message"),
    [
        (1000, None, "give the size"),
        (256, 1, "does not fit in 1 byte"),
        ("not hex", None, "raw hex bytes"),
        (1.5, 4, "whole numbers"),
    ],
)
def test_unknown_entry_input_refused(
    value: int | float | str, size: int | None, message: str
) -> None:
    with pytest.raises(InvalidValueError, match=message):
        codec.coerce_unknown(value, size, "5000h:00h")


@pytest.mark.parametrize(
    ("data_type", "expected", "actual", "same"),
    [
        (DataType.UNSIGNED16, 5, 5, True),
        (DataType.UNSIGNED16, 5, 6, False),
        (DataType.UNSIGNED16, 5, None, False),
        (DataType.REAL32, 12.345, 12.345000267028809, True),  # the REAL32 nearest to 12.345
        (DataType.VISIBLE_STRING, "abc", "abc\x00", True),
        (DataType.OCTET_STRING, b"\x01", b"\x02", False),
    ],
)
def test_same_value(data_type: int, expected: Value, actual: Value | None, same: bool) -> None:
    assert codec.same_value(entry(data_type), expected, actual) is same
