"""The drive data package: EDS files load in canopen with the manuals' factory values, the
profile.toml catalogues and fault tables agree with their EDS, and the loader rejects bad data."""

from __future__ import annotations

import configparser
import hashlib
import json
import logging
import re
from collections.abc import Iterator

import canopen
import pytest
from canopen.objectdictionary import ObjectDictionary, ODVariable, datatypes

import servodesk_data
from servodesk_data import DriveData, TakesEffect
from servodesk_data.fault_kind import FaultKind

PROFILES = servodesk_data.PROFILE_NAMES
NODE = 5
WRITABLE = {"rw", "wo", "rww", "rwr"}
TYPE_RANGE = {
    datatypes.INTEGER8: (-0x80, 0x7F),
    datatypes.INTEGER16: (-0x8000, 0x7FFF),
    datatypes.INTEGER32: (-0x80000000, 0x7FFFFFFF),
    datatypes.UNSIGNED8: (0, 0xFF),
    datatypes.UNSIGNED16: (0, 0xFFFF),
    datatypes.UNSIGNED32: (0, 0xFFFFFFFF),
}


def _od(profile: str, node_id: int = NODE) -> ObjectDictionary:
    return canopen.import_od(str(servodesk_data.eds_path(profile)), node_id)


def _entry(od: ObjectDictionary, index: int, sub: int = 0) -> ODVariable | None:
    """The entry if the EDS defines it (ODArray would invent missing subs on item access)."""
    if index not in od:
        return None
    obj = od[index]
    if isinstance(obj, ODVariable):
        return obj if sub == 0 else None
    found: ODVariable | None = obj.subindices.get(sub)
    return found


def _variables(od: ObjectDictionary) -> Iterator[ODVariable]:
    for index in od:
        obj = od[index]
        if isinstance(obj, ODVariable):
            yield obj
        else:
            yield from (obj.subindices[sub] for sub in obj.subindices)


def _default(od: ObjectDictionary, index: int, sub: int = 0) -> object:
    var = _entry(od, index, sub)
    assert var is not None, f"{index:04X}:{sub:02X} missing"
    return var.default


def _int(od: ObjectDictionary, index: int, sub: int = 0) -> int:
    value = _default(od, index, sub)
    assert isinstance(value, int)
    return value


@pytest.fixture(params=PROFILES)
def profile(request: pytest.FixtureRequest) -> str:
    name: str = request.param
    return name


# ----------------------------------------------------------------------------- EDS files


def test_eds_imports_without_warnings_and_every_default_resolves(
    profile: str, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.DEBUG, logger="canopen")
    path = servodesk_data.eds_path(profile)
    path.read_bytes().decode("ascii")  # CiA 306: ASCII only
    od = _od(profile)
    assert [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING] == []
    unresolved = [f"{v.index:04X}:{v.subindex:02X}" for v in _variables(od) if v.default is None]
    assert unresolved == []


def test_sub0_is_highest_sub_and_default_mappings_are_valid(profile: str) -> None:
    od = _od(profile)
    for index in od:
        obj = od[index]
        if isinstance(obj, ODVariable):
            continue
        if 0x1600 <= index <= 0x17FF or 0x1A00 <= index <= 0x1BFF:
            bits = 0
            for sub in range(1, _int(od, index, 0) + 1):
                raw = _int(od, index, sub)
                target = _entry(od, raw >> 16, (raw >> 8) & 0xFF)
                assert target is not None, f"{index:04X}:{sub} maps a missing {raw:08X}"
                assert target.pdo_mappable, f"{index:04X}:{sub} maps {raw:08X}"
                assert raw & 0xFF == 8 * len(target.encode_raw(0)), f"{index:04X}:{sub}"
                bits += raw & 0xFF
            assert bits <= 64
        elif index != 0x1003:  # Pre-defined error field: sub 0 counts the errors
            assert obj[0].default == max(obj.subindices), f"{index:04X}"


