"""The manuals' recommended PDO mapping for the modes a user wants to run, packed into PDOs.

The objects per mode and direction, and the transmission types, are data:
`servodesk_data/<profile>/recommended_pdos.toml`, each row citing the manual section it comes
from. This module combines the chosen modes, keeps what the node's dictionary can map, and packs
it into as few PDOs as fit, so that applying the result leaves every PDO of the device defined.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import servodesk_data
from servodesk.od import datatypes as dt
from servodesk.od.model import ObjectDictionaryModel
from servodesk.pdo.model import DIRECTION, MappedObject, PdoConfig
from servodesk.pdo.validate import READABLE, WRITABLE
from servodesk.pdo_problems import PdoKind
from servodesk_data import ObjectRef, parse_object_ref
from servodesk_protocol.pdo import (
    CAN_ID_MASK,
    MAX_ENTRIES,
    MAX_PDO_BITS,
    SUB_COB_ID,
    SUB_EVENT_TIMER,
    comm_index,
    default_can_id,
)

MODES = ("pp", "pv", "pt", "hm", "ip")  # profile position, profile velocity, profile torque,
# homing, interpolated position
MODE_NAMES = {
    "pp": "profile position",
    "pv": "profile velocity",
    "pt": "profile torque",
    "hm": "homing",
    "ip": "interpolated position",
}
PROFILES = ("mdi-s1c", "kinco", "cia402", "generic-cia402", "generic-cia301")
# generic drives get the usual CiA 402 objects: the cia402 file lists exactly those
_DATA_FOLDER = {"generic-cia402": "cia402", "generic-cia301": "cia402"}
FILE_NAME = "recommended_pdos.toml"
CONTROLWORD: ObjectRef = (0x6040, 0x00)  # Controlword
STATUSWORD: ObjectRef = (0x6041, 0x00)  # Statusword
_FIRST: dict[PdoKind, ObjectRef] = {"rpdo": CONTROLWORD, "tpdo": STATUSWORD}


@dataclass(frozen=True)
class ModeObjects:
    source: str  # the manual section, e.g. "MDi-S1-C CANopen manual §3.4.3"
    required: dict[PdoKind, tuple[ObjectRef, ...]]
    optional: dict[PdoKind, tuple[ObjectRef, ...]]


@dataclass(frozen=True)
class Transmission:
    rpdo: int
    tpdo: int
    tpdo_inhibit_time_100us: int
    tpdo_event_timer_ms: int

    def of(self, kind: PdoKind) -> int:
        return self.rpdo if kind == "rpdo" else self.tpdo


@dataclass(frozen=True)
class Recommendations:
    """One profile's recommended_pdos.toml."""

    event: Transmission  # every mode but IP
    synchronous: Transmission  # when IP is among the modes
    modes: dict[str, ModeObjects]


def recommended(
    profile: str,
    modes: Sequence[str],
    *,
    node: int,
    od: ObjectDictionaryModel,
    byte_granular: bool,
    rpdo_count: int,
    tpdo_count: int,
    optional: bool = True,
    current: Sequence[PdoConfig] = (),
) -> list[PdoConfig]:
    """Every RPDO and TPDO of the device: the recommendation for `modes` packed into the first
    ones, the rest invalid with an empty mapping and, where `current` (the device's PDOs now)
    has them, their communication parameters as they are. `optional=False` leaves out the
    manual's optional objects. ValueError for an unknown profile or mode, or when the objects
    do not fit.
    """
    unknown = [m for m in modes if m not in MODES]
    if unknown:
        raise ValueError(
            f"unknown mode(s) {', '.join(map(repr, unknown))}; known: {', '.join(MODES)}"
        )
    data = load_recommendations(profile)
    chosen = [m for m in MODES if m in modes]  # the same layout whatever order they were picked
    timing = data.synchronous if "ip" in chosen else data.event
    out: list[PdoConfig] = []
    counts: dict[PdoKind, int] = {"rpdo": rpdo_count, "tpdo": tpdo_count}
    now = {(pdo.kind, pdo.number): pdo for pdo in current}
    for kind, count in counts.items():
        required = _objects(data, chosen, kind, od, byte_granular, required=True)
        extra = _objects(data, chosen, kind, od, byte_granular, required=False) if optional else []
        extra = [obj for obj in extra if obj not in required]
        if chosen and (not required or (required[0].index, required[0].subindex) != _FIRST[kind]):
            index, sub = _FIRST[kind]
            raise ValueError(
                f"this dictionary has no PDO-mappable {index:04X}h:{sub:02X}: without it no"
                f" {kind.upper()} can drive the {', '.join(m.upper() for m in chosen)} mode(s)"
            )
        ids = _can_ids(kind, count, node, od)
        usable = len(ids)
        frames = _pack(required)
        if len(frames) > usable:
            bits = sum(obj.bits for obj in required)
            raise ValueError(
                f"the {', '.join(m.upper() for m in chosen)} objects need {len(frames)}"
                f" {kind.upper()}s ({bits} bits) but this drive has {usable} usable"
            )
        _add_optional(frames, extra, usable)
        out += _configs(kind, count, ids, frames, timing, od, now)
    return out


