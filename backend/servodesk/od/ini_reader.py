"""Tolerant INI reader for EDS/DCF files: keeps line numbers, never refuses a line.

configparser is not used: it loses line numbers, raises on duplicate keys and sections, treats
indented lines as continuations, and depends on the caller for the encoding. Field files have all
of these (see ../shared/eds/SOURCES.md).
"""

from __future__ import annotations

import codecs
import re
from collections.abc import Iterator
from dataclasses import dataclass, field

from servodesk.od.lint import Code, WarningSink
from servodesk.od.model import OdImportError

# whitespace then ';' starts a comment after a value (python-canopen's inline_comment_prefixes)
_INLINE_COMMENT = re.compile(r"\s;")
_LINE_BREAK = re.compile(r"\r\n|\r|\n")
# share of non-ASCII characters that must be common simplified Chinese (GB2312) for a GBK guess
_GBK_MIN_SHARE = 0.9
# ~700 bytes each in memory; the largest vendor EDS files hold tens of thousands
MAX_SECTIONS = 200_000


@dataclass(frozen=True, slots=True)  # slots: one per line of a file of up to megabytes
class IniEntry:
    key: str  # as written
    value: str  # stripped, an inline comment removed
    raw: str  # stripped, any inline comment kept (strings may legitimately contain " ;")
    line: int
    comment: str | None = None


@dataclass(slots=True)
class IniSection:
    name: str  # as written
    line: int
    entries: dict[str, IniEntry] = field(default_factory=dict)  # key: casefolded key

    def get(self, key: str) -> IniEntry | None:
        return self.entries.get(key.casefold())

    def text(self, key: str, default: str = "") -> str:
        entry = self.get(key)
        return default if entry is None else entry.value


@dataclass
class IniDocument:
    sections: dict[str, IniSection]  # key: casefolded name, in file order
    encoding: str

    def section(self, name: str) -> IniSection | None:
        return self.sections.get(name.casefold())


def decode_text(data: bytes, sink: WarningSink) -> tuple[str, str]:
    """UTF-8 (with or without BOM), else GBK (Chinese vendor tools), else cp1252.

    GBK accepts most cp1252 byte sequences too ("ü" then an ASCII letter is a valid GBK pair), so
    GBK is taken only when the non-ASCII text is nearly all common simplified Chinese.
    """
    utf8 = "utf-8"
    if data.startswith(codecs.BOM_UTF8):
        data, utf8 = data[len(codecs.BOM_UTF8) :], "utf-8-sig"
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        # Windows editors' "Unicode": valid text, but most CANopen tools cannot read it
        sink.add(
            Code.ENCODING,
            "File is UTF-16 (Windows 'Unicode'); read as such. Most CANopen tools need ASCII",
            line=1,
        )
        return data.decode("utf-16", errors="replace"), "utf-16"
    try:
        return data.decode("utf-8"), utf8
    except UnicodeDecodeError as exc:
        first_bad = exc.start
    line = data.count(b"\n", 0, first_bad) + 1
    gbk = _try_decode(data, "gbk")
    if gbk is not None and _looks_chinese(gbk):
        text, encoding = gbk, "gbk"
    else:
        cp1252 = _try_decode(data, "cp1252")
        # latin-1 never fails: bytes cp1252 leaves undefined (0x81, 0x8D ...) map 1:1
        text, encoding = (
            (cp1252, "cp1252") if cp1252 is not None else (data.decode("latin-1"), "latin-1")
        )
    sink.add(
        Code.ENCODING,
        f"File is not UTF-8 (first non-UTF-8 byte on line {line}); read as {encoding.upper()}. "
        "CiA 306 files should be ASCII: check the non-English names.",
        line=line,
    )
    return text, encoding


def _try_decode(data: bytes, encoding: str) -> str | None:
    try:
        return data.decode(encoding)
    except UnicodeDecodeError:
        return None


def _looks_chinese(text: str) -> bool:
    wide = [c for c in text if ord(c) > 0x7F]
    if not wide:
        return False
    common = sum(1 for c in wide if _encodes(c, "gb2312"))
    return common / len(wide) >= _GBK_MIN_SHARE


