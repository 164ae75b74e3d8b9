"""PDO validation against the shipped dictionaries of the three drives: what a commissioning
engineer is told before anything is written."""

from __future__ import annotations

from dataclasses import replace
from functools import cache

import pytest

import servodesk_data
from servodesk.od import ObjectDictionaryModel, load_od
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo.recommended import recommended
from servodesk.pdo.validate import PdoContext, used_ids, validate

NODE = 5


@cache
def dictionary(profile: str, node: int = NODE) -> ObjectDictionaryModel:
    """The drive.eds the tool ships for `profile`, loaded as the backend loads it."""
    return load_od(servodesk_data.eds_path(profile), node_id=node)


def context(profile: str, **changes: object) -> PdoContext:
    """What the PDO service knows about a `profile` drive at node 5 on an otherwise quiet bus."""
    quirks = servodesk_data.load(profile).quirks
    ctx = PdoContext(
        node=NODE,
        od=dictionary(profile),
        byte_granular=quirks.pdo_byte_granular,
        rpdo_count=quirks.rpdo_count,
        tpdo_count=quirks.tpdo_count,
        sync_producing=True,
        other_ids={},
        rtr_supported=quirks.pdo_rtr_transmission,
        fixed_cob_ids=quirks.pdo_fixed_cob_ids,
    )
    return replace(ctx, **changes)  # type: ignore[arg-type]


def obj(index: int, subindex: int, bits: int) -> MappedObject:
    return MappedObject(index, subindex, bits)


def rpdo(number: int, *mapping: MappedObject, **comm: int | bool) -> PdoConfig:
    fields: dict[str, int | bool] = {"cob_id": 0x200 + 0x100 * (number - 1) + NODE, "valid": True}
    fields |= {"transmission_type": 255} | comm
    return PdoConfig("rpdo", number, mapping=mapping, **fields)  # type: ignore[arg-type]


def tpdo(number: int, *mapping: MappedObject, **comm: int | bool) -> PdoConfig:
    fields: dict[str, int | bool] = {"cob_id": 0x180 + 0x100 * (number - 1) + NODE, "valid": True}
    fields |= {"transmission_type": 255} | comm
    return PdoConfig("tpdo", number, mapping=mapping, **fields)  # type: ignore[arg-type]


CONTROLWORD = obj(0x6040, 0, 16)
STATUSWORD = obj(0x6041, 0, 16)
TARGET_POSITION = obj(0x607A, 0, 32)


def recommendation(profile: str, modes: list[str], **changes: object) -> list[PdoConfig]:
    """`recommended()` as the PDO service calls it for a `profile` drive (generic: the cia402)."""
    ctx = context(profile if profile in servodesk_data.PROFILE_NAMES else "cia402")
    args: dict[str, object] = {
        "node": NODE,
        "od": ctx.od,
        "byte_granular": ctx.byte_granular,
        "rpdo_count": ctx.rpdo_count,
        "tpdo_count": ctx.tpdo_count,
    } | changes
    return recommended(profile, modes, **args)  # type: ignore[arg-type]


@pytest.mark.parametrize("profile", ["mdi-s1c", "kinco", "cia402"])
@pytest.mark.parametrize("modes", [["pp"], ["pv", "pt"], ["hm"], ["ip"], ["pp", "pv", "hm"]])
def test_the_recommended_mapping_passes(profile: str, modes: list[str]) -> None:
    assert validate(recommendation(profile, modes), context(profile)) == []