MDI_FACTORY = [  # MDi-S1-C manual §5.2/§5.3 tables (node 5), and the §3.4.3 default PDO mapping
    (0x1000, 0, 0),
    (0x1001, 0, 0),
    (0x1005, 0, 0x80),
    (0x1006, 0, 0),
    (0x1008, 0, "DVS_CANOPEN"),
    (0x1009, 0, "V1.0"),
    (0x100A, 0, "V1.01"),
    (0x100C, 0, 0),
    (0x100D, 0, 0),
    (0x1010, 1, 1),
    (0x1011, 4, 1),
    (0x1014, 0, 0x85),
    (0x1016, 0, 5),
    (0x1016, 5, 0),
    (0x1017, 0, 0),
    (0x1018, 1, 0x445653),
    (0x1018, 2, 1),
    (0x1018, 3, 1),
    (0x1018, 4, 1),
    (0x1200, 1, 0x605),
    (0x1200, 2, 0x585),
    (0x1400, 0, 6),
    (0x1400, 1, 0x205),
    (0x1401, 1, 0x80000305),
    (0x1402, 1, 0x80000405),
    (0x1403, 1, 0x80000505),
    (0x1403, 2, 255),
    (0x1400, 6, 0),
    (0x1600, 0, 2),
    (0x1600, 1, 0x60400010),
    (0x1600, 2, 0x607A0020),
    (0x1601, 0, 0),
    (0x1800, 1, 0x40000185),
    (0x1801, 1, 0xC0000285),
    (0x1802, 1, 0xC0000385),
    (0x1803, 1, 0xC0000485),
    (0x1800, 2, 255),
    (0x1A00, 0, 2),
    (0x1A00, 1, 0x60410010),
    (0x1A00, 2, 0x60640020),
    (0x1A03, 0, 0),
    (0x2000, 0x0F, 4),
    (0x2006, 0, 0x0B),
    (0x2006, 0x08, 6000),
    (0x2006, 0x0A, 1),
    (0x2006, 0x0B, 5),
    (0x605A, 0, 1),
    (0x6081, 0, 100000),
    (0x6083, 0, 100000),
    (0x6085, 0, 100000),
    (0x6087, 0, 1),
    (0x6091, 1, 131072),
    (0x6091, 2, 100000),
    (0x6098, 0, 17),
    (0x6099, 1, 100000),
    (0x6099, 2, 20000),
    (0x609A, 0, 1000000),
    (0x60C2, 1, 1),
    (0x60C2, 2, -3),
    (0x6502, 0, 0x6D),
]


@pytest.mark.parametrize(("index", "sub", "value"), MDI_FACTORY)
def test_mdi_factory_values(index: int, sub: int, value: object) -> None:
    assert _default(_od("mdi-s1c"), index, sub) == value


MDI_TYPES = [  # (index, sub, data type, access, mappable) from MDi-S1-C manual §5.2/§5.3
    (0x1005, 0, datatypes.UNSIGNED32, "rw", False),
    (0x100D, 0, datatypes.UNSIGNED8, "rw", False),
    (0x1017, 0, datatypes.UNSIGNED16, "rw", False),
    (0x1018, 1, datatypes.UNSIGNED32, "ro", False),
    (0x1200, 1, datatypes.UNSIGNED32, "ro", False),
    (0x603F, 0, datatypes.UNSIGNED16, "ro", True),
    (0x6040, 0, datatypes.UNSIGNED16, "rw", True),
    (0x605A, 0, datatypes.INTEGER16, "rw", True),
    (0x6060, 0, datatypes.INTEGER8, "rw", True),
    (0x6063, 0, datatypes.INTEGER32, "ro", True),
    (0x6071, 0, datatypes.INTEGER16, "rw", True),
    (0x607E, 0, datatypes.UNSIGNED8, "rw", True),
    (0x6081, 0, datatypes.UNSIGNED32, "rw", True),
    (0x6098, 0, datatypes.INTEGER8, "rw", True),
    (0x60C2, 1, datatypes.UNSIGNED8, "rw", True),
    (0x60C2, 2, datatypes.INTEGER8, "rw", True),
    (0x60FD, 0, datatypes.UNSIGNED32, "rw", True),
    (0x6502, 0, datatypes.UNSIGNED32, "ro", True),
    (0x2006, 8, datatypes.UNSIGNED16, "rw", False),
]


