"""File literals per data type: what is read, and which note says how it was read."""

from __future__ import annotations

import pytest

from servodesk.od import DataType as T
from servodesk.od.literals import parse_literal

U8, U16, U32, I16, I32, I64 = (
    T.UNSIGNED8,
    T.UNSIGNED16,
    T.UNSIGNED32,
    T.INTEGER16,
    T.INTEGER32,
    T.INTEGER64,
)


@pytest.mark.parametrize(
    ("text", "data_type", "node_id", "value", "relative", "codes"),
    [
        ("0x1F", U8, None, 31, False, []),
        ("31", U8, None, 31, False, []),
        ("0", U32, None, 0, False, []),
        ("131474", U32, None, 0x20192, False, []),  # Yiyou 1000h in decimal
        ("-5", I16, None, -5, False, []),
        ("010", U16, None, 10, False, ["leading-zero"]),
        ("001", U32, None, 1, False, ["leading-zero"]),
        ("0x80000000", I32, None, -(2**31), False, ["signed-hex"]),
        ("0xFFFFFFFFFFFFFFF6", I64, None, -10, False, ["signed-hex"]),
        ("0x7F", I32, None, 0x7F, False, []),
        ("65536", U16, None, 65535, False, ["out-of-type-range"]),
        ("-1", U8, None, 0, False, ["out-of-type-range"]),
        ("2147483648", I32, None, 2**31 - 1, False, ["out-of-type-range"]),  # decimal: no guess
        ("0x", U8, None, None, False, ["bad-integer"]),
        ("12.5", U16, None, None, False, ["bad-integer"]),
        ("1", T.BOOLEAN, None, 1, False, []),
        ("true", T.BOOLEAN, None, 1, False, []),
        ("2", T.BOOLEAN, None, 1, False, ["out-of-type-range"]),
        ("", U32, None, None, False, []),
    ],
)
def test_integers(
    text: str, data_type: int, node_id: int | None, value: object, relative: bool, codes: list[str]
) -> None:
    parsed = parse_literal(text, data_type, key="DefaultValue", node_id=node_id)
    assert (parsed.value, parsed.relative) == (value, relative)
    assert [n.code for n in parsed.notes] == codes


@pytest.mark.parametrize(
    ("text", "node_id", "value", "codes"),
    [
        ("$NODEID+0x180", 5, 0x185, []),
        ("$NODEID+0x180", None, 0x180, []),
        ("$NODEID + 0x80", 2, 0x82, []),
        ("0x180+$NODEID", 5, 0x185, ["nodeid-formula"]),
        ("1280+$NODEID", 1, 1281, ["nodeid-formula"]),
        ("$NodeID+0x600", 3, 0x603, ["nodeid-case"]),
        ("$NODEID", 7, 7, []),
        ("$NODEID+$NODEID", 7, None, ["bad-integer"]),
        ("0x80-$NODEID", 7, None, ["bad-integer"]),
        ("0x80$NODEID", 7, None, ["bad-integer"]),
    ],
)
def test_node_relative_values(
    text: str, node_id: int | None, value: int | None, codes: list[str]
) -> None:
    parsed = parse_literal(text, U32, key="DefaultValue", node_id=node_id)
    assert parsed.value == value
    assert parsed.relative == (value is not None)
    assert [n.code for n in parsed.notes] == codes


def test_leading_zero_note_mentions_the_octal_reading() -> None:
    [note] = parse_literal("010", U16, key="DefaultValue", node_id=None).notes
    assert (note.severity, "decimal 10" in note.message, "octal 8" in note.message) == (
        "info",
        True,
        True,
    )


@pytest.mark.parametrize(
    ("text", "data_type", "value", "codes"),
    [
        ("12.345", T.REAL32, pytest.approx(12.345, rel=1e-7), ["float-literal"]),
        ("456.789", T.REAL64, 456.789, ["float-literal"]),
        ("-20.0", T.REAL32, -20.0, ["float-literal"]),
        ("0", T.REAL32, 0.0, []),
        ("0.0", T.REAL64, 0.0, []),
        ("0x41A00000", T.REAL32, 20.0, []),  # CiA 306: the bit pattern
        ("0x4034000000000000", T.REAL64, 20.0, []),
        ("0x141A00000", T.REAL32, None, ["bad-float"]),
        ("1e39", T.REAL32, None, ["out-of-type-range"]),
        ("abc", T.REAL32, None, ["bad-float"]),
    ],
)
def test_floats(text: str, data_type: int, value: object, codes: list[str]) -> None:
    parsed = parse_literal(text, data_type, key="DefaultValue", node_id=None)
    assert parsed.value == value
    assert [n.code for n in parsed.notes] == codes


def test_real32_values_are_rounded_to_what_the_type_holds() -> None:
    value = parse_literal("0.1", T.REAL32, key="DefaultValue", node_id=None).value
    assert value == 0.10000000149011612


@pytest.mark.parametrize(
    ("text", "data_type", "value", "codes"),
    [
        ("C83DBB", T.OCTET_STRING, b"\xc8\x3d\xbb", []),
        ("C8 3D BB", T.OCTET_STRING, b"\xc8\x3d\xbb", []),  # CANopenEditor XDD spelling
        ("00000000000000000000", T.OCTET_STRING, bytes(10), []),  # not a leading-zero integer
        ("", T.DOMAIN, b"", []),
        ("0x0", 0x40, b"\x00", []),  # unknown type: raw bytes, as python-canopen does
        ("XYZ", T.OCTET_STRING, None, ["bad-bytes"]),
        ("Kinco ; servo", T.VISIBLE_STRING, "Kinco ; servo", []),
        ("", T.VISIBLE_STRING, "", []),
    ],
)
def test_strings_and_bytes(text: str, data_type: int, value: object, codes: list[str]) -> None:
    parsed = parse_literal(text, data_type, key="DefaultValue", node_id=None)
    assert parsed.value == value
    assert [n.code for n in parsed.notes] == codes
