"""Parse and validate a profile.toml into `DriveData`.

Every problem is a ValueError naming the file and the key (`parameters[3] (PA-106).default`), so
a person editing the TOML by hand finds the line. Unknown keys are errors too: a misspelt quirk
must not silently fall back to a default.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Mapping
from enum import Enum
from pathlib import Path
from types import MappingProxyType
from typing import TypeVar

from servodesk_data.fault_kind import FaultKind
from servodesk_data.model import (
    CJK,
    BitrateCode,
    DriveData,
    EmcyFormat,
    FaultEntry,
    Identity,
    LimitSwitchReaction,
    NodeIdSource,
    ObjectRef,
    Parameter,
    PdoRemapRule,
    Quirks,
    SdoLengthCheck,
    TakesEffect,
)

E = TypeVar("E", bound=Enum)

_REF = re.compile(r"([0-9A-Fa-f]{4}):([0-9A-Fa-f]{2})")
_U32 = 0xFFFFFFFF
# 1001h bit 0 (generic) is set with every error, bit 6 is reserved (CiA 301 §7.5.2.2)
_ER_GENERIC = 0x01
_ER_RESERVED = 0x40


def parse_object_ref(ref: str) -> ObjectRef:
    """`"2006:08"` -> `(0x2006, 0x08)`: four hex digits, a colon, two hex digits."""
    match = _REF.fullmatch(ref.strip())
    if match is None:
        raise ValueError(f"object reference {ref!r} is not INDEX:SUB in hex, e.g. '2006:08'")
    return int(match.group(1), 16), int(match.group(2), 16)


def format_object_ref(ref: ObjectRef) -> str:
    """`(0x2006, 0x08)` -> `"2006:08"`, the spelling the TOML files use."""
    return f"{ref[0]:04X}:{ref[1]:02X}"


class _Table:
    """One TOML table with the path to it, for typed reads with precise error messages."""

    def __init__(self, source: Path, where: str, raw: object) -> None:
        self.source = source
        self.where = where
        if not isinstance(raw, dict):
            raise self.error(None, f"expected a table, got {type(raw).__name__}")
        self._raw: dict[str, object] = raw
        self._seen: set[str] = set()

    def error(self, key: str | None, message: str) -> ValueError:
        place = self.where if key is None else f"{self.where}.{key}" if self.where else key
        return ValueError(f"{self.source}: {place or '(top level)'}: {message}")

    def has(self, key: str) -> bool:
        return key in self._raw

    def _get(self, key: str) -> object:
        self._seen.add(key)
        if key not in self._raw:
            raise self.error(key, "missing")
        return self._raw[key]

    def string(self, key: str) -> str:
        value = self._get(key)
        if not isinstance(value, str) or not value.strip():
            raise self.error(key, f"expected a non-empty string, got {value!r}")
        return value

    def integer(self, key: str, low: int | None = None, high: int | None = None) -> int:
        value = self._get(key)
        # bool is an int subclass in Python: `true` must not pass as 1
        if not isinstance(value, int) or isinstance(value, bool):
            raise self.error(key, f"expected an integer, got {value!r}")
        if (low is not None and value < low) or (high is not None and value > high):
            lowest = "" if low is None else str(low)
            highest = "" if high is None else str(high)
            raise self.error(key, f"{value} is outside {lowest}..{highest}")
        return value

    def optional_integer(
        self, key: str, low: int | None = None, high: int | None = None
    ) -> int | None:
        return self.integer(key, low, high) if self.has(key) else None

    def boolean(self, key: str) -> bool:
        value = self._get(key)
        if not isinstance(value, bool):
            raise self.error(key, f"expected true or false, got {value!r}")
        return value

    def _list(self, key: str) -> list[object]:
        value = self._get(key)
        if not isinstance(value, list):
            raise self.error(key, f"expected a list, got {value!r}")
        return value

    def integers(self, key: str, low: int, high: int) -> tuple[int, ...]:
        items = self._list(key)
        for item in items:
            if not isinstance(item, int) or isinstance(item, bool) or not low <= item <= high:
                raise self.error(key, f"{item!r} is not an integer in {low}..{high}")
        return tuple(item for item in items if isinstance(item, int))

    def enum_list(self, key: str, cls: type[E]) -> tuple[E, ...]:
        return tuple(self._enum_value(key, item, cls) for item in self._list(key))

    def enum(self, key: str, cls: type[E]) -> E:
        return self._enum_value(key, self._get(key), cls)

    def _enum_value(self, key: str, value: object, cls: type[E]) -> E:
        allowed = ", ".join(repr(member.value) for member in cls)
        if not isinstance(value, str):
            raise self.error(key, f"expected one of {allowed}, got {value!r}")
        try:
            return cls(value)
        except ValueError:
            raise self.error(key, f"{value!r} is not one of {allowed}") from None

    def object_ref(self, key: str) -> ObjectRef:
        return self._ref(key, self._get(key))

    def object_refs(self, key: str) -> tuple[ObjectRef, ...]:
        return tuple(self._ref(key, item) for item in self._list(key))

    def _ref(self, key: str, value: object) -> ObjectRef:
        if not isinstance(value, str):
            raise self.error(key, f"expected an object reference like '2006:08', got {value!r}")
        try:
            return parse_object_ref(value)
        except ValueError as exc:
            raise self.error(key, str(exc)) from None

    def table(self, key: str) -> _Table:
        return _Table(self.source, f"{self.where}.{key}" if self.where else key, self._get(key))

    def tables(self, key: str) -> list[_Table]:
        where = f"{self.where}.{key}" if self.where else key
        return [
            _Table(self.source, f"{where}[{i}]", item) for i, item in enumerate(self._list(key))
        ]

    def choices(self, key: str) -> dict[int, str]:
        if not self.has(key):
            return {}
        raw = self._get(key)
        if not isinstance(raw, dict):
            raise self.error(key, "expected a table of code = meaning")
        out: dict[int, str] = {}
        for code, meaning in raw.items():
            try:
                number = int(code, 0)
            except ValueError:
                raise self.error(key, f"choice code {code!r} is not an integer") from None
            if not isinstance(meaning, str) or not meaning.strip():
                raise self.error(key, f"choice {code} needs a meaning, got {meaning!r}")
            out[number] = meaning
        return out

    def finish(self) -> None:
        unknown = sorted(set(self._raw) - self._seen)
        if unknown:
            raise self.error(None, f"unknown key(s) {', '.join(unknown)}")


def load_path(path: Path) -> DriveData:
    """Parse and validate one profile.toml; its drive.eds is expected beside it."""
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from exc
    root = _Table(path, "", raw)
    profile = path.parent.name
    identity = _identity(root.table("identity"), profile)
    quirks = _quirks(root.table("quirks"))
    parameters = _parameters(root.tables("parameters"))
    faults = _faults(root, root.tables("faults"), quirks)
    root.finish()
    return DriveData(profile, identity, quirks, parameters, faults, path.parent / "drive.eds")


def _identity(t: _Table, profile: str) -> Identity:
    identity = Identity(
        name=t.string("name"),
        vendor_id=t.integer("vendor_id", 0, _U32),
        product_code=t.integer("product_code", 0, _U32),
        device_type=t.integer("device_type", 0, _U32),
        description=t.string("description"),
        seed=t.string("seed"),
    )
    if identity.name != profile:
        raise t.error("name", f"{identity.name!r} must equal the profile folder {profile!r}")
    t.finish()
    return identity


def _quirks(t: _Table) -> Quirks:
    rpdo_count = t.integer("rpdo_count", 1, 512)
    tpdo_count = t.integer("tpdo_count", 1, 512)
    node_id_source = t.enum("node_id_source", NodeIdSource)
    node_id_object = t.object_ref("node_id_object") if t.has("node_id_object") else None
    if (node_id_source is NodeIdSource.FIXED) != (node_id_object is None):
        raise t.error("node_id_object", "required exactly when node_id_source is not 'fixed'")
    bitrate_objects = t.object_refs("bitrate_objects")
    bitrate_codes = _bitrate_codes(t, bitrate_objects)
    quirks = Quirks(
        emcy_format=t.enum("emcy_format", EmcyFormat),
        sdo_block_transfer=t.boolean("sdo_block_transfer"),
        sdo_length_check=t.enum("sdo_length_check", SdoLengthCheck),
        pdo_remap_rule=t.enum("pdo_remap_rule", PdoRemapRule),
        pdo_byte_granular=t.boolean("pdo_byte_granular"),
        rpdo_count=rpdo_count,
        tpdo_count=tpdo_count,
        pdo_rtr_transmission=t.boolean("pdo_rtr_transmission"),
        pdo_fixed_cob_ids=t.integer("pdo_fixed_cob_ids", 0, max(rpdo_count, tpdo_count)),
        sync_min_period_us=t.integer("sync_min_period_us", 0, _U32),
        sync_require_period_before_enable=t.boolean("sync_require_period_before_enable"),
        supported_modes=frozenset(t.integers("supported_modes", -128, 127)),
        homing_methods=frozenset(t.integers("homing_methods", -128, 127)),
        pp_immediate_setpoint=t.boolean("pp_immediate_setpoint"),
        unsupported_mode_display=t.optional_integer("unsupported_mode_display", -128, 127),
        homing_reference_found_bit15=t.boolean("homing_reference_found_bit15"),
        max_speed_object=t.object_ref("max_speed_object"),
        fault_history_1003=t.boolean("fault_history_1003"),
        kinco_fault_bits=t.boolean("kinco_fault_bits"),
        node_id_source=node_id_source,
        node_id_object=node_id_object,
        bitrate_objects=bitrate_objects,
        bitrate_codes=bitrate_codes,
        status_only_kinds=frozenset(t.enum_list("status_only_kinds", FaultKind)),
        limit_switch_reaction=t.enum("limit_switch_reaction", LimitSwitchReaction),
        enumerated_objects=(
            t.object_refs("enumerated_objects") if t.has("enumerated_objects") else ()
        ),
    )
    if not quirks.supported_modes:
        raise t.error("supported_modes", "a drive supports at least one mode")
    t.finish()
    return quirks


def _bitrate_codes(t: _Table, objects: tuple[ObjectRef, ...]) -> tuple[BitrateCode, ...]:
    if not t.has("bitrate_codes"):
        if objects:
            raise t.error("bitrate_codes", "missing (bitrate_objects are given)")
        return ()
    codes: list[BitrateCode] = []
    for entry in t.tables("bitrate_codes"):
        code = BitrateCode(entry.integers("values", 0, _U32), entry.integer("bitrate", 1))
        entry.finish()
        if len(code.values) != len(objects):
            raise entry.error("values", f"needs one value per bitrate object ({len(objects)})")
        if any(code.values == c.values for c in codes):
            raise entry.error("values", f"{list(code.values)} is listed twice")
        if any(code.bitrate == c.bitrate for c in codes):
            raise entry.error("bitrate", f"{code.bitrate} bit/s is listed twice")
        codes.append(code)
    return tuple(codes)


def _parameters(tables: list[_Table]) -> tuple[Parameter, ...]:
    out: list[Parameter] = []
    for t in tables:
        name = t.string("name")
        t.where = f"{t.where} ({name})"
        low, high = t.integer("min"), t.integer("max")
        parameter = Parameter(
            name=name,
            object=t.object_ref("object"),
            label=t.string("label"),
            description=t.string("description"),
            unit=_optional_string(t, "unit"),
            min=low,
            max=high,
            default=t.integer("default", low, high),
            takes_effect=t.enum("takes_effect", TakesEffect),
            choices=MappingProxyType(t.choices("choices")),
        )
        t.finish()
        _check_choices(t, parameter.choices, parameter)
        for other in out:
            if other.name == name:
                raise t.error("name", f"{name!r} is listed twice")
            if other.object == parameter.object:
                raise t.error(
                    "object", f"{format_object_ref(parameter.object)} is also {other.name}"
                )
        out.append(parameter)
    return tuple(out)


def _optional_string(t: _Table, key: str) -> str:
    return t.string(key) if t.has(key) else ""


def _check_choices(t: _Table, choices: Mapping[int, str], parameter: Parameter) -> None:
    for code in choices:
        if not parameter.min <= code <= parameter.max:
            raise t.error("choices", f"code {code} is outside min..max")
    if choices and parameter.default not in choices:
        raise t.error("default", f"{parameter.default} is not one of the choices")


def _faults(root: _Table, tables: list[_Table], quirks: Quirks) -> tuple[FaultEntry, ...]:
    out: list[FaultEntry] = []
    for t in tables:
        code = t.integer("code", 1, _U32)
        t.where = f"{t.where} (code {code:#x})"
        entry = FaultEntry(
            code=code,
            name=t.string("name"),
            name_en=t.string("name_en"),
            description=t.string("description"),
            what_to_check=t.string("what_to_check"),
            emcy_code=t.integer("emcy_code", 0x0100, 0xFFFF),  # 00xx means "no error"
            error_register=t.integer("error_register", 0, 0xFF),
            kinco_bit=t.integer("kinco_bit", 0, _U32) if t.has("kinco_bit") else 0,
            kinds=t.enum_list("kinds", FaultKind) if t.has("kinds") else (),
            name_zh=t.string("name_zh") if t.has("name_zh") else None,
            description_zh=t.string("description_zh") if t.has("description_zh") else None,
            what_to_check_zh=t.string("what_to_check_zh") if t.has("what_to_check_zh") else None,
        )
        t.finish()
        _check_fault(t, entry, out, quirks)
        out.append(entry)
    _check_kinds(root, out, quirks)
    return tuple(out)


def _check_fault(t: _Table, entry: FaultEntry, seen: list[FaultEntry], quirks: Quirks) -> None:
    if any(other.code == entry.code for other in seen):
        raise t.error("code", f"{entry.code:#x} is listed twice")
    if not entry.error_register & _ER_GENERIC or entry.error_register & _ER_RESERVED:
        raise t.error("error_register", "bit 0 (generic) must be set and bit 6 (reserved) clear")
    bit = entry.kinco_bit
    if quirks.kinco_fault_bits:
        if bit == 0 or bit & (bit - 1):
            raise t.error("kinco_bit", f"{bit:#x} is not a single 2600h:02 bit")
        if any(other.kinco_bit == bit for other in seen):
            raise t.error("kinco_bit", f"{bit:#x} is used twice")
    elif bit:
        raise t.error("kinco_bit", "only profiles with kinco_fault_bits have 2600h:02 bits")
    if len(set(entry.kinds)) != len(entry.kinds):
        raise t.error("kinds", "a kind is listed twice")
    if entry.name_zh is not None:
        if entry.manual_chinese:
            raise t.error(
                "name_zh", "the manual's name is Chinese already: no translation beside it"
            )
        if CJK.search(entry.name_zh) is None:
            raise t.error("name_zh", f"{entry.name_zh!r} is not Chinese")
    for key, text in (
        ("description_zh", entry.description_zh),
        ("what_to_check_zh", entry.what_to_check_zh),
    ):
        if text is not None and CJK.search(text) is None:
            raise t.error(key, f"{text!r} is not Chinese")


def _check_kinds(root: _Table, faults: list[FaultEntry], quirks: Quirks) -> None:
    """Every FaultKind the drive can raise maps to exactly one fault, or is declared
    status-only; one it never raises (see LimitSwitchReaction) maps to none."""
    mapped: dict[FaultKind, int] = {}
    never = quirks.limit_switch_reaction.never_raised
    for entry in faults:
        for kind in entry.kinds:
            if kind in never:
                reaction = quirks.limit_switch_reaction.value
                raise root.error(
                    "faults",
                    f"{kind.value} is never raised with limit_switch_reaction = {reaction!r}",
                )
            if kind in mapped:
                codes = f"{mapped[kind]:#x} and {entry.code:#x}"
                raise root.error("faults", f"{kind.value} maps to both {codes}")
            if kind in quirks.status_only_kinds:
                raise root.error("faults", f"{kind.value} is also in quirks.status_only_kinds")
            mapped[kind] = entry.code
    handled = mapped.keys() | quirks.status_only_kinds | never
    missing = [k.value for k in FaultKind if k not in handled]
    if missing:
        raise root.error(
            "faults",
            f"no fault for kind(s) {', '.join(missing)}"
            " (map them with `kinds` or list them in quirks.status_only_kinds)",
        )