@pytest.mark.parametrize(("index", "sub", "data_type", "access", "mappable"), MDI_TYPES)
def test_mdi_types_access_and_mapping(
    index: int, sub: int, data_type: int, access: str, mappable: bool
) -> None:
    var = _entry(_od("mdi-s1c"), index, sub)
    assert var is not None
    assert (var.data_type, var.access_type, var.pdo_mappable) == (data_type, access, mappable)


@pytest.mark.parametrize(
    ("index", "sub", "low", "high"),
    [
        (0x6060, 0, 0, 7),
        (0x6071, 0, -1000, 1000),
        (0x6098, 0, 0, 99),
        (0x605A, 0, 1, 6),
        (0x607E, 0, 0, 1),
        (0x2000, 0x0F, 0, 4),
        (0x2006, 0x0A, 1, 127),
        (0x2006, 0x0B, 0, 6),
    ],
)
def test_mdi_ranges(index: int, sub: int, low: int, high: int) -> None:
    var = _entry(_od("mdi-s1c"), index, sub)
    assert var is not None
    assert (var.min, var.max) == (low, high)


def test_mdi_has_exactly_the_table_objects_plus_marked_additions() -> None:
    od = _od("mdi-s1c")
    table = {0x603F, 0x6040, 0x6041, 0x605A, 0x6060, 0x6061, 0x6063, 0x6064, 0x606C, 0x6071}
    table |= {0x6077, 0x607A, 0x607C, 0x607E, 0x6081, 0x6083, 0x6084, 0x6085, 0x6087, 0x6091}
    table |= {0x6098, 0x6099, 0x609A, 0x60C1, 0x60C2, 0x60F4, 0x60FD, 0x60FE, 0x60FF, 0x6502}
    additions = {0x6065, 0x6067, 0x6072, 0x6080}
    assert {i for i in od if i >= 0x6000} == table | additions
    assert all(f"{i:04X}h" in od.comments for i in additions)
    assert "0x00020192" in od.comments  # 1000h = 0 is explained


def test_mdi_node_relative_defaults_follow_the_node_id() -> None:
    od = _od("mdi-s1c", 127)
    assert [_default(od, 0x1400, 1), _default(od, 0x1803, 1), _default(od, 0x1014)] == [
        0x27F,
        0xC00004FF,
        0xFF,
    ]


def test_mdi_max_speed_reads_as_in_table_2_31() -> None:
    var = _entry(_od("mdi-s1c"), 0x2006, 0x08)
    assert var is not None
    # 584 | 4B 06 20 08 70 17 00 00: two data bytes, 6000 rpm
    assert var.encode_raw(6000) == bytes.fromhex("70 17")
    assert var.default == 6000
    assert servodesk_data.load("mdi-s1c").parameter("PA-103").default == 6000


