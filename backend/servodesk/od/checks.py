"""Checks on the loaded objects that no single section shows: identity, device type, PDO maps."""

from __future__ import annotations

from servodesk.od import datatypes as dt
from servodesk.od.lint import Code, WarningSink
from servodesk.od.model import DeviceInfo, OdObject, OdSub

_DEVICE_TYPE = 0x1000  # Device type
_IDENTITY = 0x1018  # Identity object
# CiA device profile numbers live in 1000h bits 0..15 (CiA 301, object 1000h): 301..499 in use
_PROFILES = range(301, 500)
_RPDO_MAPPING = range(0x1600, 0x1800)  # RPDO mapping parameter
_TPDO_MAPPING = range(0x1A00, 0x1C00)  # TPDO mapping parameter
_DUMMIES = range(0x0001, 0x0008)  # dummy entries (CiA 301: indices 1..7 name data types)


def check_model(objects: dict[int, OdObject], device: DeviceInfo, sink: WarningSink) -> None:
    _check_device_type(objects, sink)
    _check_identity(objects, device, sink)
    for index in sorted(objects):
        if index in _RPDO_MAPPING or index in _TPDO_MAPPING:
            _check_mapping(objects[index], objects, sink)


def _section(sub: OdSub) -> str:
    return f"{sub.index:04X}" if sub.subindex == 0 else f"{sub.index:04X}sub{sub.subindex:X}"


def _check_device_type(objects: dict[int, OdObject], sink: WarningSink) -> None:
    obj = objects.get(_DEVICE_TYPE)
    sub = obj.subs.get(0) if obj else None
    if sub is None or not isinstance(sub.default, int):
        return
    value = sub.default
    profile = value & 0xFFFF
    if profile in _PROFILES or not 0 <= value <= 0xFFFFFFFF:
        return
    swapped = int.from_bytes(value.to_bytes(4, "little"), "big")
    top_byte_profile = 0x0100 | (value >> 24)
    if swapped & 0xFFFF in _PROFILES:
        hint = f"byte-reversed it is 0x{swapped:08X} (profile {swapped & 0xFFFF})"
    elif profile == 0:
        return  # no profile: a device that follows no CiA device profile
    elif top_byte_profile in _PROFILES and 0x01 in value.to_bytes(4, "little")[:3]:
        hint = (
            f"its top byte 0x{value >> 24:02X} is the low byte of profile {top_byte_profile} "
            f"(0x{top_byte_profile:04X})"
        )
    else:
        return
    sink.add(
        Code.BYTE_SWAPPED,
        f"Device type default 0x{value:08X} looks byte-swapped: bits 0..15 (0x{profile:04X}) are "
        f"no CiA profile number, but {hint}. Compare with 1000h read from the drive",
        line=sub.line,
        section=_section(sub),
        key="DefaultValue",
    )


def _check_identity(objects: dict[int, OdObject], device: DeviceInfo, sink: WarningSink) -> None:
    obj = objects.get(_IDENTITY)
    if obj is None:
        return
    pairs = (
        (1, "VendorNumber", device.vendor_number),
        (2, "ProductNumber", device.product_number),
        (3, "RevisionNumber", device.revision_number),
    )
    for subindex, key, declared in pairs:
        sub = obj.subs.get(subindex)
        if sub is None or declared is None or not isinstance(sub.default, int):
            continue
        if sub.default != declared:
            sink.add(
                Code.IDENTITY_MISMATCH,
                f"[DeviceInfo] {key} 0x{declared:X} differs from the 1018h sub {subindex} default "
                f"0x{sub.default:X}; the drive reports the latter",
                line=sub.line,
                section=_section(sub),
                key="DefaultValue",
            )


def _check_mapping(mapping: OdObject, objects: dict[int, OdObject], sink: WarningSink) -> None:
    count_sub = mapping.subs.get(0)
    if count_sub is None or not isinstance(count_sub.default, int):
        return
    for subindex in range(1, count_sub.default + 1):
        entry = mapping.subs.get(subindex)
        if entry is None:
            sink.add(
                Code.PDO_MAPPING,
                f"{mapping.index:04X}h sub 0 says {count_sub.default} entries are mapped but "
                f"sub {subindex} does not exist",
                line=count_sub.line,
                section=_section(count_sub),
                key="DefaultValue",
            )
            return
        if not isinstance(entry.default, int) or entry.default == 0:
            continue
        problem = _mapping_problem(entry.default, objects)
        if problem:
            sink.add(
                Code.PDO_MAPPING,
                f"Default mapping 0x{entry.default:08X}: {problem}",
                line=entry.line,
                section=_section(entry),
                key="DefaultValue",
            )


def _mapping_problem(value: int, objects: dict[int, OdObject]) -> str | None:
    index, subindex, bits = value >> 16, (value >> 8) & 0xFF, value & 0xFF
    if index in _DUMMIES:
        return None
    obj = objects.get(index)
    target = obj.subs.get(subindex) if obj else None
    if target is None:
        return f"{index:04X}h sub {subindex} is not in the object dictionary"
    size = dt.bit_size(target.data_type)
    if size is not None and size != bits:
        return (
            f"maps {bits} bits of {index:04X}h sub {subindex} '{target.name}', which is "
            f"{dt.type_name(target.data_type)} ({size} bits)"
        )
    if not target.pdo_mappable:
        return f"{index:04X}h sub {subindex} '{target.name}' is not marked PDO-mappable"
    return None