def mode_needs(
    profile: str, mode: str, od: ObjectDictionaryModel, byte_granular: bool
) -> tuple[dict[PdoKind, list[MappedObject]], str]:
    """What `mode` cannot run without, per direction (the manual's required objects this
    dictionary can map), and the manual section that says so. ValueError for an unknown
    profile or mode."""
    if mode not in MODES:
        raise ValueError(f"unknown mode {mode!r}; known: {', '.join(MODES)}")
    data = load_recommendations(profile)
    needs: dict[PdoKind, list[MappedObject]] = {
        kind: _objects(data, [mode], kind, od, byte_granular, required=True)
        for kind in ("rpdo", "tpdo")
    }
    return needs, data.modes[mode].source


def load_recommendations(profile: str) -> Recommendations:
    """Parse and check `profile`'s recommended_pdos.toml (ValueError naming file and key)."""
    if profile not in PROFILES:
        raise ValueError(f"unknown profile {profile!r}; known: {', '.join(PROFILES)}")
    return _load(servodesk_data.data_dir(_DATA_FOLDER.get(profile, profile)) / FILE_NAME)


@cache
def _load(path: Path) -> Recommendations:
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from exc
    _keys(path, "", raw, {"transmission", "transmission_ip", "modes"})
    modes_raw = _table(path, "modes", raw["modes"])
    _keys(path, "modes", modes_raw, set(MODES))
    return Recommendations(
        event=_transmission(path, "transmission", raw["transmission"]),
        synchronous=_transmission(path, "transmission_ip", raw["transmission_ip"]),
        modes={mode: _mode(path, f"modes.{mode}", modes_raw[mode]) for mode in MODES},
    )


def _table(path: Path, where: str, raw: object) -> dict[str, object]:
    if not isinstance(raw, dict):
        raise ValueError(f"{path}: {where}: expected a table")
    return raw


def _keys(path: Path, where: str, raw: dict[str, object], keys: set[str]) -> None:
    missing, extra = keys - raw.keys(), raw.keys() - keys
    if missing or extra:
        what = [f"missing {', '.join(sorted(missing))}"] if missing else []
        what += [f"unknown {', '.join(sorted(extra))}"] if extra else []
        raise ValueError(f"{path}: {where or '(top level)'}: {'; '.join(what)}")


def _transmission(path: Path, where: str, raw: object) -> Transmission:
    table = _table(path, where, raw)
    names = ("rpdo", "tpdo", "tpdo_inhibit_time_100us", "tpdo_event_timer_ms")
    _keys(path, where, table, set(names))
    values: list[int] = []
    for name, high in zip(names, (255, 255, 0xFFFF, 0xFFFF), strict=True):
        value = table[name]
        if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= high:
            raise ValueError(f"{path}: {where}.{name}: {value!r} is not an integer in 0..{high}")
        values.append(value)
    return Transmission(*values)


def _mode(path: Path, where: str, raw: object) -> ModeObjects:
    table = _table(path, where, raw)
    _keys(path, where, table, {"source", "rpdo", "tpdo", "rpdo_optional", "tpdo_optional"})
    source = table["source"]
    if not isinstance(source, str) or not source:
        raise ValueError(f"{path}: {where}.source: expected the manual section it comes from")

    def refs(key: str) -> tuple[ObjectRef, ...]:
        items = table[key]
        if not isinstance(items, list) or not all(isinstance(i, str) for i in items):
            raise ValueError(f"{path}: {where}.{key}: expected a list like ['6040:00']")
        try:
            return tuple(parse_object_ref(str(item)) for item in items)
        except ValueError as exc:
            raise ValueError(f"{path}: {where}.{key}: {exc}") from None

    return ModeObjects(
        source,
        required={"rpdo": refs("rpdo"), "tpdo": refs("tpdo")},
        optional={"rpdo": refs("rpdo_optional"), "tpdo": refs("tpdo_optional")},
    )


