"""CiA 311 XDD/XDC (and CANopenNode's .xpd project files) -> DeviceInfo and objects.

A cheap subset: identity, bit rates, PDO counts, objects and sub-objects with type, access,
PDO mapping, default, limits and names. Standard XDDs carry these as CANopenObject attributes;
CANopenEditor writes them into the ApplicationProcess parameter the object refers to
(uniqueIDRef). Both are read; the CANopenObject attribute wins.
"""

from __future__ import annotations

import re

from servodesk.od import datatypes as dt
from servodesk.od.entries import ACCESS_TYPES
from servodesk.od.lint import Code, WarningSink
from servodesk.od.literals import decimal, parse_literal
from servodesk.od.model import Access, DeviceInfo, ObjectKind, OdObject, OdSub, Value
from servodesk.od.xdd_device import read_xdd_device
from servodesk.od.xml_tree import Node, parse_xml, text_child

# CiA 311: IEC 61131 type elements of ApplicationProcess parameters
_XML_TYPES: dict[str, int] = {
    "BOOL": dt.DataType.BOOLEAN,
    "SINT": dt.DataType.INTEGER8,
    "INT": dt.DataType.INTEGER16,
    "DINT": dt.DataType.INTEGER32,
    "LINT": dt.DataType.INTEGER64,
    "USINT": dt.DataType.UNSIGNED8,
    "UINT": dt.DataType.UNSIGNED16,
    "UDINT": dt.DataType.UNSIGNED32,
    "ULINT": dt.DataType.UNSIGNED64,
    "BYTE": dt.DataType.UNSIGNED8,
    "WORD": dt.DataType.UNSIGNED16,
    "DWORD": dt.DataType.UNSIGNED32,
    "LWORD": dt.DataType.UNSIGNED64,
    "REAL": dt.DataType.REAL32,
    "LREAL": dt.DataType.REAL64,
    "STRING": dt.DataType.VISIBLE_STRING,
    "WSTRING": dt.DataType.UNICODE_STRING,
    "BITSTRING": dt.DataType.OCTET_STRING,  # CANopenEditor also writes DOMAIN as BITSTRING
}
_PARAMETER_ACCESS: dict[str, Access] = {
    "const": "const",
    "read": "ro",
    "write": "wo",
    "readWrite": "rw",
    "readWriteInput": "rwr",
    "readWriteOutput": "rww",
    "noAccess": "ro",
}
_HEX = re.compile(r"\s*(?:0[xX])?([0-9A-Fa-f]+)\s*")
_OBJECT_TYPES: dict[int, ObjectKind] = {0x2: "domain", 0x7: "var", 0x8: "array", 0x9: "record"}


def read_xdd(
    data: bytes, sink: WarningSink, node_id: int | None
) -> tuple[DeviceInfo, dict[int, OdObject]]:
    root = parse_xml(data, sink.file)
    if root.tag != "ISO15745ProfileContainer":
        sink.add(
            Code.XML,
            f"Root element is <{root.tag}>, not an ISO 15745 profile container",
            line=root.line,
            severity="info",
        )
    params = {p.attrib["uniqueID"]: p for p in root.iter("parameter") if "uniqueID" in p.attrib}
    arrays = _array_types(root)
    reader = _ObjectReader(sink, node_id, params, arrays)
    objects: dict[int, OdObject] = {}
    for node in root.iter("CANopenObject"):
        obj = reader.read(node)
        if obj is not None:
            objects[obj.index] = obj
    return read_xdd_device(root, sink), dict(sorted(objects.items()))


def _array_types(root: Node) -> dict[str, int]:
    """dataTypeList arrays: uniqueID -> element type code."""
    types: dict[str, int] = {}
    for array in root.iter("array"):
        for child in array.children:
            if child.tag in _XML_TYPES:
                types[array.attrib.get("uniqueID", "")] = _XML_TYPES[child.tag]
    return types


