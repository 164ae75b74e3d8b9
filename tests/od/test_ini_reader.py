"""Tolerant INI reading: encodings, line endings, comments and duplicates, with line numbers."""

from __future__ import annotations

import codecs

import pytest

from servodesk.od.ini_reader import IniDocument, decode_text, read_ini
from servodesk.od.lint import WarningSink


def _read(text: str) -> tuple[IniDocument, WarningSink]:
    sink = WarningSink("t.eds")
    return read_ini(text, sink), sink


@pytest.mark.parametrize(
    ("data", "text", "encoding", "warned"),
    [
        (
            b"[1000]\nParameterName=Device type\n",
            "[1000]\nParameterName=Device type\n",
            "utf-8",
            False,
        ),
        (codecs.BOM_UTF8 + b"[1000]\n", "[1000]\n", "utf-8-sig", False),
        ("名称=β ‰\n".encode(), "名称=β ‰\n", "utf-8", False),
        (
            "ParameterName=设备类型（单位：ms）\n".encode("gbk"),
            "ParameterName=设备类型（单位：ms）\n",
            "gbk",
            True,
        ),
        # a cp1252 "ü" followed by a letter is also a valid GBK pair: must not become Chinese
        (
            "ParameterName=Geschwindigkeitsüberwachung Übersicht\n".encode("cp1252"),
            "ParameterName=Geschwindigkeitsüberwachung Übersicht\n",
            "cp1252",
            True,
        ),
        (b"Name=a\x81b\n", "Name=a\x81b\n", "latin-1", True),  # 0x81 is undefined in cp1252
        ("[1000]\nA=β\n".encode("utf-16"), "[1000]\nA=β\n", "utf-16", True),
    ],
    ids=["ascii", "utf8-bom", "utf8", "gbk", "cp1252", "latin1-fallback", "utf16"],
)
def test_decode_text_picks_the_encoding(
    data: bytes, text: str, encoding: str, warned: bool
) -> None:
    sink = WarningSink("t.eds")
    assert decode_text(data, sink) == (text, encoding)
    codes = [w.code for w in sink.items]
    assert codes == (["encoding"] if warned else [])
    if warned:
        assert encoding.upper() in sink.items[0].message.upper()
        assert sink.items[0].line == 1


def test_encoding_warning_names_the_first_bad_line() -> None:
    sink = WarningSink("t.eds")
    decode_text(b"[1000]\nA=1\nParameterName=" + "错误".encode("gbk") + b"\n", sink)
    assert sink.items[0].line == 3


def test_sections_and_keys_are_case_insensitive_with_line_numbers() -> None:
    doc, sink = _read(
        "; banner\n\n[DeviceInfo]\nVendorNumber=0x9A\n[1018sub1]\nparametername=Vendor\n"
    )
    info = doc.section("deviceinfo")
    assert info is not None
    entry = info.get("VENDORNUMBER")
    assert entry is not None
    assert (entry.key, entry.value, entry.line) == ("VendorNumber", "0x9A", 4)
    assert doc.section("1018SUB1") is not None
    assert doc.section("1018SUB1").text("ParameterName") == "Vendor"  # type: ignore[union-attr]
    assert sink.items == []


def test_inline_comment_is_split_off_but_kept_raw() -> None:
    doc, _ = _read("[6502]\nDefaultValue=0x3ED ; prevent homing\nName=a;b\n")
    section = doc.section("6502")
    assert section is not None
    entry = section.get("DefaultValue")
    assert entry is not None
    assert (entry.value, entry.raw, entry.comment) == (
        "0x3ED",
        "0x3ED ; prevent homing",
        "prevent homing",
    )
    assert section.text("Name") == "a;b"  # no whitespace before ';': part of the value


def test_commented_out_keys_are_not_read() -> None:
    doc, _ = _read("[1603sub2]\n;ParameterValue=0x60c10220\n# DefaultValue=1\n")
    assert doc.section("1603sub2").entries == {}  # type: ignore[union-attr]


def test_mixed_line_endings_are_read_and_noted_once() -> None:
    doc, sink = _read("[A]\r\nx=1\r\ny=2\nz=3\r\n")
    assert doc.section("A").text("z") == "3"  # type: ignore[union-attr]
    [warning] = sink.items
    assert (warning.code, warning.severity, warning.line) == ("line-endings", "info", 3)
    assert "3 CRLF, 1 LF" in warning.message


def test_duplicate_key_warns_and_the_later_value_wins() -> None:
    doc, sink = _read("[1000]\nDefaultValue=1\nDefaultValue=2\n")
    assert doc.section("1000").text("DefaultValue") == "2"  # type: ignore[union-attr]
    [warning] = sink.items
    assert (warning.code, warning.line, warning.section, warning.key) == (
        "duplicate-key",
        3,
        "1000",
        "DefaultValue",
    )


def test_duplicate_section_is_merged() -> None:
    doc, sink = _read("[1000]\nA=1\n[2000]\n[1000]\nB=2\n")
    assert set(doc.section("1000").entries) == {"a", "b"}  # type: ignore[union-attr]
    assert [(w.code, w.line) for w in sink.items] == [("duplicate-section", 4)]


@pytest.mark.parametrize(
    ("text", "code", "line"),
    [
        ("A=1\n[1000]\n", "outside-section", 1),
        ("[1000]\njust words\n", "bad-line", 2),
        ("[1000]\n=value\n", "bad-line", 2),
        ("[1000\nA=1\n", "bad-line", 1),
    ],
)
def test_unusable_lines_are_reported_not_fatal(text: str, code: str, line: int) -> None:
    _, sink = _read(text)
    assert [(w.code, w.line) for w in sink.items] == [(code, line)]
