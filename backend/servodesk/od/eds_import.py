"""EDS/DCF sections -> ObjectDictionaryModel objects, with a warning for every repair (CiA 306)."""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

from servodesk.od import datatypes as dt
from servodesk.od.entries import KNOWN_KEYS, EntryBuilder
from servodesk.od.ini_reader import IniDocument, IniEntry, IniSection
from servodesk.od.lint import Code, WarningSink
from servodesk.od.literals import decimal, parse_int, parse_literal
from servodesk.od.model import ObjectKind, OdObject, OdSub

_TOP = re.compile(r"[0-9A-Fa-f]{4}")
_SUB = re.compile(r"([0-9A-Fa-f]{4})sub([0-9A-Fa-f]{1,2})", re.IGNORECASE)
_AUX = re.compile(r"([0-9A-Fa-f]{4})(Name|Value|Denotation)", re.IGNORECASE)
_OBJECT_LISTS = ("MandatoryObjects", "OptionalObjects", "ManufacturerObjects")
KNOWN_SECTIONS = frozenset(
    name.casefold()
    for name in (
        "FileInfo",
        "DeviceInfo",
        "DummyUsage",
        "Comments",
        "DeviceComissioning",
        "DynamicChannels",
        "Tools",
        "SupportedModules",
        "ConnectedModules",
        *_OBJECT_LISTS,
    )
)
# CiA 306 ObjectType codes
_OBJECT_TYPES: dict[int, ObjectKind] = {
    0x2: "domain",
    0x5: "var",  # DEFTYPE
    0x6: "record",  # DEFSTRUCT
    0x7: "var",
    0x8: "array",
    0x9: "record",
}
_RECORD_KEYS = frozenset(
    k.casefold()
    for k in (
        "ParameterName",
        "ObjectType",
        "SubNumber",
        "ObjFlags",
        "StorageLocation",
        "Denotation",
    )
)
# CompactSubObj arrays describe their elements on the object's own section (CiA 306)
_ARRAY_KEYS = _RECORD_KEYS | {
    "datatype",
    "compactsubobj",
    "accesstype",
    "defaultvalue",
    "pdomapping",
    "lowlimit",
    "highlimit",
    "parametervalue",
}


@dataclass
class _Layout:
    tops: dict[int, IniSection]
    subs: dict[int, dict[int, IniSection]]
    aux: dict[tuple[int, str], IniSection]


def read_objects(doc: IniDocument, sink: WarningSink, node_id: int | None) -> dict[int, OdObject]:
    layout = _layout(doc, sink)
    builder = EntryBuilder(sink, node_id)
    objects: dict[int, OdObject] = {}
    for index in sorted(layout.tops):
        objects[index] = _read_object(index, layout, builder, sink)
    for index in sorted(set(layout.subs) - set(layout.tops)):
        first = min(layout.subs[index].values(), key=lambda s: s.line)
        sink.add(
            Code.STRAY_SUBSECTION,
            f"[{first.name}] has no [{index:04X}] section; its {len(layout.subs[index])} "
            "sub-entries are ignored",
            line=first.line,
            section=first.name,
            severity="error",
        )
    builder.report_tallies()
    _check_object_lists(doc, objects, sink)
    return objects


def _layout(doc: IniDocument, sink: WarningSink) -> _Layout:
    layout = _Layout({}, {}, {})
    for section in doc.sections.values():
        name = section.name
        if _TOP.fullmatch(name):
            layout.tops[int(name, 16)] = section
        elif match := _SUB.fullmatch(name):
            index, sub = int(match.group(1), 16), int(match.group(2), 16)
            layout.subs.setdefault(index, {})[sub] = section
        elif match := _AUX.fullmatch(name):
            layout.aux[(int(match.group(1), 16), match.group(2).casefold())] = section
        elif name.casefold() not in KNOWN_SECTIONS and not name.casefold().startswith("tool"):
            sink.add(
                Code.UNKNOWN_SECTION,
                f"Section [{name}] is not part of CiA 306; ignored",
                line=section.line,
                section=name,
                severity="info",
            )
    return layout


