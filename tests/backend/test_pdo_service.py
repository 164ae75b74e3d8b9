"""The PDO service against the simulated drives (1 MDi-S1-C, 2 Kinco, 3 CiA 402): read every
PDO, apply in each drive's procedure, refuse invalid mappings before any write, undo a change
the drive refuses part-way, and watch the PDOs live."""

from __future__ import annotations

import asyncio
import dataclasses

import pytest

from servodesk.errors import PdoApplyError, PdoInvalidError, SdoAbortError
from servodesk.models.network import NmtCommandName, SyncConfig
from servodesk.od import ObjectDictionaryModel
from servodesk.od.datatypes import DataType
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo.procedure import Procedure, plan
from servodesk.pdo.read import Slot
from servodesk.pdo.recommended import MODES
from servodesk.pdo.service import PdoService
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio

NOT_MAPPABLE = 0x06040041  # SDO abort: object cannot be mapped to the PDO
DEVICE_STATE = 0x08000022  # SDO abort: not in the present device state
PDO_AREA = range(0x1400, 0x1C00)  # every PDO communication and mapping parameter
STATUSWORD = MappedObject(0x6041, 0, 16)  # Statusword
POSITION = MappedObject(0x6064, 0, 32)  # Position actual value
CONTROLWORD = MappedObject(0x6040, 0, 16)  # Controlword
VELOCITY = MappedObject(0x606C, 0, 32)  # Velocity actual value
FLAG = (0x6061, 0)  # Modes of operation display, made a BOOLEAN by `with_flag`
HEARTBEAT_TIME = (0x1017, 0)  # Producer heartbeat time: not mappable on any of the drives

Key = tuple[int, int]


def pdo_service(nodes: SimNodes, *, sync_producing: bool = False) -> PdoService:
    period = 10_000 if sync_producing else None
    return PdoService(
        nodes,
        known_nodes=lambda: sorted(nodes.profiles),
        network=lambda: nodes.network,
        bitrate=lambda: None,
        sync=lambda: SyncConfig(producing=sync_producing, period_us=period),
    )


async def pdo_area(nodes: SimNodes, node: int) -> dict[Key, bytes | int]:
    """Every sub of 1400h–1BFFh the node's dictionary lists, as read (or the abort code)."""
    session = nodes.session(node)
    out: dict[Key, bytes | int] = {}
    for index, obj in sorted(nodes.od(node).objects.items()):
        if index not in PDO_AREA:
            continue
        for sub in sorted(obj.subs):
            try:
                out[(index, sub)] = await session.upload(index, sub)
            except SdoAbortError as abort:
                out[(index, sub)] = abort.code
    return out


def written(tap: SdoTap) -> list[tuple[int, int, int]]:
    """(index, sub-index, value) of each expedited SDO download seen."""
    out = []
    for frame in tap.frames:
        size = 4 - ((frame.data[0] >> 2) & 3)
        value = int.from_bytes(frame.data[4 : 4 + size], "little")
        out.append((int.from_bytes(frame.data[1:3], "little"), frame.data[3], value))
    return out


def unnamed(pdos: list[PdoConfig]) -> list[PdoConfig]:
    return [
        dataclasses.replace(p, mapping=tuple(dataclasses.replace(o, name=None) for o in p.mapping))
        for p in pdos
    ]


def pdo(pdos: list[PdoConfig], kind: str, number: int) -> PdoConfig:
    return next(p for p in pdos if p.kind == kind and p.number == number)


def with_flag(od: ObjectDictionaryModel) -> ObjectDictionaryModel:
    """`od` with a mappable BOOLEAN (as a vendor's EDS may have): 1-bit mapping is legal for it
    where the drive maps bits (CiA 301), not where it maps whole bytes only (MDi, Kinco)."""
    obj = od.objects[FLAG[0]]
    sub = dataclasses.replace(obj.subs[FLAG[1]], data_type=DataType.BOOLEAN, pdo_mappable=True)
    objects = {**od.objects, FLAG[0]: dataclasses.replace(obj, subs={**obj.subs, FLAG[1]: sub})}
    return dataclasses.replace(od, objects=objects)


def claim_mappable(od: ObjectDictionaryModel, index: int, subindex: int) -> ObjectDictionaryModel:
    """`od` claiming that an entry is PDO-mappable (the drive knows better)."""
    obj = od.objects[index]
    sub = dataclasses.replace(obj.subs[subindex], pdo_mappable=True)
    objects = {**od.objects, index: dataclasses.replace(obj, subs={**obj.subs, subindex: sub})}
    return dataclasses.replace(od, objects=objects)


# ------------------------------------------------------------------------------------ reading


async def test_reads_every_pdo_with_names(nodes: SimNodes) -> None:
    service = pdo_service(nodes)
    counts = {1: 4, 2: 4, 3: 8}  # the profiles' rpdo_count / tpdo_count
    for node, count in counts.items():
        pdos = await service.read(node)
        assert [(p.kind, p.number) for p in pdos] == [
            *(("rpdo", n) for n in range(1, count + 1)),
            *(("tpdo", n) for n in range(1, count + 1)),
        ]
    tpdo1 = pdo(await service.read(1), "tpdo", 1)
    assert tpdo1.valid
    assert tpdo1.cob_id == 0x181
    assert [(o.index, o.name) for o in tpdo1.mapping] == [
        (0x6041, "Statusword"),
        (0x6064, "Position actual value"),
    ]


