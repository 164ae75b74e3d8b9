"""One EDS object or sub-object section -> OdSub (CiA 306; keys read case-insensitively)."""

from __future__ import annotations

from dataclasses import dataclass, field

from servodesk.od import datatypes as dt
from servodesk.od.ini_reader import IniEntry, IniSection
from servodesk.od.lint import Code, WarningSink
from servodesk.od.literals import Parsed, parse_int, parse_literal
from servodesk.od.model import Access, OdSub

ACCESS_TYPES: dict[str, Access] = {
    "ro": "ro",
    "wo": "wo",
    "rw": "rw",
    "rwr": "rwr",
    "rww": "rww",
    "const": "const",
}
KNOWN_KEYS = frozenset(
    key.casefold()
    for key in (
        "ParameterName",
        "ObjectType",
        "DataType",
        "AccessType",
        "DefaultValue",
        "PDOMapping",
        "LowLimit",
        "HighLimit",
        "ParameterValue",
        "SubNumber",
        "CompactSubObj",
        "ObjFlags",
        "StorageLocation",
        "Denotation",
        "UploadFile",
        "DownloadFile",
        "Count",
        "ParamRefd",
        # python-canopen extensions, read as such
        "Unit",
        "Factor",
        "Description",
    )
)
_ASSUMED_ACCESS: Access = "ro"  # unknown access: never offer a write the drive may refuse


_TALLY_TEXT = {
    Code.ACCESS_CASE: "AccessType is written in upper or mixed case ({details}) in {count} "
    "entries; CiA 306 uses lower case. Read case-insensitively",
    Code.NODEID_CASE: "$NODEID is spelt {details} in {count} entries; CiA 306 writes $NODEID. "
    "Read as node-relative",
    Code.ARRAY_WITHOUT_DATATYPE: "{count} ARRAY objects have no DataType of their own ({details}); "
    "each sub-entry's DataType is used. CiA 306 allows this, but some tools crash on it "
    "(ros2_canopen issue 202)",
}


@dataclass
class _Tally:
    """Harmless oddities repeated all over a file: one info line with a count, not one each."""

    first: tuple[int | None, str, str | None]  # line, section, key of the first occurrence
    details: list[str] = field(default_factory=list)