CASES: list[tuple[str, str, list[PdoConfig], dict[str, object], str, int | None, int | None]] = [
    (
        "not mappable",
        "mdi-s1c",
        [rpdo(2, CONTROLWORD, obj(0x2006, 0x08, 16))],
        {},
        "RPDO2: 2006h:08 PA-103 Maximum speed is not PDO-mappable in this drive's dictionary",
        0x2006,
        0x08,
    ),
    (
        "not in the dictionary",
        "kinco",
        [rpdo(1, CONTROLWORD, obj(0x60B1, 0, 32))],
        {},
        "RPDO1: 60B1h:00 is not in this drive's dictionary",
        0x60B1,
        0,
    ),
    (
        "read-only object in an RPDO",
        "cia402",
        [rpdo(1, STATUSWORD)],
        {},
        "RPDO1: 6041h:00 Statusword is read-only (ro); an RPDO writes into it",
        0x6041,
        0,
    ),
    (
        "length does not match the type",
        "mdi-s1c",
        [rpdo(1, obj(0x6040, 0, 8))],
        {},
        "RPDO1: 6040h:00 Controlword is UNSIGNED16 (16 bits) but is mapped with 8 bits",
        0x6040,
        0,
    ),
    (
        "more than one frame",
        "kinco",
        [tpdo(1, STATUSWORD, obj(0x6064, 0, 32), obj(0x606C, 0, 32))],
        {},
        "TPDO1 maps 80 bits; one CAN frame carries at most 64 (8 bytes)",
        0x1A00,
        0,
    ),
    (
        "collision inside the configuration",
        "kinco",
        [tpdo(1, STATUSWORD), tpdo(2, STATUSWORD, cob_id=0x185)],
        {},
        "TPDO2 CAN id 185h is already used by TPDO1",
        0x1801,
        1,
    ),
    (
        "collision with another node",
        "cia402",
        [tpdo(5, STATUSWORD, cob_id=0x182)],
        {"other_ids": {0x182: "node 2 TPDO1"}},
        "TPDO5 CAN id 182h is already used by node 2 TPDO1",
        0x1804,
        1,
    ),
    (
        "collision with the node's own EMCY",
        "kinco",
        [tpdo(1, STATUSWORD, cob_id=0x85)],
        {},
        "TPDO1 CAN id 85h is already used by this node's EMCY",
        0x1800,
        1,
    ),
    (
        "not an 11-bit id",
        "kinco",
        [rpdo(1, CONTROLWORD, cob_id=0x805)],
        {},
        "RPDO1 CAN id 805h is not an 11-bit identifier (0–7FFh)",
        0x1400,
        1,
    ),
    (
        "restricted id",
        "kinco",
        [rpdo(1, CONTROLWORD, cob_id=0x701)],
        {},
        "RPDO1 CAN id 701h is reserved by CiA 301 (heartbeat / boot-up)",
        0x1400,
        1,
    ),
    (
        "the drive fixes the CAN id of PDOs 1-4",
        "mdi-s1c",
        [rpdo(1, CONTROLWORD, cob_id=0x301)],
        {},
        "RPDO1 CAN id 301h cannot be set: this drive fixes it at 205h (200h + node id);"
        " only the valid bit can change",
        0x1400,
        1,
    ),
    (
        "remote request on an RPDO",
        "cia402",
        [rpdo(1, CONTROLWORD, transmission_type=253)],
        {},
        "RPDO1 transmission type 253 (remote request) is for TPDOs only; use 0–240 or 254/255",
        0x1400,
        2,
    ),
    (
        "remote request on a drive without RTR PDOs",
        "mdi-s1c",
        [tpdo(1, STATUSWORD, transmission_type=252)],
        {},
        "TPDO1 transmission type 252 (remote request): this drive has no RTR-triggered PDOs",
        0x1800,
        2,
    ),
    (
        "reserved transmission type",
        "kinco",
        [tpdo(1, STATUSWORD, transmission_type=245)],
        {},
        "TPDO1 transmission type 245 is reserved (use 0–240 or 252–255)",
        0x1800,
        2,
    ),
    (
        "more PDOs than the drive has",
        "mdi-s1c",
        [rpdo(5, CONTROLWORD, cob_id=0x222)],
        {},
        "RPDO5 does not exist: this drive has 4 RPDOs (RPDO1–RPDO4)",
        0x1404,
        None,
    ),
    (
        "inhibit time too long",
        "cia402",
        [tpdo(1, STATUSWORD, inhibit_time_100us=70000)],
        {},
        "TPDO1 inhibit time 70000 is outside 0–65535",
        0x1800,
        3,
    ),
    (
        "negative event timer",
        "mdi-s1c",
        [tpdo(1, STATUSWORD, event_timer_ms=-1)],
        {},
        "TPDO1 event timer -1 is outside 0–65535",
        0x1800,
        5,
    ),
    (
        "SYNC start value on a drive without 1800h:06",
        "kinco",
        [tpdo(1, STATUSWORD, transmission_type=1, sync_start=3)],
        {},
        "TPDO1 sets the SYNC start value but this drive has no 1800h:06 SYNC start value",
        0x1800,
        6,
    ),
]


@pytest.mark.parametrize(
    ("profile", "pdos", "changes", "message", "index", "subindex"),
    [case[1:] for case in CASES],
    ids=[case[0] for case in CASES],
)
def test_each_problem_is_one_sentence_naming_the_object(
    profile: str,
    pdos: list[PdoConfig],
    changes: dict[str, object],
    message: str,
    index: int | None,
    subindex: int | None,
) -> None:
    problems = validate(pdos, context(profile, **changes))
    assert [(p.message, p.index, p.subindex) for p in problems] == [(message, index, subindex)]