def _objects(
    data: Recommendations,
    modes: Sequence[str],
    kind: PdoKind,
    od: ObjectDictionaryModel,
    byte_granular: bool,
    *,
    required: bool,
) -> list[MappedObject]:
    """The modes' objects for `kind`, deduplicated, controlword / statusword first, reduced to
    what `od` has and can map in that direction."""
    refs: list[ObjectRef] = []
    for mode in modes:
        table = data.modes[mode].required if required else data.modes[mode].optional
        refs += [ref for ref in table[kind] if ref not in refs]
    refs.sort(key=lambda ref: ref != _FIRST[kind])  # stable: only moves the first one forward
    access = WRITABLE if kind == "rpdo" else READABLE
    out: list[MappedObject] = []
    for index, subindex in refs:
        sub = od.get(index, subindex)
        size = dt.bit_size(sub.data_type) if sub else None
        if sub is None or size is None or not sub.pdo_mappable or sub.access not in access:
            continue
        if sub.data_type == dt.DataType.BOOLEAN and byte_granular:
            size = 8  # a whole byte where the drive maps bytes only
        out.append(MappedObject(index, subindex, size, sub.name))
    return out


def _can_ids(kind: PdoKind, count: int, node: int, od: ObjectDictionaryModel) -> list[int]:
    """The CAN id of PDOs 1..n, as far as one is known: the pre-defined connection set for 1–4,
    the dictionary's default COB-ID beyond (a PDO without one cannot be recommended)."""
    direction = DIRECTION[kind]
    ids: list[int] = []
    for number in range(1, count + 1):
        base = default_can_id(direction, number)
        if base is not None:
            ids.append(base + node)
            continue
        entry = od.get(comm_index(direction, number), SUB_COB_ID)
        default = entry.default if entry else None
        if not isinstance(default, int) or not default & CAN_ID_MASK:
            break
        ids.append(default & CAN_ID_MASK)
    return ids


def _pack(objects: Sequence[MappedObject]) -> list[list[MappedObject]]:
    """First fit in the given order, or, when that takes more frames, first fit with the larger
    objects first (the first object, controlword / statusword, stays at the front)."""
    in_order = _first_fit(objects)
    if len(objects) < 2:
        return in_order
    by_size = [objects[0], *sorted(objects[1:], key=lambda obj: -obj.bits)]
    largest_first = _first_fit(by_size)
    return largest_first if len(largest_first) < len(in_order) else in_order


def _first_fit(objects: Sequence[MappedObject]) -> list[list[MappedObject]]:
    frames: list[list[MappedObject]] = []
    for obj in objects:
        if not _place(frames, obj):
            frames.append([obj])
    return frames


def _place(frames: list[list[MappedObject]], obj: MappedObject) -> bool:
    for frame in frames:
        if len(frame) < MAX_ENTRIES and sum(o.bits for o in frame) + obj.bits <= MAX_PDO_BITS:
            frame.append(obj)
            return True
    return False


def _add_optional(
    frames: list[list[MappedObject]], extra: Sequence[MappedObject], usable: int
) -> None:
    """Optional objects go where room is left, or into PDOs the recommendation does not use yet."""
    for obj in extra:
        if not _place(frames, obj) and len(frames) < usable:
            frames.append([obj])


def _configs(
    kind: PdoKind,
    count: int,
    ids: Sequence[int],
    frames: Sequence[Sequence[MappedObject]],
    timing: Transmission,
    od: ObjectDictionaryModel,
    current: Mapping[tuple[PdoKind, int], PdoConfig],
) -> list[PdoConfig]:
    """The PDOs; a TPDO gets the event timer only where the drive has its sub 5."""
    out: list[PdoConfig] = []
    for number in range(1, count + 1):
        can_id = ids[number - 1] if number <= len(ids) else 0
        if number > len(frames):
            out.append(_unused(kind, number, can_id, timing, current.get((kind, number))))
            continue
        tpdo = kind == "tpdo"
        timer = od.get(comm_index(DIRECTION[kind], number), SUB_EVENT_TIMER) is not None
        out.append(
            PdoConfig(
                kind,
                number,
                can_id,
                valid=True,
                transmission_type=timing.of(kind),
                inhibit_time_100us=timing.tpdo_inhibit_time_100us if tpdo else 0,
                event_timer_ms=timing.tpdo_event_timer_ms if tpdo and timer else 0,
                mapping=tuple(frames[number - 1]),
            )
        )
    return out


def _unused(
    kind: PdoKind, number: int, can_id: int, timing: Transmission, now: PdoConfig | None
) -> PdoConfig:
    """A PDO the recommendation does not use: invalid and empty, so the applied mapping does
    not depend on what was there; its communication parameters stay as the device has them
    (nothing to change in what is not used), else the recommendation's."""
    if now is None:
        return PdoConfig(kind, number, can_id, False, timing.of(kind))
    return PdoConfig(
        kind,
        number,
        now.cob_id,
        False,
        now.transmission_type,
        now.inhibit_time_100us,
        now.event_timer_ms,
        now.sync_start,
    )
