"""load_od / load_od_bytes: pick the reader by extension (case-insensitive) or by content."""

from __future__ import annotations

from codecs import BOM_UTF16_BE, BOM_UTF16_LE
from pathlib import Path, PurePath

from servodesk.od.checks import check_model
from servodesk.od.eds_device import read_device_info
from servodesk.od.eds_import import read_objects
from servodesk.od.ini_reader import decode_text, read_ini
from servodesk.od.lint import Code, WarningSink
from servodesk.od.model import FileFormat, ObjectDictionaryModel, OdImportError
from servodesk.od.xdd_import import read_xdd

_XML_SUFFIXES = frozenset({".xdd", ".xdc", ".xpd"})
_INI_SUFFIXES = frozenset({".eds", ".dcf"})


def load_od(path: Path | str, *, node_id: int | None = None) -> ObjectDictionaryModel:
    path = Path(path)
    return load_od_bytes(path.read_bytes(), str(path), node_id=node_id)


def load_od_bytes(
    data: bytes, filename: str, *, node_id: int | None = None
) -> ObjectDictionaryModel:
    """Read an uploaded EDS/DCF/XDD/XPD. Raises OdImportError only when nothing is usable."""
    sink = WarningSink(filename)
    suffix = PurePath(filename).suffix.lower()
    encoding = "utf-8"  # XML: expat decodes per the file's declaration
    looks_xml = data.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<")
    if suffix in _INI_SUFFIXES and looks_xml:
        sink.add(Code.XML, f"The {suffix} file holds XML; read as XDD", line=1, severity="warning")
    if looks_xml:
        if suffix not in _XML_SUFFIXES | _INI_SUFFIXES and suffix:
            sink.add(
                Code.XML,
                f"Unknown extension '{suffix}'; the content is XML, read as XDD",
                line=1,
                severity="info",
            )
        device, objects = read_xdd(data, sink, node_id)
        file_format: FileFormat = "xdd"
    else:
        if suffix in _XML_SUFFIXES:
            sink.add(Code.XML, f"The {suffix} file is not XML; read as EDS", line=1)
        if b"\x00" in data[:4096] and not data.startswith((BOM_UTF16_LE, BOM_UTF16_BE)):
            raise OdImportError(f"{filename} is a binary file, not an EDS, DCF or XDD")
        text, encoding = decode_text(data, sink)
        doc = read_ini(text, sink, encoding=encoding)
        if not doc.sections:
            raise OdImportError(f"{filename} has no [sections]: it is not an EDS or DCF file")
        device = read_device_info(doc, sink)
        if node_id is None:
            # a DCF describes one configured node: its values are for that node id (CiA 306)
            node_id = device.node_id
        objects = read_objects(doc, sink, node_id)
        is_dcf = suffix == ".dcf" or (suffix != ".eds" and doc.section("DeviceComissioning"))
        file_format = "dcf" if is_dcf else "eds"
    if not objects:
        raise OdImportError(f"{filename} describes no object dictionary entries")
    check_model(objects, device, sink)
    return ObjectDictionaryModel(
        device=device,
        objects=objects,
        warnings=tuple(sink.items),
        source=filename,
        format=file_format,
        node_id=node_id,
        encoding=encoding,
    )
