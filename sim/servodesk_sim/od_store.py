"""The values of one drive's object dictionary, with the CiA 301 access rules an SDO sees.

The *definition* of each entry (data type, access, limits, default, `$NODEID`) is canopen's
`ObjectDictionary`; this module holds the current values, encodes them with canopen's codecs and
implements store (1010h) / restore (1011h) and the two NMT resets on top of that.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from enum import Enum

from canopen.objectdictionary import ObjectDictionary, ODArray, ODRecord, ODVariable, datatypes

from servodesk_protocol.cob_id import CAN_ID_MASK
from servodesk_protocol.sdo_abort import (
    CANNOT_STORE,
    GENERAL_ERROR,
    INVALID_VALUE,
    LENGTH_TOO_HIGH,
    LENGTH_TOO_LOW,
    NO_OBJECT,
    NO_SUBINDEX,
    READ_ONLY,
    TYPE_MISMATCH,
    VALUE_TOO_HIGH,
    VALUE_TOO_LOW,
    WRITE_ONLY,
)
from servodesk_sim.abort_codes import SdoAbort


class LengthCheck(Enum):
    """How a drive answers an SDO download whose size does not match a fixed-size object."""

    GENERIC = "generic"  # any size mismatch -> 06070010 (MDi, MDi-S1-C manual table 2.18; Kinco)
    SPECIFIC = "specific"  # too long -> 06070012, too short -> 06070013 (cia402, Nanotec article)


Value = int | float | str | bytes
Validator = Callable[[int, Value], None]  # (subindex, decoded value); raise SdoAbort to refuse
WriteHook = Callable[[int, Value], None]  # (subindex, decoded value) after an accepted write

STORE_PARAMETERS = 0x1010  # Store parameters
RESTORE_DEFAULTS = 0x1011  # Restore default parameters
SAVE_SIGNATURE = 0x65766173  # ASCII "save", little-endian (CiA 301 §7.5.2.13)
LOAD_SIGNATURE = 0x64616F6C  # ASCII "load", little-endian (CiA 301 §7.5.2.14)
# Simulator-only objects (fault injection etc.) never end up in the stored parameter set.
SIM_ONLY_FIRST = 0x5FF0
SIM_ONLY_LAST = 0x5FFF
SIM_FORGET_AT_STORE = 0x5FF5  # SIM forget at next store: index<<8|subindex of the entry

_Key = tuple[int, int]


class Area(Enum):
    """Object dictionary areas that 1010h/1011h sub-indices select (CiA 301 §7.5.2.13)."""

    COMMUNICATION = "communication"  # 1000h–1FFFh
    MANUFACTURER = "manufacturer"  # 2000h–5FFFh
    APPLICATION = "application"  # 6000h–9FFFh (device profile)


ALL_AREAS = frozenset(Area)
# 1010h/1011h sub-index -> areas it saves or restores.
AREAS_OF_SUBINDEX: dict[int, frozenset[Area]] = {
    1: ALL_AREAS,
    2: frozenset({Area.COMMUNICATION}),
    3: frozenset({Area.APPLICATION}),
    4: frozenset({Area.MANUFACTURER}),
}


def area_of(index: int) -> Area | None:
    """The area an index belongs to, or None outside 1000h–9FFFh."""
    if 0x1000 <= index <= 0x1FFF:
        return Area.COMMUNICATION
    if 0x2000 <= index <= 0x5FFF:
        return Area.MANUFACTURER
    if 0x6000 <= index <= 0x9FFF:
        return Area.APPLICATION
    return None


def _nodeid_base(raw: str) -> int:
    """Value of an EDS `$NODEID+0x180`-style default without the node id.

    Same normalisation as canopen's EDS importer (objectdictionary/eds.py `_convert_variable`).
    """
    text = raw.replace(" ", "").upper()
    return int(re.sub(r"\+?\$NODEID\+?", "", text), 0)


@dataclass(frozen=True, slots=True)
class _Stored:
    value: Value
    node_id: int  # node id when it was stored, to re-resolve node-relative COB-IDs


class ObjectStore:
    """Current values of one drive's object dictionary (implements values.ValueStore)."""

    def __init__(self, od: ObjectDictionary, node_id: int, *, length_check: LengthCheck) -> None:
        self.od = od
        self._node_id = node_id
        self._length_check = length_check
        # canopen resolved `$NODEID` defaults with the id it was given on import.
        self._od_node_id: int = od.node_id if od.node_id is not None else node_id
        self._vars: dict[_Key, ODVariable] = {}
        self._highest_sub: dict[int, int] = {}  # ARRAY/RECORD index -> highest sub-index
        for index in od:
            obj = od[index]
            if isinstance(obj, ODVariable):
                self._vars[(index, 0)] = obj
            elif isinstance(obj, ODRecord | ODArray):
                # Only the sub-indices the OD lists: ODArray.__getitem__ would invent others.
                subs: dict[int, ODVariable] = obj.subindices
                for sub, var in subs.items():
                    self._vars[(index, sub)] = var
                if subs:
                    self._highest_sub[index] = max(subs)
        self._values: dict[_Key, Value] = {}
        self._changes = 0  # every write and reset counts (ValueStore.changes)
        self._stored: dict[_Key, _Stored] = {}
        self._validators: dict[int, list[Validator]] = {}
        self._hooks: dict[int, list[WriteHook]] = {}
        # entries the next store leaves out (5FF5h injection): "lost at power cycle" drives
        self._forget_next: set[_Key] = set()
        self._load(self._vars)

    @property
    def node_id(self) -> int:
        return self._node_id

    @property
    def changes(self) -> int:
        return self._changes

    # ------------------------------------------------------------------ lookup and internal access

    def has(self, index: int, subindex: int = 0) -> bool:
        return (index, subindex) in self._vars

    def variable(self, index: int, subindex: int = 0) -> ODVariable:
        var = self._vars.get((index, subindex))
        if var is not None:
            return var
        if index in self.od:
            raise SdoAbort(NO_SUBINDEX, f"{index:04X}h has no sub-index {subindex:02X}h")
        raise SdoAbort(NO_OBJECT, f"no object {index:04X}h")

    def get(self, index: int, subindex: int = 0) -> int:
        value = self._values[(index, subindex)]
        if not isinstance(value, int):
            raise TypeError(f"{index:04X}h:{subindex:02X}h holds {type(value).__name__}, not int")
        return value

    def set(self, index: int, subindex: int, value: int) -> None:
        self.set_value(index, subindex, value)

    def get_value(self, index: int, subindex: int = 0) -> Value:
        return self._values[(index, subindex)]

    def set_value(self, index: int, subindex: int, value: Value) -> None:
        """Publish a value from inside the drive: no access checks, no validators, no hooks."""
        key = (index, subindex)
        if key not in self._values:
            raise KeyError(f"{index:04X}h:{subindex:02X}h is not in the object dictionary")
        old = self._values[key]
        if old != value or type(old) is not type(value):
            self._values[key] = value
            self._changes += 1

    def add_validator(self, index: int, fn: Validator) -> None:
        self._validators.setdefault(index, []).append(fn)

    def add_write_hook(self, index: int, fn: WriteHook) -> None:
        self._hooks.setdefault(index, []).append(fn)

    # ------------------------------------------------------------------------------- SDO / PDO

    def read_bytes(self, index: int, subindex: int) -> bytes:
        """Encoded current value, as an SDO upload returns it."""
        var = self.variable(index, subindex)
        if not var.readable:
            raise SdoAbort(WRITE_ONLY, f"{index:04X}h:{subindex:02X}h is write-only")
        try:
            return var.encode_raw(self._values[(index, subindex)])
        except (ValueError, TypeError) as exc:
            # A value the type cannot carry (e.g. a non-ASCII EDS default for a VISIBLE_STRING):
            # a real device answers with a general error instead of going silent.
            raise SdoAbort(GENERAL_ERROR, f"{index:04X}h:{subindex:02X}h: {exc}") from exc

    def write_bytes(self, index: int, subindex: int, data: bytes) -> None:
        """Check, decode and store a value from an SDO download or an RPDO, then run the hooks."""
        var = self.variable(index, subindex)
        if not var.writable:
            raise SdoAbort(READ_ONLY, f"{index:04X}h:{subindex:02X}h is {var.access_type}")
        self._check_length(var, data)
        decoded = var.decode_raw(data)
        value: Value = bytes(decoded) if isinstance(decoded, bytearray) else decoded
        _check_limits(var, value)
        areas = None
        if index in (STORE_PARAMETERS, RESTORE_DEFAULTS) and subindex >= 1:
            areas = _store_command_areas(index, subindex, value)
        for validate in self._validators.get(index, ()):
            validate(subindex, value)
        self._changes += 1
        if areas is None:
            self._values[(index, subindex)] = value
        elif index == STORE_PARAMETERS:
            self._save(areas)
        else:
            self._forget(areas)
        for hook in self._hooks.get(index, ()):
            hook(subindex, value)

    def _check_length(self, var: ODVariable, data: bytes) -> None:
        if not var.fixed_size:  # strings and DOMAIN take any length
            return
        expected = len(var) // 8  # canopen gives the size in bits
        if len(data) == expected:
            return
        if self._length_check is LengthCheck.GENERIC:
            raise SdoAbort(TYPE_MISMATCH, f"{len(data)} bytes for a {expected}-byte object")
        code = LENGTH_TOO_HIGH if len(data) > expected else LENGTH_TOO_LOW
        raise SdoAbort(code, f"{len(data)} bytes for a {expected}-byte object")

    # ----------------------------------------------------------------------- store and restore

    def commit_stored(self, index: int, subindex: int) -> None:
        """Put one entry's current value into the stored set, as if saved (commissioning)."""
        key = (index, subindex)
        self._stored[key] = _Stored(self._values[key], self._node_id)

    def reset_node(self) -> None:
        """NMT reset node: every area back to its last stored values, else the EDS defaults.

        The MDi-S1-C manual §2.3.1: reset node restores the manufacturer and profile areas to the
        last saved
        values; CiA 301 resets communication as part of it, so that area is reloaded too.
        """
        self._load(self._vars)

    def reset_communication(self, node_id: int) -> None:
        """NMT reset communication: 1000h–1FFFh back to stored values, `$NODEID` for `node_id`."""
        self._node_id = node_id
        self._load(key for key in self._vars if area_of(key[0]) is Area.COMMUNICATION)

    def _storable(self, key: _Key, var: ODVariable) -> bool:
        index = key[0]
        return (
            var.writable
            and not SIM_ONLY_FIRST <= index <= SIM_ONLY_LAST
            and index not in (STORE_PARAMETERS, RESTORE_DEFAULTS)
        )

    def forget_at_next_store(self, index: int, subindex: int) -> None:
        """The next store does not keep this entry (nor its earlier stored value): after the
        reset that follows, the entry holds its EDS default (simulated EEPROM fault)."""
        var = self.variable(index, subindex)
        if not self._storable((index, subindex), var):
            raise SdoAbort(INVALID_VALUE, f"{index:04X}h:{subindex:02X}h is never stored")
        self._forget_next.add((index, subindex))

    def _save(self, areas: frozenset[Area]) -> None:
        forget, self._forget_next = self._forget_next, set()
        if (SIM_FORGET_AT_STORE, 0) in self._values:
            self._values[(SIM_FORGET_AT_STORE, 0)] = 0  # the injection is used up
        for key, var in self._vars.items():
            if key in forget:
                self._stored.pop(key, None)
            elif area_of(key[0]) in areas and self._storable(key, var):
                self._stored[key] = _Stored(self._values[key], self._node_id)

    def _forget(self, areas: frozenset[Area]) -> None:
        # CiA 301: restoring defaults takes effect at the next reset, which then loads the EDS.
        for key in [k for k in self._stored if area_of(k[0]) in areas]:
            del self._stored[key]

    def _load(self, keys: Iterable[_Key]) -> None:
        self._changes += 1
        for key in keys:
            stored = self._stored.get(key)
            var = self._vars[key]
            self._values[key] = (
                self._default(key, var) if stored is None else self._restored(var, stored)
            )

    def _restored(self, var: ODVariable, stored: _Stored) -> Value:
        value = stored.value
        base = self._relative_base(var)
        if base is None or not isinstance(value, int) or stored.node_id == self._node_id:
            return value
        # A stored COB-ID that still used the node-relative CAN-ID follows the new node id (flag
        # bits such as "PDO invalid" kept); one the master set to another CAN-ID stays as stored.
        if value & CAN_ID_MASK == (base + stored.node_id) & CAN_ID_MASK:
            return value - stored.node_id + self._node_id
        return value

    def _relative_base(self, var: ODVariable) -> int | None:
        """Default of a `$NODEID` entry without the node id, or None for other entries."""
        if not var.relative:
            return None
        raw = getattr(var, "default_raw", None)  # set by canopen's EDS import
        if isinstance(raw, str) and "$NODEID" in raw.upper():
            return _nodeid_base(raw)
        if isinstance(var.default, int):
            return var.default - self._od_node_id
        return None

    def _default(self, key: _Key, var: ODVariable) -> Value:
        index, sub = key
        if index in (STORE_PARAMETERS, RESTORE_DEFAULTS) and sub >= 1:
            return 1  # bit 0: the device saves / restores on command (CiA 301 §7.5.2.13)
        base = self._relative_base(var)
        if base is not None:
            return base + self._node_id
        default: Value | None = var.default
        if isinstance(default, int):
            return _as_signed(var, default)
        if default is not None:
            return default
        if sub == 0 and index in self._highest_sub:
            # ARRAY/RECORD sub 0 names the highest sub-index, except where CiA 301 §7.5.2 makes
            # it a count of entries in use, which starts at 0.
            return 0 if _sub0_counts_entries(index) else self._highest_sub[index]
        return _zero(var)