# ------------------------------------------------------------------------------------ applying


@pytest.mark.parametrize("node", [1, 2, 3])
@pytest.mark.parametrize("mode", MODES)
async def test_recommended_mappings_apply_and_read_back(
    nodes: SimNodes, node: int, mode: str
) -> None:
    service = pdo_service(nodes, sync_producing=True)  # IP is synchronous
    wanted = await service.recommended(node, [mode])
    result = await service.apply(node, wanted, actor="test")
    assert unnamed(result) == unnamed(wanted)
    assert unnamed(await service.read(node)) == unnamed(wanted)


async def test_mdi_order_invalidate_first(nodes: SimNodes) -> None:
    service = pdo_service(nodes)
    tpdo1 = pdo(await service.read(1), "tpdo", 1)
    tap = SdoTap(nodes, 1, writes_only=True)
    new = dataclasses.replace(tpdo1, mapping=(STATUSWORD, VELOCITY), event_timer_ms=100)
    await service.apply(1, [new])
    tap.remove()
    # MDi-S1-C CANopen manual §2.5.4: invalid, count 0, entries, count, parameters, valid; only
    # what changes is written (entry 1 stays the statusword); the RTR bit 30 is kept
    assert written(tap) == [
        (0x1800, 1, 0xC0000181),
        (0x1A00, 0, 0),
        (0x1A00, 2, 0x606C0020),
        (0x1A00, 0, 2),
        (0x1800, 5, 100),
        (0x1800, 1, 0x40000181),
    ]


async def test_kinco_order_communication_first(nodes: SimNodes) -> None:
    service = pdo_service(nodes)
    tpdo1 = pdo(await service.read(2), "tpdo", 1)
    tap = SdoTap(nodes, 2, writes_only=True)
    new = dataclasses.replace(
        tpdo1, mapping=(STATUSWORD, POSITION), transmission_type=254, inhibit_time_100us=50
    )
    await service.apply(2, [new])
    tap.remove()
    # Kinco manual §5.4.4: the PDO stays valid; transmission type, inhibit time, then the
    # entries and the count last (it was 0 already)
    assert written(tap) == [
        (0x1800, 2, 254),
        (0x1800, 3, 50),
        (0x1A00, 1, 0x60410010),
        (0x1A00, 2, 0x60640020),
        (0x1A00, 0, 2),
    ]


@pytest.mark.parametrize(
    ("node", "mapping", "words"),
    [
        (1, (MappedObject(*HEARTBEAT_TIME, 16),), "not PDO-mappable"),
        (3, (POSITION, POSITION, VELOCITY), "one CAN frame carries at most 64"),
        (1, (STATUSWORD, MappedObject(*FLAG, 1)), "whole bytes only"),
    ],
    ids=["not-mappable", "over-64-bits", "not-byte-aligned-on-mdi"],
)
async def test_invalid_mappings_are_refused_before_any_write(
    nodes: SimNodes, node: int, mapping: tuple[MappedObject, ...], words: str
) -> None:
    nodes.set_od(node, with_flag(nodes.od(node)))
    service = pdo_service(nodes)
    wanted = dataclasses.replace(pdo(await service.read(node), "tpdo", 1), mapping=mapping)
    tap = SdoTap(nodes, writes_only=True)
    with pytest.raises(PdoInvalidError) as refused:
        await service.apply(node, [wanted])
    tap.remove()
    assert any(words in problem.message for problem in refused.value.problems)
    assert tap.frames == []  # not one SDO write reached any drive
    validation = await service.validate(node, [wanted])
    assert not validation.ok
    assert [p.message for p in validation.problems] == [p.message for p in refused.value.problems]


async def test_bit_mapping_is_fine_where_the_drive_maps_bits(nodes: SimNodes) -> None:
    nodes.set_od(3, with_flag(nodes.od(3)))
    service = pdo_service(nodes)
    wanted = dataclasses.replace(
        pdo(await service.read(3), "tpdo", 1), mapping=(STATUSWORD, MappedObject(*FLAG, 1))
    )
    assert (await service.validate(3, [wanted])).problems == []


async def test_cia402_in_operational_is_handled(nodes: SimNodes) -> None:
    service = pdo_service(nodes)
    await nodes.nmt(3, NmtCommandName.START)
    tpdo2 = pdo(await service.read(3), "tpdo", 2)
    new = dataclasses.replace(tpdo2, mapping=(STATUSWORD, POSITION), transmission_type=255)
    result = await service.apply(3, [new])
    assert unnamed([pdo(result, "tpdo", 2)]) == unnamed([new])
    # back in Operational: the drive refuses PDO changes again (Nanotec CANopen article)
    with pytest.raises(SdoAbortError) as refused:
        await nodes.session(3).download(0x1801, 2, bytes([254]))  # TPDO2 transmission type
    assert refused.value.code == DEVICE_STATE