@pytest.mark.parametrize(
    ("profile_name", "index", "sub", "value"),
    [
        ("kinco", 0x1000, 0, 0x00020192),
        ("kinco", 0x1008, 0, "Kinco Servo"),
        ("kinco", 0x1018, 1, 0x300),
        ("kinco", 0x1400, 1, 0x205),
        ("kinco", 0x1401, 1, 0x80000305),
        ("kinco", 0x1800, 1, 0x185),
        ("kinco", 0x1800, 3, 1000),
        ("kinco", 0x1803, 1, 0x80000485),
        ("kinco", 0x2600, 2, 0),
        ("kinco", 0x2F80, 0, 0),
        ("kinco", 0x2F81, 0, 0x00),
        ("kinco", 0x2F82, 0, 0x14),
        ("kinco", 0x6502, 0, 0x6D),
        ("cia402", 0x1000, 0, 0x00020192),
        ("cia402", 0x1003, 0, 0),
        ("cia402", 0x1003, 8, 0),
        ("cia402", 0x1018, 1, 0x26C),
        ("cia402", 0x1019, 0, 0),
        ("cia402", 0x1403, 1, 0x505),
        ("cia402", 0x1404, 1, 0x80000000),
        ("cia402", 0x1407, 1, 0x80000000),
        ("cia402", 0x1800, 1, 0x185),
        ("cia402", 0x1800, 4, 0),
        ("cia402", 0x1803, 1, 0x485),
        ("cia402", 0x1804, 1, 0xC0000000),
        ("cia402", 0x1807, 6, 0),
        ("cia402", 0x6502, 0, 0x6D),
    ],
)
def test_kinco_and_cia402_factory_values(
    profile_name: str, index: int, sub: int, value: object
) -> None:
    assert _default(_od(profile_name), index, sub) == value


@pytest.mark.parametrize(
    ("index", "value"), [(0x5FF1, -5 * 131072), (0x5FF2, 5 * 131072), (0x5FF3, 131072)]
)
def test_sim_only_objects(profile: str, index: int, value: int) -> None:
    od = _od(profile)
    assert _default(od, index) == value
    assert _default(od, 0x5FF4) == 131072 + 131072 // 4
    inject = _entry(od, 0x5FF0)
    assert inject is not None
    assert (inject.data_type, inject.access_type, inject.pdo_mappable) == (
        datatypes.UNSIGNED32,
        "rw",
        False,
    )
    assert all(od[i].name.startswith("SIM ") for i in range(0x5FF0, 0x5FF5))
    assert [i for i in od if 0x5F00 <= i <= 0x5FFF and not od[i].name.startswith("SIM ")] == []
    assert "simulator-only" in od.comments


# ----------------------------------------------------------------------------- TOML vs EDS


def _device_info(profile: str) -> configparser.SectionProxy:
    parser = configparser.RawConfigParser()
    parser.read(servodesk_data.eds_path(profile), encoding="ascii")
    return parser["DeviceInfo"]


def test_identity_matches_eds(profile: str) -> None:
    data, od = servodesk_data.load(profile), _od(profile)
    ident = data.identity
    assert ident.name == profile
    assert [_default(od, 0x1018, 1), _default(od, 0x1018, 2), _default(od, 0x1000)] == [
        ident.vendor_id,
        ident.product_code,
        ident.device_type,
    ]
    info = od.device_information
    assert (info.vendor_number, info.product_number) == (ident.vendor_id, ident.product_code)
    assert data.eds == servodesk_data.eds_path(profile)
    assert servodesk_data.data_dir(profile).joinpath("profile.toml").is_file()


def test_quirks_match_eds(profile: str) -> None:
    data, od = servodesk_data.load(profile), _od(profile)
    q = data.quirks
    assert len([i for i in od if 0x1400 <= i <= 0x15FF]) == q.rpdo_count
    assert len([i for i in od if 0x1600 <= i <= 0x17FF]) == q.rpdo_count
    assert len([i for i in od if 0x1800 <= i <= 0x19FF]) == q.tpdo_count
    assert len([i for i in od if 0x1A00 <= i <= 0x1BFF]) == q.tpdo_count
    info = _device_info(profile)
    assert (int(info["NrOfRXPDO"]), int(info["NrOfTXPDO"])) == (q.rpdo_count, q.tpdo_count)
    assert (int(info["Granularity"]) == 8) is q.pdo_byte_granular
    modes = _int(od, 0x6502)
    assert {bit + 1 for bit in range(32) if modes >> bit & 1} == q.supported_modes
    assert _default(od, 0x6098) in q.homing_methods
    assert (_entry(od, 0x1003) is not None) is q.fault_history_1003
    assert (_entry(od, 0x2600, 2) is not None) is q.kinco_fault_bits
    for ref in (q.max_speed_object, q.node_id_object, *q.bitrate_objects):
        assert ref is None or _entry(od, *ref) is not None, ref
    for n in range(q.pdo_fixed_cob_ids):  # node-id based CAN-IDs: base + node id
        assert _int(od, 0x1400 + n, 1) & 0x7FF == 0x200 + 0x100 * n + NODE
        assert _int(od, 0x1800 + n, 1) & 0x7FF == 0x180 + 0x100 * n + NODE


