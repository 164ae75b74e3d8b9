"""Model + current values -> DCF text (CiA 306: an EDS plus ParameterValue and NodeID).

canopen's `export_od` is not used, because it does not round-trip: it writes negative integers
as `0x-5`, which its own importer then drops without a word, writes CreationTime with the month
in place of the minutes, and reads the wall clock, so the same input gives different files.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping

from servodesk.od import datatypes as dt
from servodesk.od.model import ObjectDictionaryModel, OdObject, OdSub

_MANDATORY = (0x1000, 0x1001, 0x1018)  # Device type, Error register, Identity object
_MANUFACTURER = range(0x2000, 0x6000)
_OBJECT_TYPE = {"var": 0x7, "domain": 0x2, "array": 0x8, "record": 0x9}


def export_dcf(
    model: ObjectDictionaryModel, values: Mapping[tuple[int, int], object], *, node_id: int
) -> str:
    """`values` maps (index, sub-index) to the value read from or written to the node.

    Entries without a value keep the ParameterValue the model was loaded with, if any. Raises
    ValueError when a value names an entry the model does not have or does not fit its type.
    """
    unknown = sorted(key for key in values if model.get(*key) is None)
    if unknown:
        shown = ", ".join(f"{i:04X}h sub {s}" for i, s in unknown[:5])
        raise ValueError(f"values for entries not in the object dictionary: {shown}")
    lines: list[str] = []
    _file_and_device(model, node_id, lines)
    mandatory = [i for i in _MANDATORY if i in model.objects]
    manufacturer = [i for i in model.objects if i in _MANUFACTURER]
    optional = [i for i in model.objects if i not in mandatory and i not in _MANUFACTURER]
    for list_name, indices in (
        ("MandatoryObjects", mandatory),
        ("OptionalObjects", optional),
        ("ManufacturerObjects", manufacturer),
    ):
        lines += ["", f"[{list_name}]", f"SupportedObjects={len(indices)}"]
        lines += [f"{n}=0x{index:04X}" for n, index in enumerate(indices, start=1)]
        for index in indices:
            _object(model.objects[index], values, model.node_id, lines)
    return "\n".join(lines) + "\n"


def _file_and_device(model: ObjectDictionaryModel, node_id: int, lines: list[str]) -> None:
    device = model.device
    lines += ["[FileInfo]", f"FileName={device.file_name}"]
    if device.file_version is not None:
        lines.append(f"FileVersion={device.file_version}")
    if device.file_revision is not None:
        lines.append(f"FileRevision={device.file_revision}")
    lines += ["EDSVersion=4.0", f"Description={device.description}"]
    lines += [f"CreatedBy={device.created_by}", f"ModifiedBy={device.modified_by}"]
    lines.append(f"LastEDS={model.source.replace(chr(92), '/').rsplit('/', 1)[-1]}")
    lines += ["", "[DeviceInfo]", f"VendorName={device.vendor_name}"]
    for key, number in (
        ("VendorNumber", device.vendor_number),
        ("ProductNumber", device.product_number),
        ("RevisionNumber", device.revision_number),
    ):
        if number is not None:
            lines.append(f"{key}=0x{number:08X}")
    lines += [f"ProductName={device.product_name}", f"OrderCode={device.order_code}"]
    lines += [f"BaudRate_{k}={int(k * 1000 in device.baud_rates)}" for k in _KBIT]
    for key, flag in (
        ("SimpleBootUpMaster", device.simple_boot_up_master),
        ("SimpleBootUpSlave", device.simple_boot_up_slave),
        ("DynamicChannelsSupported", device.dynamic_channels_supported),
        ("GroupMessaging", device.group_messaging),
        ("LSS_Supported", device.lss_supported),
    ):
        lines.append(f"{key}={int(flag)}")
    for key, count in (
        ("Granularity", device.granularity),
        ("NrOfRXPDO", device.nr_rx_pdo),
        ("NrOfTXPDO", device.nr_tx_pdo),
        ("CompactPDO", device.compact_pdo),
    ):
        if count is not None:
            lines.append(f"{key}={count}")
    lines += ["", "[DummyUsage]"]
    lines += [f"Dummy{i:04d}={int(i in device.dummy_usage)}" for i in range(1, 8)]
    comments = device.comments.splitlines()
    lines += ["", "[Comments]", f"Lines={len(comments)}"]
    lines += [f"Line{n}={text}" for n, text in enumerate(comments, start=1)]
    lines += ["", "[DeviceComissioning]", f"NodeID={node_id}", f"NodeName={device.node_name}"]
    if device.baud_rate is not None:
        lines.append(f"Baudrate={device.baud_rate // 1000}")
    if device.net_number is not None:
        lines.append(f"NetNumber={device.net_number}")


_KBIT = (10, 20, 50, 125, 250, 500, 800, 1000)


def _object(
    obj: OdObject,
    values: Mapping[tuple[int, int], object],
    loaded_for: int | None,
    lines: list[str],
) -> None:
    section = f"{obj.index:04X}"
    object_type = _OBJECT_TYPE[obj.object_type]
    if obj.object_type in ("var", "domain") and 0 in obj.subs:
        _entry(section, object_type, obj.subs[0], values, loaded_for, lines)
        return
    lines += ["", f"[{section}]", f"ParameterName={obj.name}", f"ObjectType=0x{object_type:X}"]
    lines.append(f"SubNumber={len(obj.subs)}")
    for subindex in sorted(obj.subs):
        _entry(f"{section}sub{subindex:X}", 0x7, obj.subs[subindex], values, loaded_for, lines)


def _entry(
    section: str,
    object_type: int,
    sub: OdSub,
    values: Mapping[tuple[int, int], object],
    loaded_for: int | None,
    lines: list[str],
) -> None:
    lines += ["", f"[{section}]", f"ParameterName={sub.name}", f"ObjectType=0x{object_type:X}"]
    lines += [f"DataType=0x{sub.data_type:04X}", f"AccessType={sub.access}"]
    if sub.default is not None:
        lines.append(f"DefaultValue={_kept(sub, sub.default, sub.relative, loaded_for)}")
    lines.append(f"PDOMapping={int(sub.pdo_mappable)}")
    if sub.low is not None:
        lines.append(f"LowLimit={_literal(sub, sub.low)}")
    if sub.high is not None:
        lines.append(f"HighLimit={_literal(sub, sub.high)}")
    if sub.obj_flags:
        lines.append(f"ObjFlags=0x{sub.obj_flags:X}")
    if (sub.index, sub.subindex) in values:
        lines.append(f"ParameterValue={_literal(sub, values[(sub.index, sub.subindex)])}")
    elif sub.value is not None:
        lines.append(f"ParameterValue={_kept(sub, sub.value, sub.value_relative, loaded_for)}")


def _kept(sub: OdSub, value: object, relative: bool, loaded_for: int | None) -> str:
    """A value from the loaded file, node-relative again if it was written so."""
    if relative and isinstance(value, int):
        return f"$NODEID+0x{value - (loaded_for or 0):X}"
    return _literal(sub, value)


def _literal(sub: OdSub, value: object) -> str:
    """A value as CiA 306 files write it."""
    data_type = sub.data_type
    if dt.is_text(data_type):
        if not isinstance(value, str):
            raise ValueError(f"{sub.index:04X}h sub {sub.subindex}: expected text, got {value!r}")
        if "\n" in value or "\r" in value:
            raise ValueError(
                f"{sub.index:04X}h sub {sub.subindex}: a line break cannot go in a DCF"
            )
        return value
    if dt.is_bytes(data_type) or not dt.is_known(data_type):
        if not isinstance(value, bytes | bytearray):
            raise ValueError(f"{sub.index:04X}h sub {sub.subindex}: expected bytes, got {value!r}")
        return bytes(value).hex().upper()
    if dt.is_float(data_type) and isinstance(value, int | float) and not isinstance(value, bool):
        # CiA 306: the bit pattern; decimals are refused by strict tools such as Lely's dcfchk
        fmt, size = (">f", 4) if data_type == dt.DataType.REAL32 else (">d", 8)
        return "0x" + struct.pack(fmt, value).hex().upper().rjust(2 * size, "0")
    if not isinstance(value, int):
        raise ValueError(f"{sub.index:04X}h sub {sub.subindex}: expected a number, got {value!r}")
    low, high = dt.int_range(data_type)
    if not low <= value <= high:
        raise ValueError(
            f"{sub.index:04X}h sub {sub.subindex}: {value} does not fit {dt.type_name(data_type)}"
        )
    return str(value) if value < 0 else f"0x{value:X}"