FINE: list[tuple[str, str, list[PdoConfig], dict[str, object]]] = [
    (
        "RPDO with inhibit time and event timer (ignored; Kinco 1400h has neither)",
        "kinco",
        [rpdo(1, CONTROLWORD, TARGET_POSITION, inhibit_time_100us=50, event_timer_ms=100)],
        {},
    ),
    (
        # a warning of its own (sync_rule.py), not a problem of the mapping
        "synchronous without a SYNC producer",
        "cia402",
        [tpdo(1, STATUSWORD, transmission_type=1)],
        {"sync_producing": False},
    ),
    (
        "synchronous but invalid PDO while no SYNC runs",
        "mdi-s1c",
        [tpdo(1, STATUSWORD, valid=False, transmission_type=1)],
        {"sync_producing": False},
    ),
    (
        "invalid PDOs may keep colliding ids",
        "cia402",
        [tpdo(5, valid=False, cob_id=0), tpdo(6, valid=False, cob_id=0)],
        {"other_ids": {0x182: "node 2 TPDO1"}},
    ),
    (
        "another node's TPDO id on an invalid PDO",
        "kinco",
        [tpdo(1, STATUSWORD, valid=False, cob_id=0x182)],
        {"other_ids": {0x182: "node 2 TPDO1"}},
    ),
    (
        "free CAN id on PDOs 5-8 of the Nanotec-style drive",
        "cia402",
        [rpdo(5, CONTROLWORD, cob_id=0x222), tpdo(8, STATUSWORD, cob_id=0x1A2)],
        {},
    ),
    (
        "a full frame of whole bytes",
        "mdi-s1c",
        [tpdo(1, STATUSWORD, obj(0x6064, 0, 32), obj(0x6061, 0, 8), obj(0x607E, 0, 8))],
        {},
    ),
]


@pytest.mark.parametrize(
    ("profile", "pdos", "changes"), [case[1:] for case in FINE], ids=[case[0] for case in FINE]
)
def test_configurations_that_can_be_applied(
    profile: str, pdos: list[PdoConfig], changes: dict[str, object]
) -> None:
    assert validate(pdos, context(profile, **changes)) == []


def test_byte_granular_drives_refuse_single_bits() -> None:
    # the shipped dictionaries have no BOOLEAN object; give the MDi one, mappable
    od = dictionary("mdi-s1c")
    digital = od.objects[0x60FE]
    flag = replace(digital.subs[1], subindex=2, name="Brake released", data_type=0x0001)
    flags = replace(digital, subs={**digital.subs, 2: flag})
    ctx = context("mdi-s1c", od=replace(od, objects={**od.objects, 0x60FE: flags}))
    problems = validate([rpdo(1, CONTROLWORD, obj(0x60FE, 2, 1))], ctx)
    assert [p.message for p in problems] == [
        "RPDO1: 60FEh:02 Brake released is mapped with 1 bits; this drive maps whole bytes only"
        " (8, 16, 32 bits)"
    ]
    assert validate([rpdo(1, CONTROLWORD, obj(0x60FE, 2, 8))], ctx) == []
    bit_granular = replace(ctx, byte_granular=False)
    assert validate([rpdo(1, CONTROLWORD, obj(0x60FE, 2, 1))], bit_granular) == []


def test_more_than_eight_objects() -> None:
    problems = validate([rpdo(1, *[obj(0x6060, 0, 8)] * 9)], context("cia402"))
    assert [(p.message, p.index, p.subindex) for p in problems] == [
        ("RPDO1 maps 9 objects; a PDO holds at most 8", 0x1600, 0),
        ("RPDO1 maps 72 bits; one CAN frame carries at most 64 (8 bytes)", 0x1600, 0),
    ]


def test_a_pdo_given_twice_is_reported_once() -> None:
    problems = validate([tpdo(1, STATUSWORD), tpdo(1, STATUSWORD)], context("kinco"))
    assert [p.message for p in problems] == ["TPDO1 is given twice"]


def test_used_ids_name_every_id_of_the_node() -> None:
    pdos = [tpdo(1, STATUSWORD), tpdo(2, valid=False), rpdo(1, CONTROLWORD)]
    assert used_ids(3, [replace(p, cob_id=p.cob_id - NODE + 3) for p in pdos]) == {
        0x083: "node 3 EMCY",
        0x583: "node 3 SDO response",
        0x603: "node 3 SDO request",
        0x703: "node 3 heartbeat",
        0x183: "node 3 TPDO1",
        0x203: "node 3 RPDO1",
    }