def test_catalogue_entries_exist_with_matching_range_and_default(profile: str) -> None:
    data, od = servodesk_data.load(profile), _od(profile)
    for p in data.parameters:
        var = _entry(od, *p.object)
        assert var is not None, p.name
        assert var.access_type in WRITABLE, p.name
        assert var.default == p.default, p.name
        assert var.data_type in TYPE_RANGE, p.name
        type_low, type_high = TYPE_RANGE[int(var.data_type)]
        assert p.min == (var.min if var.min is not None else type_low), p.name
        assert p.max == (var.max if var.max is not None else type_high), p.name
        assert p.unit == var.unit, p.name
        assert all(p.min <= code <= p.max for code in p.choices), p.name


def test_catalogue_covers_the_commissioning_parameters(profile: str) -> None:
    data = servodesk_data.load(profile)
    objects = {p.object for p in data.parameters}
    common = {(0x605A, 0), (0x6065, 0), (0x6067, 0), (0x6081, 0), (0x6083, 0), (0x6084, 0)}
    common |= {(0x6085, 0), (0x6091, 1), (0x6091, 2), (0x6098, 0), (0x6099, 1), (0x6099, 2)}
    assert common | {(0x609A, 0)} <= objects
    assert set(data.parameter("Homing method").choices) == data.quirks.homing_methods


@pytest.mark.parametrize(
    ("number", "ref"),
    [
        (14, (0x2000, 0x0F)),
        (103, (0x2006, 0x08)),
        (105, (0x2006, 0x0A)),
        (106, (0x2006, 0x0B)),
        (0, (0x2000, 0x01)),
        (15, (0x2000, 0x10)),
        (16, (0x2001, 0x01)),
    ],
)
def test_mdi_pa_rule(number: int, ref: tuple[int, int]) -> None:
    assert servodesk_data.mdi_pa_object(number) == ref


def test_mdi_pa_parameters_follow_the_rule_and_need_a_reset_for_node_and_bitrate() -> None:
    data, od = servodesk_data.load("mdi-s1c"), _od("mdi-s1c")
    pa = {p.name: p for p in data.parameters if p.name.startswith("PA-")}
    assert sorted(pa) == ["PA-103", "PA-105", "PA-106", "PA-14"]
    for name, p in pa.items():
        assert p.object == servodesk_data.mdi_pa_object(int(name[3:]))
        var = _entry(od, *p.object)
        assert var is not None
        assert var.name.startswith(f"{name} ")
    assert pa["PA-105"].takes_effect is TakesEffect.AFTER_RESET
    assert pa["PA-106"].takes_effect is TakesEffect.AFTER_RESET
    assert pa["PA-106"].choices[5] == "500 kbit/s"
    with pytest.raises(ValueError, match="PA--1"):
        servodesk_data.mdi_pa_object(-1)


# ----------------------------------------------------------------------------- faults

MDI_ALARMS = [1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 14, 18, 19, 20, 21, 23, 29, 39, 40, 41, 42, 47]
MDI_ALARMS += [50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 61, 62]  # MDi-S1-C manual §4.1

