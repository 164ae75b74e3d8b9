"""Import warnings: one per problem, pointing at the file, line, section and key."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Literal, Protocol

# info: read the way its author evidently meant, nothing lost (e.g. "$NodeID", upper-case RO)
# warning: a value was repaired, guessed or left empty, or the file contradicts itself
# error: an object or entry in the file could not be loaded at all
Severity = Literal["info", "warning", "error"]
MAX_PER_CODE = 1000  # warnings kept per code and file; real files have at most a few hundred


class Code(StrEnum):
    """Stable warning ids: tests, the UI and users filter on these, so never rename one."""

    # file level
    ENCODING = "encoding"  # not UTF-8/ASCII: decoded as GBK or cp1252
    LINE_ENDINGS = "line-endings"  # CRLF and LF mixed
    BAD_LINE = "bad-line"  # a line that is neither section, key=value nor comment
    OUTSIDE_SECTION = "outside-section"  # key=value before the first [section]
    DUPLICATE_SECTION = "duplicate-section"
    DUPLICATE_KEY = "duplicate-key"
    UNKNOWN_SECTION = "unknown-section"
    UNKNOWN_KEY = "unknown-key"
    EDS_VERSION = "eds-version"  # EDSVersion is not 4.x (or 3.0)
    OBJECT_LIST = "object-list"  # [Mandatory/Optional/ManufacturerObjects] disagree with sections
    XML = "xml"  # XDD structure problems
    # values
    EMPTY_VALUE = "empty-value"
    BAD_INTEGER = "bad-integer"
    BAD_FLOAT = "bad-float"
    BAD_BYTES = "bad-bytes"
    LEADING_ZERO = "leading-zero"  # "010": read as decimal, C reads octal
    INLINE_COMMENT = "inline-comment"  # "0x3ED ; prevent homing"
    FLOAT_LITERAL = "float-literal"  # REAL default written as a decimal float, not its bit pattern
    SIGNED_HEX = "signed-hex"  # LowLimit=0x80000000 on INTEGER32, read as two's complement
    OUT_OF_TYPE_RANGE = "out-of-type-range"  # HighLimit=65536 on UNSIGNED16
    DEFAULT_OUT_OF_RANGE = "default-out-of-range"  # DefaultValue outside LowLimit..HighLimit
    LIMITS_INVERTED = "limits-inverted"  # LowLimit > HighLimit
    NODEID_FORMULA = "nodeid-formula"  # "0x180+$NODEID": offset before the node id
    NODEID_CASE = "nodeid-case"  # "$NodeID": harmless, counted once per file
    # objects
    SUBNUMBER_MISMATCH = "subnumber-mismatch"
    HIGHEST_SUBINDEX = "highest-subindex"  # sub 0 default names a sub-index that is not defined
    MISSING_NAME = "missing-name"
    MISSING_DATATYPE = "missing-datatype"
    ARRAY_WITHOUT_DATATYPE = "array-without-datatype"
    UNKNOWN_DATATYPE = "unknown-datatype"
    BAD_ACCESS = "bad-access"
    ACCESS_CASE = "access-case"
    BAD_OBJECT_TYPE = "bad-object-type"
    NO_SUBENTRIES = "no-subentries"
    STRAY_SUBSECTION = "stray-subsection"  # [xxxxsubN] without a usable [xxxx]
    DISABLED_OBJECT = "disabled-object"  # CANopenNode project: object not compiled in
    # device semantics
    BYTE_SWAPPED = "byte-swapped"  # 1000h 0x92020100 instead of 0x00020192
    IDENTITY_MISMATCH = "identity-mismatch"  # [DeviceInfo] VendorNumber != 1018h:01 default
    PDO_MAPPING = "pdo-mapping"  # default mapping points at a missing or wrong-sized object


@dataclass(frozen=True, slots=True)
class LintWarning:
    file: str
    line: int | None
    section: str | None
    key: str | None
    code: str
    message: str
    severity: Severity


class WarningSink:
    """Collects warnings for one file, so importers never pass the file name around."""

    def __init__(self, file: str) -> None:
        self.file = file
        self.items: list[LintWarning] = []
        self._counts: dict[Code, int] = {}

    def add(
        self,
        code: Code,
        message: str,
        *,
        line: int | None = None,
        section: str | None = None,
        key: str | None = None,
        severity: Severity = "warning",
    ) -> None:
        count = self._counts[code] = self._counts.get(code, 0) + 1
        if count > MAX_PER_CODE:
            return  # a hostile file: a million bad lines must not take a million warnings' memory
        if count == MAX_PER_CODE:
            message += f" (and every further {code} warning of this file is left out)"
        self.items.append(LintWarning(self.file, line, section, key, code, message, severity))


def format_warning(w: LintWarning) -> str:
    """`file:line [section] key: message (severity code)`; unknown parts are left out."""
    where = w.file if w.line is None else f"{w.file}:{w.line}"
    parts = [where]
    if w.section is not None:
        parts.append(f"[{w.section}]")
    head = " ".join(parts)
    key = f" {w.key}" if w.key else ""
    return f"{head}{key}: {w.message} ({w.severity} {w.code})"


class Linted(Protocol):
    """What carries warnings: an ObjectDictionaryModel (od/model.py imports this module, so
    this one names only what it reads; no import cycle, not even for types)."""

    @property
    def warnings(self) -> Sequence[LintWarning]: ...


def lint_report(model: Linted) -> str:
    """One warning per line, in file order, for a CLI or a log."""
    return "\n".join(format_warning(w) for w in sort_warnings(model.warnings))


def sort_warnings(warnings: Iterable[LintWarning]) -> list[LintWarning]:
    return sorted(warnings, key=lambda w: (w.line is not None, w.line or 0))


def count_by_code(warnings: Iterable[LintWarning]) -> dict[str, int]:
    counts: dict[str, int] = {}
    for w in warnings:
        counts[w.code] = counts.get(w.code, 0) + 1
    return counts