def _encodes(char: str, encoding: str) -> bool:
    try:
        char.encode(encoding)
    except UnicodeEncodeError:
        return False
    return True


def read_ini(text: str, sink: WarningSink, *, encoding: str = "utf-8") -> IniDocument:
    doc = IniDocument(sections={}, encoding=encoding)
    _check_line_endings(text, sink)
    current: IniSection | None = None
    for number, line in enumerate(_split_lines(text), start=1):
        stripped = line.strip()
        if not stripped or stripped[0] in ";#":
            continue
        if stripped.startswith("["):
            current = _open_section(doc, stripped, number, sink)
            continue
        key, sep, value = stripped.partition("=")
        key = key.strip()
        if not sep or not key:
            sink.add(
                Code.BAD_LINE, f"Line '{_clip(stripped)}' is not key=value; ignored", line=number
            )
            continue
        if current is None:
            sink.add(
                Code.OUTSIDE_SECTION,
                f"'{key}' comes before the first [section]; ignored",
                line=number,
                key=key,
            )
            continue
        _add_entry(current, key, value.strip(), number, sink)
    return doc


def _split_lines(text: str) -> Iterator[str]:
    """_LINE_BREAK.split(text), one line at a time: a list of every line of a file of a million
    short lines takes many times the file's size."""
    start = 0
    for match in _LINE_BREAK.finditer(text):
        yield text[start : match.start()]
        start = match.end()
    yield text[start:]


def _open_section(doc: IniDocument, stripped: str, number: int, sink: WarningSink) -> IniSection:
    end = stripped.find("]")
    name = stripped[1:end].strip() if end >= 0 else stripped[1:].strip()
    if end < 0:
        sink.add(
            Code.BAD_LINE,
            f"Section header '{_clip(stripped)}' has no ']'; read as [{name}]",
            line=number,
            section=name,
        )
    existing = doc.sections.get(name.casefold())
    if existing is not None:
        sink.add(
            Code.DUPLICATE_SECTION,
            f"Section [{name}] appears again (first on line {existing.line}); entries merged, "
            "later values win",
            line=number,
            section=name,
        )
        return existing
    if len(doc.sections) >= MAX_SECTIONS:
        raise OdImportError(
            f"{sink.file}: line {number}: more than {MAX_SECTIONS} [sections]; "
            "not a device description"
        )
    section = IniSection(name=name, line=number)
    doc.sections[name.casefold()] = section
    return section


def _add_entry(section: IniSection, key: str, raw: str, number: int, sink: WarningSink) -> None:
    comment: str | None = None
    value = raw
    match = _INLINE_COMMENT.search(raw)
    if match is not None:
        value = raw[: match.start()].strip()
        comment = raw[match.end() :].strip()
    previous = section.entries.get(key.casefold())
    if previous is not None:
        sink.add(
            Code.DUPLICATE_KEY,
            f"{key} is set twice (first on line {previous.line}, '{_clip(previous.raw)}'); "
            f"using '{_clip(value)}'",
            line=number,
            section=section.name,
            key=key,
        )
    section.entries[key.casefold()] = IniEntry(key, value, raw, number, comment)


def _check_line_endings(text: str, sink: WarningSink) -> None:
    crlf = text.count("\r\n")
    lone_lf = text.count("\n") - crlf
    lone_cr = text.count("\r") - crlf
    kinds = [name for name, n in (("CRLF", crlf), ("LF", lone_lf), ("CR", lone_cr)) if n]
    if len(kinds) < 2:
        return
    # the first line whose break differs from the first line's
    breaks = [m.group() for m in _LINE_BREAK.finditer(text)]
    line = next(n for n, brk in enumerate(breaks, start=1) if brk != breaks[0])
    counts = ", ".join(
        f"{n} {name}" for name, n in (("CRLF", crlf), ("LF", lone_lf), ("CR", lone_cr)) if n
    )
    sink.add(
        Code.LINE_ENDINGS,
        f"Mixed line endings ({counts}); the first change is at line {line}. Read as usual.",
        line=line,
        severity="info",
    )


def _clip(text: str, width: int = 60) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."