def _sub0_counts_entries(index: int) -> bool:
    return (
        index == 0x1003  # Pre-defined error field: number of errors
        or 0x1600 <= index <= 0x17FF  # RPDO mapping: number of mapped objects
        or 0x1A00 <= index <= 0x1BFF  # TPDO mapping
    )


def _zero(var: ODVariable) -> Value:
    """Start value of an entry without a default: zero, moved into the entry's limits."""
    if var.data_type in (datatypes.VISIBLE_STRING, datatypes.UNICODE_STRING):
        return ""
    if var.data_type in (datatypes.OCTET_STRING, datatypes.DOMAIN):
        return b""
    zero: int | float = 0.0 if var.data_type in datatypes.FLOAT_TYPES else 0
    if var.min is not None and zero < var.min:
        return var.min
    if var.max is not None and zero > var.max:
        return var.max
    return zero


def _as_signed(var: ODVariable, value: int) -> int:
    """EDS files often write signed defaults as their bit pattern (0xFFFF for INTEGER16 -1),
    which canopen keeps as a positive number; take them as the device would."""
    if var.data_type not in datatypes.SIGNED_TYPES:
        return value
    bits = len(var)
    if 1 << (bits - 1) <= value < 1 << bits:
        return value - (1 << bits)
    return value


def _check_limits(var: ODVariable, value: Value) -> None:
    if var.data_type not in datatypes.NUMBER_TYPES or not isinstance(value, int | float):
        return
    if var.min is not None and value < var.min:
        raise SdoAbort(VALUE_TOO_LOW, f"{value} < {var.min}")
    if var.max is not None and value > var.max:
        raise SdoAbort(VALUE_TOO_HIGH, f"{value} > {var.max}")


def _store_command_areas(index: int, subindex: int, value: Value) -> frozenset[Area]:
    """Areas a 1010h/1011h write selects; a wrong signature or sub-index -> 08000020."""
    signature = SAVE_SIGNATURE if index == STORE_PARAMETERS else LOAD_SIGNATURE
    areas = AREAS_OF_SUBINDEX.get(subindex)
    if areas is None or value != signature:
        raise SdoAbort(CANNOT_STORE, f"{index:04X}h:{subindex:02X}h needs signature {signature:#x}")
    return areas