# The fault each simulated cause raises (None: statusword only or never raised). The MDi's limit
# inputs are drive inhibits: one stops the motion, both are alarm 7 (MDi-S1-C manual §4.1).
KIND_CODES = {
    "mdi-s1c": [1, 4, None, None, 7, 62, 61, 61, None],
    "kinco": [0x8400, 0x8611, 0x8613, 0x8612, None, 0x6011, 0x8120, 0x8120, None],
    "cia402": [0x8400, 0x8611, 0x8613, 0x8612, None, 0x8700, 0x8130, 0x8130, None],
}
KIND_ORDER = [
    FaultKind.OVERSPEED,
    FaultKind.FOLLOWING_ERROR,
    FaultKind.POSITIVE_LIMIT,
    FaultKind.NEGATIVE_LIMIT,
    FaultKind.BOTH_LIMITS,
    FaultKind.SYNC_LOST,
    FaultKind.HEARTBEAT_LOST,
    FaultKind.LIFE_GUARD,
    FaultKind.HOMING_ERROR,
]


def test_every_fault_kind_is_mapped_once(profile: str) -> None:
    data = servodesk_data.load(profile)
    assert set(KIND_ORDER) == set(FaultKind)
    codes = [_code(data, kind) for kind in KIND_ORDER]
    assert codes == KIND_CODES[profile]
    never = data.quirks.limit_switch_reaction.never_raised
    for kind in FaultKind:
        holders = [f.code for f in data.faults if kind in f.kinds]
        assert len(holders) + (kind in data.quirks.status_only_kinds) + (kind in never) == 1, kind


def _code(data: DriveData, kind: FaultKind) -> int | None:
    entry = data.fault_for_kind(kind)
    return None if entry is None else entry.code


def test_fault_tables_have_unique_codes_and_consistent_error_register(profile: str) -> None:
    faults = servodesk_data.load(profile).faults
    assert len({f.code for f in faults}) == len(faults)
    for f in faults:
        assert f.error_register & 0x01, f.code  # generic error bit with every fault
        expected = {0x2: 0x02, 0x3: 0x04, 0x4: 0x08}.get(f.emcy_code >> 12, 0)
        if f.emcy_code >> 8 in (0x81, 0x82):
            expected = 0x10
        assert f.error_register & expected == expected, hex(f.code)
        assert f.description
        assert f.what_to_check
        assert f.name_en


def test_mdi_alarm_table_is_complete() -> None:
    data = servodesk_data.load("mdi-s1c")
    assert [f.code for f in data.faults] == MDI_ALARMS
    assert all(any("\u4e00" <= ch <= "\u9fff" for ch in f.name) for f in data.faults)
    following = data.fault(4)
    assert following is not None
    assert following.emcy_code == 0x8611
    assert data.fault(9) is None


KINCO_BITS = [  # Kinco manual §8: (2600h:02 bit, 603Fh code)
    (0x1, 0x6010), (0x2, 0x6011), (0x4, 0x7305), (0x8, 0x17305), (0x10, 0x17306),
    (0x20, 0x4210), (0x40, 0x5112), (0x80, 0x3210), (0x100, 0x3220), (0x200, 0x12320),
    (0x400, 0x22320), (0x800, 0x32320), (0x1000, 0x5441), (0x2000, 0x8611), (0x4000, 0x8400),
    (0x8000, 0x8312), (0x10000, 0x8120), (0x20000, 0x2310), (0x40000, 0x8612),
    (0x80000, 0x8613), (0x100000, 0x4310), (0x200000, 0x7600), (0x400000, 0x7601),
    (0x800000, 0x7602), (0x1000000, 0x7603),
]  # fmt: skip


def test_kinco_fault_bits_and_codes() -> None:
    faults = servodesk_data.load("kinco").faults
    assert [(f.kinco_bit, f.code) for f in faults] == KINCO_BITS
    assert all(f.emcy_code == f.code & 0xFFFF for f in faults)  # 603Fh / EMCY carry 16 bits


# Kinco's manual and the CiA tables are English only: each entry has ServoDesk's Chinese
# translation (name_zh) beside the source's words, which stay as they were (a deliberate
# correction of the English updates its digest here); the MDi's Chinese is the manual's name
ENGLISH_FAULT_NAMES = {
    "kinco": (25, "a2fdb69e727d475ea104d9f3ed87fe53f791b972eadaf4abb2a9937519c5cbcc"),
    "cia402": (23, "7743f549da2cf17c86469a2c6ddc9c1c22c1c2937db2473d9f42d852feb5d3ec"),
    "mdi-s1c": (34, "505216c3cb0ec6a3c11dc26abf9529694363e38e35ca9ac8a9dbc27ce50195f0"),
}


