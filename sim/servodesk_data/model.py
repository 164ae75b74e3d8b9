"""Typed, frozen view of one drive's profile.toml: identity, quirks, parameter catalogue, faults.

Field names are the TOML keys, so a reader of the file finds every key here and vice versa.
String-valued TOML keys become `StrEnum`s: typed for the code, equal to the TOML spelling.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path

from servodesk_data.fault_kind import FaultKind

# the EMCY data format is protocol (MDi alarm number, Kinco, CiA 301); profiles name it
from servodesk_protocol.emcy import EmcyFormat as EmcyFormat

ObjectRef = tuple[int, int]  # (index, sub-index), written "2006:08" in the TOML files


class SdoLengthCheck(StrEnum):
    GENERIC = "generic"  # any size mismatch -> 06070010h (MDi-S1-C manual table 2.18)
    SPECIFIC = "specific"  # too long 06070012h / too short 06070013h (Nanotec article)


class PdoRemapRule(StrEnum):
    """When a drive lets a master change a PDO's parameters. Under every rule the mapping
    entries (sub 1..8) change only while the mapping's sub 0 is 0 (CiA 301 §7.5.2.38)."""

    # mapping and comm subs 2, 3, 5 only while the PDO's COB-ID bit 31 is set, 06010000h
    # (MDi-S1-C manual §5.2, tables 2.40/2.41)
    WHILE_INVALID = "while_invalid"
    # no PDO parameter in NMT Operational, 08000022h (Nanotec article)
    OUTSIDE_OPERATIONAL = "outside_operational"
    # only the CiA 301 sub-0 procedure: a valid PDO keeps its COB-ID while its type, inhibit
    # time and mapping change (Kinco manual §5.4.4/§5.4.5 write 1800h:02 and 1A00h:01.. with
    # 1800h:01 = 181h, the mapping count last)
    WHILE_UNMAPPED = "while_unmapped"


class NodeIdSource(StrEnum):
    PARAMETER = "parameter"  # MDi PA-105 (MDi-S1-C manual §2.2)
    DIP_PLUS_OFFSET = "dip_plus_offset"  # Kinco DIP switch + 2F80h (Kinco manual §5.1)
    FIXED = "fixed"  # set outside CANopen (not described by the manual)


class LimitSwitchReaction(StrEnum):
    """What a drive does when the axis runs into a limit switch (60FDh bit 0/1) outside homing."""

    # a fault: positive_limit / negative_limit (Kinco 8613h/8612h, Kinco servo CANopen manual §8)
    FAULT = "fault"
    # drive-inhibit inputs: the drive stops and refuses that direction, no fault; both inputs
    # active while enabled raise both_limits (MDi alarm 7, MDi-S1-C CANopen manual §4.1)
    INHIBIT = "inhibit"

    @property
    def never_raised(self) -> frozenset[FaultKind]:
        """Fault kinds a drive with this reaction never raises (its table need not map them)."""
        if self is LimitSwitchReaction.INHIBIT:
            return frozenset({FaultKind.POSITIVE_LIMIT, FaultKind.NEGATIVE_LIMIT})
        return frozenset({FaultKind.BOTH_LIMITS})


class TakesEffect(StrEnum):
    IMMEDIATELY = "immediately"
    AFTER_RESET = "after_reset"
    AFTER_STORE_AND_RESET = "after_store_and_reset"


CJK = re.compile(r"[\u3400-\u9fff]")  # Chinese characters (the MDi-S1-C manual's names)


@dataclass(frozen=True)
class Identity:
    name: str  # the profile name, equal to its folder ("mdi-s1c")
    vendor_id: int  # 1018h:01
    product_code: int  # 1018h:02
    device_type: int  # 1000h
    description: str
    seed: str  # which manual the profile is written from


@dataclass(frozen=True)
class BitrateCode:
    """One bitrate setting: the values of the profile's bitrate objects, in their order."""

    values: tuple[int, ...]
    bitrate: int  # bit/s