class EntryBuilder:
    def __init__(self, sink: WarningSink, node_id: int | None) -> None:
        self.sink = sink
        self.node_id = node_id
        self._tallies: dict[Code, _Tally] = {}

    def tally(
        self, code: Code, detail: str, *, line: int | None, section: str, key: str | None
    ) -> None:
        self._tallies.setdefault(code, _Tally((line, section, key))).details.append(detail)

    def report_tallies(self) -> None:
        for code, tally in self._tallies.items():
            line, section, key = tally.first
            unique = sorted(set(tally.details))
            details = ", ".join(unique[:5]) + (", ..." if len(unique) > 5 else "")
            self.sink.add(
                code,
                _TALLY_TEXT[code].format(count=len(tally.details), details=details),
                line=line,
                section=section,
                key=key,
                severity="info",
            )

    def name(self, section: IniSection, fallback: str) -> str:
        entry = section.get("ParameterName")
        if entry is not None and entry.raw:
            return entry.raw
        self.sink.add(
            Code.MISSING_NAME,
            f"ParameterName is missing or empty; shown as '{fallback}'",
            line=section.line,
            section=section.name,
        )
        return fallback

    def entry(
        self,
        section: IniSection,
        index: int,
        subindex: int,
        *,
        name: str | None = None,
        array_type: int | None = None,
    ) -> OdSub:
        if name is None:
            name = self.name(section, f"{index:04X}sub{subindex:X}")
        data_type = self._data_type(section, array_type)
        default = self._value(section, "DefaultValue", data_type)
        value = self._value(section, "ParameterValue", data_type)
        low = self._limit(section, "LowLimit", data_type)
        high = self._limit(section, "HighLimit", data_type)
        self._check_range(section, default, value, low, high)
        self._check_unknown_keys(section)
        return OdSub(
            index=index,
            subindex=subindex,
            name=name,
            data_type=data_type,
            access=self._access(section),
            pdo_mappable=bool(self._integer(section, "PDOMapping")),
            default=default.value if default else None,
            default_raw=_raw(section, "DefaultValue", data_type),
            relative=bool(default and default.relative),
            low=low,
            high=high,
            unit=section.text("Unit"),
            value=value.value if value else None,
            description=_raw(section, "Description", dt.DataType.VISIBLE_STRING) or "",
            value_raw=_raw(section, "ParameterValue", data_type),
            value_relative=bool(value and value.relative),
            factor=self._factor(section),
            obj_flags=self._integer(section, "ObjFlags", severity_info=True) or 0,
            line=section.line,
        )

    def _data_type(self, section: IniSection, array_type: int | None) -> int:
        entry = section.get("DataType")
        code: int | None = None
        if entry is not None:
            try:
                code = parse_int(entry.value)[0]
            except ValueError:
                code = None
        if code is None:
            fallback = array_type if array_type is not None else dt.DataType.DOMAIN
            what = "is missing" if entry is None else f"'{entry.value}' is not a number"
            source = "the array's" if array_type is not None else "DOMAIN (raw bytes)"
            self.sink.add(
                Code.MISSING_DATATYPE,
                f"DataType {what}; using {source} {dt.type_name(fallback)}",
                line=section.line if entry is None else entry.line,
                section=section.name,
                key="DataType",
            )
            return fallback
        if not dt.is_known(code):
            # DEFTYPE/DEFSTRUCT codes (0x20.. 0x25F) need the type's own object; read as bytes
            self.sink.add(
                Code.UNKNOWN_DATATYPE,
                f"DataType 0x{code:04X} is not a CiA 301 basic type; values read as raw bytes",
                line=entry.line if entry else section.line,
                section=section.name,
                key="DataType",
            )
            return dt.DataType.DOMAIN
        return code

    def _access(self, section: IniSection) -> Access:
        entry = section.get("AccessType")
        if entry is None:
            self.sink.add(
                Code.BAD_ACCESS,
                f"AccessType is missing; assumed '{_ASSUMED_ACCESS}'",
                line=section.line,
                section=section.name,
                key="AccessType",
            )
            return _ASSUMED_ACCESS
        access = ACCESS_TYPES.get(entry.value.lower())
        if access is None:
            self.sink.add(
                Code.BAD_ACCESS,
                f"AccessType '{entry.value}' is not ro/wo/rw/rwr/rww/const; assumed "
                f"'{_ASSUMED_ACCESS}'",
                line=entry.line,
                section=section.name,
                key=entry.key,
            )
            return _ASSUMED_ACCESS
        if entry.value != access:
            self.tally(
                Code.ACCESS_CASE, entry.value, line=entry.line, section=section.name, key=entry.key
            )
        return access

    def _value(self, section: IniSection, key: str, data_type: int) -> Parsed | None:
        entry = section.get(key)
        if entry is None:
            return None
        text = entry.raw if dt.is_text(data_type) else entry.value
        if entry.comment is not None and not dt.is_text(data_type):
            self.sink.add(
                Code.INLINE_COMMENT,
                f"{key} '{entry.raw}' has a comment after the value; read as '{entry.value}'",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="info",
            )
        if not text and not dt.is_text(data_type) and not dt.is_bytes(data_type):
            self.sink.add(
                Code.EMPTY_VALUE,
                f"{key} is empty; no {key} for this {dt.type_name(data_type)} entry",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="info",
            )
            return None
        parsed = parse_literal(text, data_type, key=key, node_id=self.node_id)
        self._report(parsed, section, entry)
        return parsed

    def _limit(self, section: IniSection, key: str, data_type: int) -> int | float | None:
        if not (dt.is_integer(data_type) or dt.is_float(data_type)):
            return None
        parsed = self._value(section, key, data_type)
        if parsed is None or not isinstance(parsed.value, int | float):
            return None
        return parsed.value

    def _report(self, parsed: Parsed, section: IniSection, entry: IniEntry) -> None:
        for note in parsed.notes:
            if note.code in _TALLY_TEXT:
                self.tally(
                    note.code, note.detail, line=entry.line, section=section.name, key=entry.key
                )
                continue
            self.sink.add(
                note.code,
                note.message,
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity=note.severity,
            )

    def _check_range(
        self,
        section: IniSection,
        default: Parsed | None,
        value: Parsed | None,
        low: int | float | None,
        high: int | float | None,
    ) -> None:
        if low is not None and high is not None and low > high:
            entry = section.get("LowLimit")
            self.sink.add(
                Code.LIMITS_INVERTED,
                f"LowLimit {low} is above HighLimit {high}; limits not checked",
                line=entry.line if entry else section.line,
                section=section.name,
                key="LowLimit",
            )
            return
        for key, parsed in (("DefaultValue", default), ("ParameterValue", value)):
            if parsed is None or parsed.relative or not isinstance(parsed.value, int | float):
                continue
            if (low is not None and parsed.value < low) or (
                high is not None and parsed.value > high
            ):
                entry = section.get(key)
                self.sink.add(
                    Code.DEFAULT_OUT_OF_RANGE,
                    f"{key} {parsed.value} lies outside LowLimit..HighLimit "
                    f"({_show(low)}..{_show(high)}); kept as written",
                    line=entry.line if entry else section.line,
                    section=section.name,
                    key=key,
                )

    def _integer(self, section: IniSection, key: str, *, severity_info: bool = False) -> int | None:
        entry = section.get(key)
        if entry is None or not entry.value:
            return None
        try:
            return parse_int(entry.value)[0]
        except ValueError:
            self.sink.add(
                Code.BAD_INTEGER,
                f"{key} '{entry.value}' is not a number; ignored",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="info" if severity_info else "warning",
            )
            return None

    def _factor(self, section: IniSection) -> float:
        entry = section.get("Factor")
        if entry is None or not entry.value:
            return 1.0
        try:
            return float(entry.value)
        except ValueError:
            self.sink.add(
                Code.BAD_FLOAT,
                f"Factor '{entry.value}' is not a number; using 1",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="info",
            )
            return 1.0

    def _check_unknown_keys(self, section: IniSection) -> None:
        for key, entry in section.entries.items():
            if key not in KNOWN_KEYS:
                self.sink.add(
                    Code.UNKNOWN_KEY,
                    f"Key '{entry.key}' is not part of CiA 306; ignored",
                    line=entry.line,
                    section=section.name,
                    key=entry.key,
                    severity="info",
                )


def _raw(section: IniSection, key: str, data_type: int) -> str | None:
    entry = section.get(key)
    if entry is None:
        return None
    return entry.raw if dt.is_text(data_type) else entry.value


def _show(limit: int | float | None) -> str:
    return "" if limit is None else str(limit)