@pytest.mark.parametrize("profile", ["kinco", "cia402"])
def test_english_only_fault_tables_have_a_chinese_translation(profile: str) -> None:
    faults = servodesk_data.load(profile).faults
    for f in faults:
        assert f.name_zh is not None, hex(f.code)
        assert f.name_zh.strip(), hex(f.code)
        assert any("\u3400" <= ch <= "\u9fff" for ch in f.name_zh), (hex(f.code), f.name_zh)
        assert not any("\u3400" <= ch <= "\u9fff" for ch in f.name + f.name_en), hex(f.code)


@pytest.mark.parametrize("profile", sorted(ENGLISH_FAULT_NAMES))
def test_fault_names_keep_the_sources_words(profile: str) -> None:
    faults = servodesk_data.load(profile).faults
    names = json.dumps([(f.code, f.name, f.name_en) for f in faults], ensure_ascii=False)
    digest = hashlib.sha256(names.encode()).hexdigest()
    assert (len(faults), digest) == ENGLISH_FAULT_NAMES[profile]


def test_mdi_chinese_is_the_manuals_not_a_translation() -> None:
    assert all(f.name_zh is None for f in servodesk_data.load("mdi-s1c").faults)


# every shipped fault's cause and check in Chinese (the API's check_zh): the MDi's cause in its
# manual's own words, the rest ServoDesk's translation, keeping object indices, parameter names
# and bit names as they are
_KEPT = re.compile(r"[0-9A-F]{4}h|PA-\d+|\b[A-Z][A-Za-z0-9]*_[A-Za-z0-9_]+\b")
_CJK = re.compile(r"[\u3400-\u9fff]")


@pytest.mark.parametrize("profile", ["mdi-s1c", "kinco", "cia402"])
def test_every_shipped_fault_has_its_cause_and_check_in_chinese(profile: str) -> None:
    for f in servodesk_data.load(profile).faults:
        for text in (f.description_zh, f.what_to_check_zh):
            assert text is not None, hex(f.code)
            assert text.strip(), hex(f.code)
            assert _CJK.search(text), (hex(f.code), text)
        assert f.what_to_check_zh is not None
        for token in _KEPT.findall(f.what_to_check):
            assert token in f.what_to_check_zh, (hex(f.code), token, f.what_to_check_zh)
        for token in _KEPT.findall(f.description):
            assert token in (f.description_zh or ""), (hex(f.code), token, f.description_zh)


def test_mdi_chinese_cause_is_the_manuals() -> None:
    for f in servodesk_data.load("mdi-s1c").faults:
        assert f.description_zh == f.description.split(" — ")[0].strip(), f.code


def test_cia402_faults_are_their_own_emcy_codes() -> None:
    faults = servodesk_data.load("cia402").faults
    assert all(f.emcy_code == f.code and f.kinco_bit == 0 for f in faults)
    assert {0x2310, 0x3210, 0x3220, 0x4210, 0x4310, 0x7121, 0x7305, 0x8130} <= {
        f.code for f in faults
    }


def test_factory_bitrates_and_unsupported_bitrates() -> None:
    for name, rate in (("mdi-s1c", 500_000), ("kinco", 1_000_000)):
        data, od = servodesk_data.load(name), _od(name)
        factory = {ref: _int(od, *ref) for ref in data.quirks.bitrate_objects}
        assert servodesk_data.bitrate_of(data, factory) == rate
    with pytest.raises(ValueError, match="mdi-s1c cannot run at 800000 bit/s"):
        servodesk_data.bitrate_objects(servodesk_data.load("mdi-s1c"), 800_000)
    assert servodesk_data.bitrate_objects(servodesk_data.load("cia402"), 500_000) == {}