async def test_a_refused_step_leaves_the_device_as_it_was(nodes: SimNodes) -> None:
    # The dictionary claims 1017h is mappable; the drive refuses it when its entry is written,
    # after RPDO1 was already changed: both are undone.
    nodes.set_od(1, claim_mappable(nodes.od(1), *HEARTBEAT_TIME))
    service = pdo_service(nodes)
    before = await pdo_area(nodes, 1)
    current = await service.read(1)
    rpdo1 = dataclasses.replace(pdo(current, "rpdo", 1), mapping=(CONTROLWORD,))
    tpdo1 = dataclasses.replace(
        pdo(current, "tpdo", 1), mapping=(STATUSWORD, MappedObject(*HEARTBEAT_TIME, 16))
    )
    with pytest.raises(PdoApplyError) as failed:
        await service.apply(1, [rpdo1, tpdo1])
    assert failed.value.step == "write 1A00h:02 = 10170010h"
    assert failed.value.abort_code == NOT_MAPPABLE
    assert failed.value.restored is True
    assert await pdo_area(nodes, 1) == before


# ------------------------------------------------------------------------------------ live


async def test_live_check_decodes_tpdo_frames(nodes: SimNodes) -> None:
    service = pdo_service(nodes)
    wanted = await service.recommended(1, ["pp"])
    tpdo1 = dataclasses.replace(pdo(wanted, "tpdo", 1), event_timer_ms=20)
    await service.apply(1, [*(p for p in wanted if p != pdo(wanted, "tpdo", 1)), tpdo1])
    await nodes.nmt(1, NmtCommandName.START)
    await service.start_live(1)
    await asyncio.sleep(0.6)
    check = service.live(1)
    row = next(r for r in check.pdos if r.kind == "tpdo" and r.number == 1)
    assert row.cob_id == 0x181
    assert row.frames >= 5
    assert row.rate_hz is not None
    assert 35 <= row.rate_hz <= 65  # every 20 ms: 50/s from frame to frame
    names = {value.name: value.value for value in row.values}
    assert "Statusword" in names
    assert "Position actual value" in names
    service.stop_live(1)
    assert not service.live(1).active


# ------------------------------------------------------------------------------------ procedure

TPDO1 = Slot("tpdo", 1)
MDI_TPDO1 = {  # 1800h TPDO1 communication, 1A00h TPDO1 mapping
    (0x1800, 1): 0x40000181,
    (0x1800, 2): 255,
    (0x1800, 5): 0,
    (0x1A00, 0): 1,
    (0x1A00, 1): 0x60410010,
    (0x1A00, 2): 0,
}


@pytest.mark.parametrize(
    ("change", "procedure", "expected"),
    [
        # only the valid bit: one write, nothing to invalidate around
        ({(0x1800, 1): 0xC0000181}, Procedure.INVALIDATE_FIRST, [(0x1800, 1, 0xC0000181)]),
        # a parameter of a valid PDO: invalid, the parameter, valid again
        (
            {(0x1800, 5): 20},
            Procedure.INVALIDATE_FIRST,
            [(0x1800, 1, 0xC0000181), (0x1800, 5, 20), (0x1800, 1, 0x40000181)],
        ),
        # Kinco: a valid PDO's communication parameters before the mapping, its count last
        (
            {(0x1800, 2): 1, (0x1A00, 0): 2, (0x1A00, 2): 0x60640020},
            Procedure.COMM_FIRST,
            [(0x1800, 2, 1), (0x1A00, 0, 0), (0x1A00, 2, 0x60640020), (0x1A00, 0, 2)],
        ),
        # Kinco, a new CAN id: invalid around it (CiA 301 §7.5.2.35)
        (
            {(0x1800, 1): 0x40000281},
            Procedure.COMM_FIRST,
            [(0x1800, 1, 0xC0000181), (0x1800, 1, 0x40000281)],
        ),
    ],
    ids=["valid-bit-only", "parameter-of-valid-pdo", "kinco-comm-first", "kinco-new-id"],
)
def test_plan(
    change: dict[Key, int], procedure: Procedure, expected: list[tuple[int, int, int]]
) -> None:
    steps = plan(TPDO1, MDI_TPDO1, {**MDI_TPDO1, **change}, procedure)
    assert [(s.index, s.subindex, s.value) for s in steps] == expected


def test_restore_plan_writes_everything_touched_back() -> None:
    tried = {**MDI_TPDO1, (0x1A00, 0): 2, (0x1A00, 2): 0x10170010}
    force = frozenset({(0x1800, 1), (0x1A00, 0), (0x1A00, 2)})
    steps = plan(TPDO1, tried, MDI_TPDO1, Procedure.INVALIDATE_FIRST, force=force)
    assert [s.label for s in steps] == [
        "write 1800h:01 = C0000181h",
        "write 1A00h:00 = 00h",
        "write 1A00h:02 = 00000000h",
        "write 1A00h:00 = 01h",
        "write 1800h:01 = 40000181h",
    ]
