"""User input codec: what a commissioning engineer types, per CiA 301 data type."""

from __future__ import annotations

import re

import pytest

from servodesk.od import DataType as T
from servodesk.od import OdSub, format_value, parse_value


def _sub(data_type: int, low: int | float | None = None, high: int | float | None = None) -> OdSub:
    return OdSub(0x2000, 1, "Test", data_type, "rw", False, low=low, high=high)


@pytest.mark.parametrize(
    ("data_type", "text", "value"),
    [
        (T.UNSIGNED8, "31", 31),
        (T.UNSIGNED8, "0x1F", 31),
        (T.UNSIGNED8, " 0X1f ", 31),
        (T.UNSIGNED8, "0b11111", 31),
        (T.UNSIGNED8, "031", 31),  # decimal, never octal
        (T.UNSIGNED8, "255", 255),
        (T.INTEGER8, "-128", -128),
        (T.INTEGER8, "+5", 5),
        (T.INTEGER16, "-5", -5),
        (T.INTEGER16, "0xFFFB", -5),  # hex is the raw register value
        (T.INTEGER16, "-0x10", -16),
        (T.INTEGER24, "0x800000", -(2**23)),
        (T.UNSIGNED24, "0xFFFFFF", 2**24 - 1),
        (T.INTEGER32, "-2147483648", -(2**31)),
        (T.UNSIGNED32, "0x60410010", 0x60410010),
        (T.INTEGER64, "0xFFFFFFFFFFFFFFFF", -1),
        (T.UNSIGNED64, "18446744073709551615", 2**64 - 1),
        (T.BOOLEAN, "1", 1),
        (T.BOOLEAN, "true", 1),
        (T.BOOLEAN, "Off", 0),
        (T.REAL32, "1.5", 1.5),
        (T.REAL32, "-2e3", -2000.0),
        (T.REAL32, "0.1", 0.10000000149011612),  # what the drive will hold
        (T.REAL64, "0.1", 0.1),
        (T.VISIBLE_STRING, "Axis 1 ", "Axis 1 "),  # strings are not stripped
        (T.VISIBLE_STRING, "", ""),
        (T.UNICODE_STRING, "轴 1", "轴 1"),
        (T.OCTET_STRING, "C8 3D BB", b"\xc8\x3d\xbb"),
        (T.OCTET_STRING, "c8:3d:bb", b"\xc8\x3d\xbb"),
        (T.OCTET_STRING, "0xC83DBB", b"\xc8\x3d\xbb"),
        (T.DOMAIN, "", b""),
        (T.TIME_OF_DAY, "00 11 22 33 44 55", bytes.fromhex("001122334455")),
    ],
)
def test_parse_value(data_type: int, text: str, value: object) -> None:
    parsed = parse_value(_sub(data_type), text)
    assert parsed == value
    assert type(parsed) is type(value)


@pytest.mark.parametrize(
    ("data_type", "text", "message"),
    [
        (T.UNSIGNED8, "256", "256 is out of range for UNSIGNED8 (0..255)"),
        (T.UNSIGNED8, "-1", "-1 is out of range for UNSIGNED8 (0..255)"),
        (T.INTEGER16, "32768", "32768 is out of range for INTEGER16 (-32768..32767)"),
        (T.INTEGER16, "0x10000", "65536 is out of range for INTEGER16"),
        (T.UNSIGNED16, "1.5", "'1.5' is not a whole number; UNSIGNED16 takes 0..65535"),
        (T.UNSIGNED16, "abc", "not a whole number"),
        (T.UNSIGNED16, "", "Enter a value for UNSIGNED16"),
        (T.BOOLEAN, "2", "'2' is not a BOOLEAN"),
        (T.REAL32, "fast", "'fast' is not a number"),
        (T.REAL32, "nan", "not a finite number"),
        (T.REAL32, "1e39", "too large for REAL32"),
        (T.VISIBLE_STRING, "25 °C", "printable ASCII only; remove '°'"),
        (T.OCTET_STRING, "C8 3", "is not hex bytes"),
        (T.TIME_DIFFERENCE, "00 11", "TIME_DIFFERENCE is 6 bytes; got 2"),
    ],
)
def test_parse_value_refuses_with_a_clear_message(data_type: int, text: str, message: str) -> None:
    with pytest.raises(ValueError, match=re.escape(message)):
        parse_value(_sub(data_type), text)


@pytest.mark.parametrize(
    ("low", "high", "text", "message"),
    [
        (2, 6, "1", "1 is below the minimum 2 of 2000h sub 1"),
        (2, 6, "31", "31 is above the maximum 6 of 2000h sub 1"),
        (-1000, None, "-1001", "below the minimum -1000"),
    ],
)
def test_parse_value_checks_the_entry_limits(
    low: int, high: int | None, text: str, message: str
) -> None:
    with pytest.raises(ValueError, match=re.escape(message)):
        parse_value(_sub(T.INTEGER32, low, high), text)


def test_inverted_limits_from_a_file_are_not_enforced() -> None:
    assert parse_value(_sub(T.UNSIGNED8, 3, 1), "2") == 2


def test_float_limits() -> None:
    sub = _sub(T.REAL32, 4.5, None)
    assert parse_value(sub, "5.2") == pytest.approx(5.2)
    with pytest.raises(ValueError, match=r"below the minimum 4\.5"):
        parse_value(sub, "4")


@pytest.mark.parametrize(
    ("data_type", "value", "text"),
    [
        (T.UNSIGNED32, 0x60410010, "1614872592"),
        (T.INTEGER16, -5, "-5"),
        (T.BOOLEAN, True, "1"),
        (T.BOOLEAN, 0, "0"),
        (T.REAL32, 0.10000000149011612, "0.1"),
        (T.REAL32, 12.345000267028809, "12.345"),
        (T.REAL32, 20.0, "20.0"),
        (T.REAL64, 456.789, "456.789"),
        (T.VISIBLE_STRING, "Axis 1", "Axis 1"),
        (T.OCTET_STRING, b"\xc8\x3d\xbb", "C8 3D BB"),
        (T.DOMAIN, bytearray(b"\x01"), "01"),
        (T.UNSIGNED8, None, ""),
    ],
)
def test_format_value(data_type: int, value: object, text: str) -> None:
    assert format_value(_sub(data_type), value) == text


@pytest.mark.parametrize(
    ("data_type", "text"),
    [
        (T.INTEGER32, "-123456"),
        (T.UNSIGNED64, "0xFFFFFFFFFFFFFFFF"),
        (T.REAL32, "3.14159"),
        (T.REAL64, "-1e-300"),
        (T.OCTET_STRING, "DE AD BE EF"),
        (T.VISIBLE_STRING, "Kinco ; servo"),
    ],
)
def test_format_then_parse_round_trips(data_type: int, text: str) -> None:
    sub = _sub(data_type)
    value = parse_value(sub, text)
    assert parse_value(sub, format_value(sub, value)) == value


@pytest.mark.parametrize(
    ("data_type", "value"),
    [(T.UNSIGNED8, "31"), (T.REAL32, "1.5"), (T.VISIBLE_STRING, 5), (T.OCTET_STRING, "C8")],
)
def test_format_value_refuses_the_wrong_python_type(data_type: int, value: object) -> None:
    with pytest.raises(TypeError, match="value must be"):
        format_value(_sub(data_type), value)