@dataclass(frozen=True)
class Quirks:
    emcy_format: EmcyFormat
    sdo_block_transfer: bool
    sdo_length_check: SdoLengthCheck
    pdo_remap_rule: PdoRemapRule
    pdo_byte_granular: bool
    rpdo_count: int
    tpdo_count: int
    pdo_rtr_transmission: bool
    pdo_fixed_cob_ids: int  # PDOs 1..n whose CAN-ID follows the node id (only bit 31/30 writable)
    sync_min_period_us: int  # 0 = no limit
    sync_require_period_before_enable: bool
    supported_modes: frozenset[int]
    homing_methods: frozenset[int]
    pp_immediate_setpoint: bool
    unsupported_mode_display: int | None  # 6061h after an unsupported 6060h; None = keep old mode
    homing_reference_found_bit15: bool
    max_speed_object: ObjectRef
    fault_history_1003: bool
    kinco_fault_bits: bool
    node_id_source: NodeIdSource
    node_id_object: ObjectRef | None
    bitrate_objects: tuple[ObjectRef, ...]
    bitrate_codes: tuple[BitrateCode, ...]
    # Kinds that this drive shows only in the statusword, never as a fault (no EMCY, no 603Fh).
    status_only_kinds: frozenset[FaultKind]
    limit_switch_reaction: LimitSwitchReaction
    # Objects that accept only the values their catalogue entry lists as choices (MDi 605Ah:
    # 1, 2, 5, 6 although 3 and 4 lie inside the range); other values abort 06090030.
    enumerated_objects: tuple[ObjectRef, ...] = ()


@dataclass(frozen=True)
class Parameter:
    name: str  # what the user calls it: "PA-14", "Node offset", "Following error window"
    object: ObjectRef
    label: str
    description: str
    unit: str
    min: int
    max: int
    default: int
    takes_effect: TakesEffect
    # code -> meaning; may be partial, empty when free-valued (read-only, left out of the hash)
    choices: Mapping[int, str] = field(hash=False)


@dataclass(frozen=True)
class FaultEntry:
    code: int  # the profile's own number: MDi alarm, Kinco 603Fh code, CiA EMCY code
    name: str  # as the manual names it (Chinese for MDi)
    name_en: str
    description: str
    what_to_check: str
    emcy_code: int  # CiA 301/402 class code for 1003h and for decoding
    error_register: int  # 1001h bits set while the fault is active (bit 0 always)
    kinco_bit: int  # 2600h:02 bit (Kinco), 0 elsewhere
    kinds: tuple[FaultKind, ...]  # which simulated causes raise this fault
    # ServoDesk's Chinese translation of name_en where the source is English only (Kinco,
    # CiA 402); None for a table whose `name` is the manual's own Chinese (MDi)
    name_zh: str | None = None
    # description and what_to_check in Chinese: MDi's description_zh is the manual's own words,
    # the rest ServoDesk's translation. Every shipped table has them (tests/sim); a user's
    # profile may leave them out (None), and its faults then have no Chinese check text
    description_zh: str | None = None
    what_to_check_zh: str | None = None

    @property
    def manual_chinese(self) -> bool:
        """Whether `name` is the manual's own Chinese (MDi-S1-C) rather than its English."""
        return bool(CJK.search(self.name))

    @property
    def chinese_name(self) -> str | None:
        """The Chinese name: the manual's own, else ServoDesk's translation (None: neither)."""
        return self.name if self.manual_chinese else self.name_zh


@dataclass(frozen=True)
class DriveData:
    profile: str
    identity: Identity
    quirks: Quirks
    parameters: tuple[Parameter, ...]
    faults: tuple[FaultEntry, ...]
    eds: Path  # the drive.eds beside the profile.toml

    def parameter(self, name: str) -> Parameter:
        """Catalogue entry by its user-facing name (KeyError if the profile has none)."""
        for parameter in self.parameters:
            if parameter.name == name:
                return parameter
        raise KeyError(f"{self.profile} has no parameter {name!r}")

    def fault(self, code: int) -> FaultEntry | None:
        """Fault table entry for the profile's own code, None for an unlisted code."""
        for entry in self.faults:
            if entry.code == code:
                return entry
        return None

    def fault_for_kind(self, kind: FaultKind) -> FaultEntry | None:
        """The fault this drive raises for `kind`; None when it only shows it in the statusword."""
        for entry in self.faults:
            if kind in entry.kinds:
                return entry
        return None