class _ObjectReader:
    def __init__(
        self,
        sink: WarningSink,
        node_id: int | None,
        params: dict[str, Node],
        arrays: dict[str, int],
    ) -> None:
        self.sink = sink
        self.node_id = node_id
        self.params = params
        self.arrays = arrays

    def read(self, node: Node) -> OdObject | None:
        index = _hex(node.attrib.get("index", ""), 0xFFFF)
        if index is None:
            self.sink.add(
                Code.XML,
                f"CANopenObject index '{node.attrib.get('index')}' is not hex 0..FFFF; "
                "object ignored",
                line=node.line,
                severity="error",
            )
            return None
        section = f"{index:04X}"
        param = self.params.get(node.attrib.get("uniqueIDRef", ""))
        if param is not None and _property(param, "CO_disabled") == "true":
            self.sink.add(
                Code.DISABLED_OBJECT,
                "Object is disabled in this CANopenNode project; "
                "left out as the device does not have it",
                line=node.line,
                section=section,
                severity="info",
            )
            return None
        name = node.attrib.get("name") or _label(param) or f"Object {index:04X}h"
        kind = self._kind(node, section)
        if kind in ("var", "domain"):
            return OdObject(
                index, name, kind, {0: self._sub(node, param, index, 0, None)}, node.line
            )
        element_type = self.arrays.get(_type_ref(param) or "")
        subs: dict[int, OdSub] = {}
        for child in node.findall("CANopenSubObject"):
            subindex = _hex(child.attrib.get("subIndex", ""), 0xFF)
            if subindex is None:
                self.sink.add(
                    Code.XML,
                    "CANopenSubObject has no hex subIndex 0..FF; ignored",
                    line=child.line,
                    severity="error",
                    section=section,
                )
                continue
            child_param = self.params.get(child.attrib.get("uniqueIDRef", ""))
            subs[subindex] = self._sub(child, child_param, index, subindex, element_type)
        declared = node.attrib.get("subNumber")
        number = decimal(declared) if declared is not None else None
        if number is not None and number != len(subs):
            self.sink.add(
                Code.SUBNUMBER_MISMATCH,
                f"subNumber is {declared} but {len(subs)} "
                "sub-objects are defined; the ones present are used",
                line=node.line,
                section=section,
                key="subNumber",
            )
        if not subs:
            self.sink.add(
                Code.NO_SUBENTRIES,
                f"{kind.upper()} {index:04X}h has no sub-objects",
                line=node.line,
                section=section,
            )
        return OdObject(index, name, kind, subs, node.line)

    def _kind(self, node: Node, section: str) -> ObjectKind:
        text = node.attrib.get("objectType", "7")
        code = decimal(text)
        kind = _OBJECT_TYPES.get(-1 if code is None else code)
        if kind is None:
            kind = "record" if node.find("CANopenSubObject") else "var"
            self.sink.add(
                Code.BAD_OBJECT_TYPE,
                f"objectType '{text}' unknown; read as {kind.upper()}",
                line=node.line,
                section=section,
                key="objectType",
            )
        return kind

    def _sub(
        self, node: Node, param: Node | None, index: int, subindex: int, element_type: int | None
    ) -> OdSub:
        section = f"{index:04X}" if node.tag == "CANopenObject" else f"{index:04X}sub{subindex:X}"
        attrs = node.attrib
        data_type = self._data_type(node, param, element_type, section)
        default_text = attrs.get("defaultValue", _child_value(param, "defaultValue"))
        value_text = attrs.get("actualValue", _child_value(param, "actualValue"))
        default = self._literal(default_text, data_type, "defaultValue", node, section)
        value = self._literal(value_text, data_type, "actualValue", node, section)
        low_text = attrs.get("lowLimit", _range_value(param, "minValue"))
        high_text = attrs.get("highLimit", _range_value(param, "maxValue"))
        low = self._limit(low_text, data_type, "lowLimit", node, section)
        high = self._limit(high_text, data_type, "highLimit", node, section)
        self._check_range(default[0], low, high, node, section)
        return OdSub(
            index=index,
            subindex=subindex,
            name=attrs.get("name") or _label(param) or section,
            data_type=data_type,
            access=self._access(node, param, section),
            pdo_mappable=attrs.get("PDOmapping", "no") != "no",
            default=default[0],
            default_raw=default_text,
            relative=default[1],
            low=low,
            high=high,
            value=value[0],
            description=text_child(param, "description"),
            value_raw=value_text,
            value_relative=value[1],
            line=node.line,
        )

    def _data_type(self, node: Node, param: Node | None, fallback: int | None, section: str) -> int:
        text = node.attrib.get("dataType")
        if text:
            try:
                code = int(text, 16)
            except ValueError:
                code = -1
            if dt.is_known(code):
                return code
            self.sink.add(
                Code.UNKNOWN_DATATYPE,
                f"dataType '{text}' is not a CiA 301 basic type; values read as raw bytes",
                line=node.line,
                section=section,
                key="dataType",
            )
            return dt.DataType.DOMAIN
        for child in param.children if param is not None else []:
            if child.tag in _XML_TYPES:
                return _XML_TYPES[child.tag]
        if fallback is not None:
            return fallback
        self.sink.add(
            Code.MISSING_DATATYPE,
            "No data type; values read as raw bytes (DOMAIN)",
            line=node.line,
            section=section,
        )
        return dt.DataType.DOMAIN

    def _access(self, node: Node, param: Node | None, section: str) -> Access:
        text = node.attrib.get("accessType")
        if text is not None:
            access = ACCESS_TYPES.get(text.lower())
        else:
            # CiA 311: a parameter without `access` is read-only
            text = param.attrib.get("access", "read") if param is not None else "read"
            access = _PARAMETER_ACCESS.get(text)
        if access is None:
            self.sink.add(
                Code.BAD_ACCESS,
                f"Access '{text}' unknown; assumed 'ro'",
                line=node.line,
                section=section,
            )
            return "ro"
        return access

    def _literal(
        self, text: str | None, data_type: int, key: str, node: Node, section: str
    ) -> tuple[Value | None, bool]:
        if text is None:
            return None, False
        parsed = parse_literal(text, data_type, key=key, node_id=self.node_id, decimal_floats=True)
        for note in parsed.notes:
            self.sink.add(
                note.code,
                note.message,
                line=node.line,
                section=section,
                key=key,
                severity=note.severity,
            )
        return parsed.value, parsed.relative

    def _limit(
        self, text: str | None, data_type: int, key: str, node: Node, section: str
    ) -> int | float | None:
        if text is None or not (dt.is_integer(data_type) or dt.is_float(data_type)):
            return None
        value = self._literal(text, data_type, key, node, section)[0]
        return value if isinstance(value, int | float) else None

    def _check_range(
        self,
        default: Value | None,
        low: int | float | None,
        high: int | float | None,
        node: Node,
        section: str,
    ) -> None:
        if not isinstance(default, int | float):
            return
        if (low is not None and default < low) or (high is not None and default > high):
            self.sink.add(
                Code.DEFAULT_OUT_OF_RANGE,
                f"defaultValue {default} lies outside {low}..{high}; kept as written",
                line=node.line,
                section=section,
                key="defaultValue",
            )


def _hex(text: str, highest: int) -> int | None:
    """An index or sub-index: ASCII hex (int(x, 16) also takes "-1", "1_0" and Arabic digits)."""
    match = _HEX.fullmatch(text)
    if match is None:
        return None
    value = int(match.group(1), 16)
    return value if value <= highest else None


def _property(param: Node, name: str) -> str | None:
    for prop in param.findall("property"):
        if prop.attrib.get("name") == name:
            return prop.attrib.get("value")
    return None


def _label(param: Node | None) -> str:
    return text_child(param, "label")


def _type_ref(param: Node | None) -> str | None:
    ref = param.find("dataTypeIDRef") if param is not None else None
    return ref.attrib.get("uniqueIDRef") if ref is not None else None


def _child_value(param: Node | None, tag: str) -> str | None:
    child = param.find(tag) if param is not None else None
    return child.attrib.get("value") if child is not None else None


def _range_value(param: Node | None, tag: str) -> str | None:
    if param is None:
        return None
    for allowed in param.findall("allowedValues"):
        for value_range in allowed.findall("range"):
            child = value_range.find(tag)
            if child is not None:
                return child.attrib.get("value")
    return None