def _read_object(index: int, layout: _Layout, builder: EntryBuilder, sink: WarningSink) -> OdObject:
    section = layout.tops[index]
    name = builder.name(section, f"Object {index:04X}h")
    kind = _object_kind(section, sink)
    subs = layout.subs.get(index, {})
    if kind in ("var", "domain"):
        if subs:
            first = min(subs.values(), key=lambda s: s.line)
            sink.add(
                Code.STRAY_SUBSECTION,
                f"[{section.name}] is a single value (VAR) but has sub-sections like "
                f"[{first.name}]; they are ignored",
                line=first.line,
                section=first.name,
            )
        var = builder.entry(section, index, 0, name=name)
        return OdObject(index, name, kind, {0: var}, section.line)
    compact = section.get("CompactSubObj")
    if kind == "array" and compact is not None and compact.value not in ("", "0"):
        entries = _compact_array(index, name, section, layout, builder, sink)
    else:
        array_type = _array_type(section, kind, builder)
        entries = {
            sub: builder.entry(subs[sub], index, sub, array_type=array_type) for sub in sorted(subs)
        }
        _check_sub_number(section, len(entries), sink)
        _check_highest_subindex(entries, sink)
        _check_top_keys(section, kind, sink)
    if not entries:
        sink.add(
            Code.NO_SUBENTRIES,
            f"{kind.upper()} {index:04X}h '{name}' has no sub-entries; only its name is known",
            line=section.line,
            section=section.name,
        )
    return OdObject(index, name, kind, entries, section.line)


def _object_kind(section: IniSection, sink: WarningSink) -> ObjectKind:
    entry = section.get("ObjectType")
    if entry is None:
        return "var"  # CiA 306 §4.6.3.2: a missing ObjectType means VAR
    try:
        code, _ = parse_int(entry.value)
    except ValueError:
        code = -1
    kind = _OBJECT_TYPES.get(code)
    if kind is not None:
        return kind
    guess: ObjectKind = "var" if section.get("DataType") is not None else "record"
    sink.add(
        Code.BAD_OBJECT_TYPE,
        f"ObjectType '{entry.value}' is not VAR/ARRAY/RECORD/DOMAIN; read as {guess.upper()}",
        line=entry.line,
        section=section.name,
        key=entry.key,
    )
    return guess


def _array_type(section: IniSection, kind: ObjectKind, builder: EntryBuilder) -> int | None:
    """An ARRAY's DataType is the type of its elements; real files nearly always leave it out."""
    entry = section.get("DataType")
    if entry is not None:
        try:
            return parse_int(entry.value)[0]
        except ValueError:
            return None
    if kind == "array":
        builder.tally(
            Code.ARRAY_WITHOUT_DATATYPE,
            section.name,
            line=section.line,
            section=section.name,
            key=None,
        )
    return None


def _compact_array(
    index: int,
    name: str,
    section: IniSection,
    layout: _Layout,
    builder: EntryBuilder,
    sink: WarningSink,
) -> dict[int, OdSub]:
    """CompactSubObj=N (CiA 306): sub 0 = N, subs 1..N share the object's description.

    Names may come from an [xxxxName] section and, in a DCF, values from [xxxxValue].
    """
    count_entry = section.get("CompactSubObj")
    count = 0
    if count_entry is not None:
        try:
            count = min(max(parse_int(count_entry.value)[0], 0), 0xFE)
        except ValueError:
            sink.add(
                Code.BAD_INTEGER,
                f"CompactSubObj '{count_entry.value}' is not a number; no sub-entries made",
                line=count_entry.line,
                section=section.name,
                key=count_entry.key,
            )
    names = _numbered(layout.aux.get((index, "name")))
    values = _numbered(layout.aux.get((index, "value")))
    first = builder.entry(section, index, 1, name=name)
    entries: dict[int, OdSub] = {
        0: OdSub(index, 0, "NrOfObjects", dt.DataType.UNSIGNED8, "ro", False, count, str(count))
    }
    for sub in range(1, count + 1):
        sub_name = names[sub].raw if sub in names else f"{name}{sub}"
        entries[sub] = replace(first, subindex=sub, name=sub_name)
        value_entry = values.get(sub)
        if value_entry is None:
            continue
        parsed = parse_literal(
            value_entry.value, first.data_type, key=value_entry.key, node_id=builder.node_id
        )
        for note in parsed.notes:
            sink.add(
                note.code,
                note.message,
                line=value_entry.line,
                section=f"{index:04X}Value",
                key=value_entry.key,
                severity=note.severity,
            )
        entries[sub] = replace(
            entries[sub],
            value=parsed.value,
            value_raw=value_entry.value,
            value_relative=parsed.relative,
        )
    return entries


def _numbered(section: IniSection | None) -> dict[int, IniEntry]:
    """`1=...`, `2=...` keys of an [xxxxName] / [xxxxValue] section."""
    if section is None:
        return {}
    numbered = ((decimal(key), entry) for key, entry in section.entries.items())
    return {number: entry for number, entry in numbered if number is not None}


def _check_sub_number(section: IniSection, found: int, sink: WarningSink) -> None:
    entry = section.get("SubNumber")
    if entry is None:
        return
    try:
        declared = parse_int(entry.value)[0]
    except ValueError:
        return
    if declared != found:
        sink.add(
            Code.SUBNUMBER_MISMATCH,
            f"SubNumber is {declared} but {found} sub-entries are defined; "
            f"the {found} present are used",
            line=entry.line,
            section=section.name,
            key=entry.key,
        )


def _check_highest_subindex(entries: dict[int, OdSub], sink: WarningSink) -> None:
    """Sub 0 of an ARRAY/RECORD holds the highest sub-index; a larger default names a ghost."""
    sub0 = entries.get(0)
    if sub0 is None or not isinstance(sub0.default, int) or len(entries) < 2:
        return
    highest = max(entries)
    if sub0.default > highest:
        sink.add(
            Code.HIGHEST_SUBINDEX,
            f"Sub 0 default {sub0.default} names sub-index {sub0.default}, but the highest one "
            f"defined is {highest}; reads of the missing ones will fail on the drive",
            line=sub0.line,
            section=f"{sub0.index:04X}sub0",
            key="DefaultValue",
        )


def _check_top_keys(section: IniSection, kind: ObjectKind, sink: WarningSink) -> None:
    """Keys on an ARRAY/RECORD's own section that describe values belong in its sub-sections."""
    if kind in ("var", "domain"):
        return
    allowed = _ARRAY_KEYS if kind == "array" else _RECORD_KEYS
    for key, entry in section.entries.items():
        if key in allowed:
            continue
        known = key in KNOWN_KEYS
        sink.add(
            Code.UNKNOWN_KEY,
            f"{entry.key} has no meaning on a {kind.upper()}'s own section; ignored"
            if known
            else f"Key '{entry.key}' is not part of CiA 306; ignored",
            line=entry.line,
            section=section.name,
            key=entry.key,
            severity="info",
        )


def _check_object_lists(doc: IniDocument, objects: dict[int, OdObject], sink: WarningSink) -> None:
    """The three object lists should name exactly the object sections (CiA 306)."""
    listed: set[int] = set()
    for list_name in _OBJECT_LISTS:
        section = doc.section(list_name)
        if section is None:
            continue
        numbered = [e for k, e in section.entries.items() if k.isdigit()]
        for entry in numbered:
            try:
                index = parse_int(entry.value)[0]
            except ValueError:
                continue
            listed.add(index)
            if index not in objects:
                sink.add(
                    Code.OBJECT_LIST,
                    f"{index:04X}h is listed but has no [{index:04X}] section",
                    line=entry.line,
                    section=section.name,
                    key=entry.key,
                )
        declared = section.get("SupportedObjects")
        if declared is not None:
            try:
                count = parse_int(declared.value)[0]
            except ValueError:
                count = -1
            if count != len(numbered):
                sink.add(
                    Code.OBJECT_LIST,
                    f"SupportedObjects is '{declared.value}' but {len(numbered)} objects "
                    "are listed",
                    line=declared.line,
                    section=section.name,
                    key=declared.key,
                )
    if not listed:
        return
    for index in sorted(set(objects) - listed):
        sink.add(
            Code.OBJECT_LIST,
            f"{index:04X}h has a section but is in no object list; loaded anyway",
            line=objects[index].line,
            section=f"{index:04X}",
            severity="info",
        )
