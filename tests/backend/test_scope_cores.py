"""Pure cores of the scope, table-tested: physical units and keys of signals, the TPDO plan
(packing, CAN ids, SDO fallbacks), numpy batch decoding against the per-frame reference decoder,
monotonic arrival times, SDO values and the trigger detectors."""

from __future__ import annotations

import math
import re
import struct
from collections.abc import Sequence
from functools import partial
from itertools import accumulate
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from servodesk.motion.units import DriveUnits
from servodesk.od import DataType, DeviceInfo, ObjectDictionaryModel, OdObject, OdSub
from servodesk.od import datatypes as dt
from servodesk.od.model import Access
from servodesk.pdo.decode import PdoDecoder
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.scope import trigger as tr
from servodesk.scope.batch import BatchDecoder, FieldSpec, Floats, sdo_value, strictly_increasing
from servodesk.scope.plan import NodePlan, plan_node
from servodesk.scope.signals import SignalInfo, scaling, signal_info, signal_key
from servodesk.scope.trigger import BitTrigger, LevelTrigger, StateTrigger
from servodesk_protocol.cia402 import Cia402State as S

T = DataType
NODE = 5
DISABLED, READY, ON, ENABLED, FAULT, NONE = 0x0250, 0x0231, 0x0233, 0x0237, 0x0218, 0x0201
USER_RPM = DriveUnits(velocity_actual_rpm=False)  # 606Ch in 60FFh's units
Batches = list[list[float]]
Hit = tuple[float, str] | None
Layout = list[tuple[int | None, int]]  # (data type, bits) one after the other; None: unknown
lv = partial(LevelTrigger, 5.0, label="pos")  # a level of 5
bt = partial(BitTrigger, label="sw")
sw = partial(StateTrigger, label="402")
Trigger = LevelTrigger | BitTrigger | StateTrigger
DEFAULT = DriveUnits()  # 131072 inc/rev, 100000 user units/rev
GEARED = DriveUnits.of(131072, (131072 * 3, 100000))  # 3 motor revs per 100000 user units


def arr(*values: float) -> Floats:
    return np.asarray(values, dtype=np.float64)


def sub(index: int, t: int, name: str = "", access: Access = "ro", mappable: bool = True) -> OdSub:
    return OdSub(index, 0, name or f"Object {index:04X}", t, access, mappable)


def info(index: int, data_type: int = T.INTEGER32, **kw: Any) -> SignalInfo:
    return signal_info(NODE, sub(index, data_type, **kw), DEFAULT)


@pytest.mark.parametrize(
    ("index", "subindex", "units", "raw", "want"),
    [
        (0x6064, 0, DEFAULT, 50000, ("position", "rev", "user units", 0.5)),
        (0x607A, 0, GEARED, 100000, ("position", "rev", "user units", 3.0)),
        (0x6063, 0, DEFAULT, -131072, ("position", "rev", "inc", -1.0)),
        (0x60F4, 0, DEFAULT, 250, ("following_error", "rev", "user units", 0.0025)),
        (0x606C, 0, DEFAULT, 3000, ("velocity", "rpm", "rpm", 3000.0)),
        (0x606C, 0, USER_RPM, 100000, ("velocity", "rpm", "user units/s", 60.0)),
        (0x60FF, 0, DEFAULT, -50000, ("velocity", "rpm", "user units/s", -30.0)),
        (0x606B, 0, GEARED, 100000, ("velocity", "rpm", "user units/s", 180.0)),
        (0x6077, 0, DEFAULT, -125, ("torque", "%", "0.1 % rated torque", -12.5)),
        (0x6078, 0, DEFAULT, 55, ("current", "%", "0.1 % rated current", 5.5)),
        (0x6041, 0, DEFAULT, 0x237, ("statusword", "V", "V", 0x237)),  # raw, the OD's unit
        (0x6064, 1, DEFAULT, 7, ("other", "V", "V", 7.0)),  # only sub 0 is the known object
        (0x2000, 0, DEFAULT, 230, ("other", "V", "V", 230.0)),
    ],
)
def test_scaling(
    index: int, subindex: int, units: DriveUnits, raw: int, want: tuple[Any, ...]
) -> None:
    scale = scaling(index, subindex, "V", units)
    assert (scale.quantity, scale.unit, scale.raw_unit, raw * scale.scale) == pytest.approx(want)


@pytest.mark.parametrize(
    ("index", "subindex", "name", "key"),
    [
        (0x6064, 0, "Position actual value", "position_actual"),
        (0x6041, 0, "Statusword", "statusword"),
        (0x6064, 1, "Odd sub", "x6064_01_odd_sub"),
        (0x2006, 8, "Overspeed (rpm)", "x2006_08_overspeed_rpm"),
        (0x2000, 0, "", "x2000_00"),
        (0x2000, 0, "Ü—", "x2000_00"),
        (0x2001, 0xFF, "  Température moteur  ", "x2001_ff_temp_rature_moteur"),
        (0x2002, 1, "a" * 31 + " tail", "x2002_01_" + "a" * 31),  # cut at 32, no "_" at the end
    ],
)
def test_signal_key(index: int, subindex: int, name: str, key: str) -> None:
    assert signal_key(index, subindex, name) == key
    assert re.fullmatch("[a-z0-9_]+", key)


@pytest.mark.parametrize(
    ("data_type", "access", "mappable", "want"),
    [
        (T.INTEGER32, "ro", True, (32, True, None)),
        (T.BOOLEAN, "rw", True, (1, True, None)),
        (T.REAL64, "wo", True, (64, False, None)),
        (T.UNSIGNED16, "ro", False, (16, True, "is not PDO-mappable in this drive's dictionary")),
        (T.VISIBLE_STRING, "ro", True, (None, True, "has no fixed size")),
    ],
)
def test_signal_info(data_type: int, access: Access, mappable: bool, want: tuple[Any, ...]) -> None:
    signal = info(0x2100, data_type, access=access, mappable=mappable, name="Bus voltage")
    assert (signal.bits, signal.readable, signal.mappable_reason) == want
    assert (signal.label, signal.key) == ("2100h:00 Bus voltage", "x2100_00_bus_voltage")


def tpdo(n: int, cob: int | None = None, valid: bool = False, *maps: MappedObject) -> PdoConfig:
    cob = (0x80 + 0x100 * n + NODE if n <= 4 else 0) if cob is None else cob
    return PdoConfig("tpdo", n, cob, valid, 255, 10, 100, 0, tuple(maps))


FREE = [tpdo(n) for n in range(1, 9)]
SW, POS, MODE = info(0x6041, T.UNSIGNED16), info(0x6064), info(0x6061, T.INTEGER8)
VEL, TRQ = info(0x606C), info(0x6077, T.INTEGER16)


def plan(signals: Sequence[SignalInfo], current: Sequence[PdoConfig] = FREE, **kw: Any) -> NodePlan:
    facts = {"byte_granular": True, "fixed_cob_ids": 0, "taken_ids": {}, **kw}
    return plan_node(NODE, signals, current, **facts)


def where(result: NodePlan) -> list[tuple[str, int | None, int | None, int]]:
    return [(p.source, p.tpdo, p.cob_id, p.bit_offset) for p in result.placements]


def test_plan_packs_first_fit_into_free_tpdos_sent_on_every_sync() -> None:
    result = plan([SW, POS, MODE, VEL, TRQ])
    # 56 bits in TPDO1: the velocity opens TPDO2, the torque does not fit TPDO1 either (72 bits)
    assert where(result) == [("pdo", 1, 0x185, o) for o in (0, 16, 48)] + [
        ("pdo", 2, 0x285, o) for o in (0, 32)
    ]
    first = result.scope_pdos[0]
    assert [(o.index, o.bits) for o in first.mapping] == [(0x6041, 16), (0x6064, 32), (0x6061, 8)]
    comm = {
        (p.valid, p.transmission_type, p.inhibit_time_100us, p.event_timer_ms, p.sync_start)
        for p in result.scope_pdos
    }
    assert comm == {(True, 1, 0, 0, 0)}  # sent on every SYNC
    assert result.restore_pdos == (FREE[0], FREE[1])  # exactly the slots taken, as they were
    assert result.notes == ()


@pytest.mark.parametrize(
    ("byte_granular", "bits", "tpdos"),
    [(False, 1, [1] * 8 + [2]), (True, 8, [1] * 8 + [2])],  # ≤ 8 entries, ≤ 64 bits
)
def test_plan_booleans(byte_granular: bool, bits: int, tpdos: list[int]) -> None:
    flags = [info(0x2200 + n, T.BOOLEAN) for n in range(9)]
    result = plan(flags, byte_granular=byte_granular)
    assert [p.tpdo for p in result.placements] == tpdos
    assert {o.bits for pdo in result.scope_pdos for o in pdo.mapping} == {bits}
    assert [p.bit_offset for p in result.placements][:3] == [0, bits, 2 * bits]


def test_plan_keeps_the_users_valid_tpdos() -> None:
    mine = tpdo(1, 0x185, True, MappedObject(0x6041, 0, 16))
    current = [mine, tpdo(2), tpdo(3, 0x385, True), tpdo(4)]
    result = plan([POS, VEL, TRQ], current)
    assert [p.tpdo for p in result.placements] == [2, 2, 4]
    assert result.restore_pdos == (current[1], current[3])
    assert mine not in result.scope_pdos


@pytest.mark.parametrize(
    ("signal", "current", "note"),
    [
        (info(0x2300, access="wo"), FREE, "is write-only"),
        (info(0x2300, mappable=False), FREE, "is not PDO-mappable in this drive's dictionary"),
        (info(0x1008, T.VISIBLE_STRING), FREE, "has no fixed size"),
        (POS, [tpdo(n, valid=True) for n in (1, 2, 3, 4)], "has no free TPDO to travel in"),
        (POS, [tpdo(1, 0x585, valid=False)], "has no free TPDO"),  # own id only: none usable
    ],
)
def test_plan_falls_back_to_sdo(signal: SignalInfo, current: list[PdoConfig], note: str) -> None:
    result = plan([signal], current, id_change_needs_reset=current[0].cob_id == 0x585)
    (placement,) = result.placements
    assert (placement.source, placement.tpdo, placement.cob_id) == ("sdo", None, None)
    assert (placement.note or "").startswith(f"polled by SDO: it {note}")
    assert (result.scope_pdos, result.restore_pdos) == ((), ())


@pytest.mark.parametrize(
    ("slot", "fixed", "taken", "cob_id"),
    [
        (tpdo(1, 0x1F0), 0, {}, 0x1F0),  # the slot's own id when usable
        (tpdo(1, 0x1F0), 4, {}, 0x185),  # a drive that fixes ids 1–4: only 180h + node
        (tpdo(1, 0x1F0), 0, {0x1F0: "node 112 TPDO1"}, 0x185),  # else the pre-defined one
        (tpdo(2, 0x601), 0, {}, 0x285),  # CiA 301 restricted (SDO request range)
        (tpdo(2, 0x85), 0, {}, 0x285),  # this node's EMCY
        (tpdo(2, 0x205), 0, {}, 0x285),  # this node's valid RPDO1 (below)
        (tpdo(2, 0), 0, {0x285: "x"}, 0x1C5),  # then base + node id
        (tpdo(5), 0, {}, 0x1C5),
        (tpdo(6), 0, {0x1C5: "a", 0x2C5: "b"}, 0x3C5),
        (tpdo(1, 0x1F0), 4, {0x185: "node 5 twin"}, None),  # the fixed id taken: no id
    ],
)
def test_plan_picks_a_can_id(slot: PdoConfig, fixed: int, taken: Any, cob_id: int | None) -> None:
    rpdo = PdoConfig("rpdo", 1, 0x205, True, 255)
    result = plan([POS], [rpdo, slot], fixed_cob_ids=fixed, taken_ids=taken)
    assert result.placements[0].cob_id == cob_id
    if cob_id is None:
        assert result.notes == (f"TPDO{slot.number} is free but no CAN id is free for it",)


def test_plan_never_uses_a_restricted_id_and_says_which_slots_got_none() -> None:
    node = 127  # 540h + 7Fh = 5BFh lies in the SDO response range
    taken = {base + node: "other" for base in (0x1C0, 0x2C0, 0x3C0, 0x4C0, 0x240, 0x340, 0x440)}
    result = plan_node(
        node, [POS], [tpdo(5), tpdo(6)], byte_granular=True, fixed_cob_ids=0, taken_ids=taken
    )
    assert result.placements[0].source == "sdo"
    assert result.notes == ("TPDO5, TPDO6 are free but no CAN id is free for them",)


def test_plan_for_a_drive_that_takes_new_ids_only_after_a_reset() -> None:
    current = [tpdo(1, 0), tpdo(2, 0x185 + 0x100), tpdo(3, 0x601), tpdo(4, 0x1C5)]
    result = plan([POS, VEL, TRQ, info(0x2000, T.INTEGER64)], current, id_change_needs_reset=True)
    assert where(result)[:3] == [("pdo", 2, 0x285, 0), ("pdo", 2, 0x285, 32), ("pdo", 4, 0x1C5, 0)]
    assert where(result)[3][0] == "sdo"
    (note,) = result.notes
    assert note.startswith("TPDO1, TPDO3 have no usable CAN id, and this drive takes a new one")
    assert result.restore_pdos == (current[1], current[3])


SIZES: Layout = [(t, dt.int_bits(t)) for t in T if dt.is_integer(t)]
SIZES += [(T.REAL32, 32), (T.REAL64, 64), (T.BOOLEAN, 8)]  # and mapped with another length,
SIZES += [(T.REAL32, 16), (T.INTEGER16, 12), (None, 3), (None, 64)]  # or unknown to the OD
UNKNOWN = 0x5FFF  # not in the dictionary: raw unsigned
OBJECTS = {0x2000 + t: OdObject(0x2000 + t, t.name, "var", {0: sub(0x2000 + t, t)}) for t in T}
OD = ObjectDictionaryModel(DeviceInfo(), OBJECTS, (), "test", "eds")
MAPPINGS = st.lists(st.sampled_from(SIZES), min_size=1, max_size=8)
FITTING = MAPPINGS.filter(lambda layout: sum(bits for _, bits in layout) <= 64)  # one frame


def reference(layout: Layout, payload: bytes) -> list[float]:
    mapping = [MappedObject(UNKNOWN if t is None else 0x2000 + t, 0, bits) for t, bits in layout]
    return [float(v) for v in PdoDecoder(mapping, OD).values(payload)]


def batch(layout: Layout, payloads: list[bytes]) -> list[list[float]]:
    offsets = accumulate((bits for _, bits in layout), initial=0)
    decoder = BatchDecoder([FieldSpec(o, b, t) for o, (t, b) in zip(offsets, layout, strict=False)])
    assert not decoder.short(payloads).any()
    columns = decoder.decode(decoder.words(payloads))
    return [[float(c[row]) for c in columns] for row in range(len(payloads))]


def compare(layout: Layout, data: st.DataObject) -> None:
    """A batch of random payloads (8 bytes or as short as the mapping allows) both ways."""
    need = (sum(bits for _, bits in layout) + 7) // 8
    payloads = data.draw(st.lists(st.binary(min_size=need, max_size=8), min_size=1, max_size=9))
    for row, payload in zip(batch(layout, payloads), payloads, strict=True):
        np.testing.assert_array_equal(row, reference(layout, payload), payload.hex())


@pytest.mark.parametrize(("data_type", "bits"), SIZES)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_batch_decode_at_any_offset(data_type: int | None, bits: int, data: st.DataObject) -> None:
    offset = data.draw(st.integers(0, 64 - bits), label="offset")
    compare([(None, offset), (data_type, bits)] if offset else [(data_type, bits)], data)


@settings(max_examples=200, deadline=None)
@given(layout=FITTING, data=st.data())
def test_batch_decode_of_whole_mappings(layout: Layout, data: st.DataObject) -> None:
    compare(layout, data)


@pytest.mark.parametrize(
    ("layout", "payload", "values"),
    [
        ([(T.INTEGER16, 16), (T.INTEGER32, 32)], b"\xfe\xff\x18\xfc\xff\xff", [-2, -1000]),
        ([(T.BOOLEAN, 1), (T.INTEGER16, 12)], bytes([0xFF, 0x1F]), [1, -1]),
        ([(T.UNSIGNED8, 8), (T.REAL32, 32)], b"\x07" + struct.pack("<f", 1.5), [7, 1.5]),
        ([(T.BOOLEAN, 8)], b"\xff", [1]),  # a byte-mapped BOOLEAN is true, not 255
        ([(T.INTEGER64, 64)], struct.pack("<q", -(2**62)), [-(2.0**62)]),
    ],
)
def test_batch_decode_examples(layout: Layout, payload: bytes, values: list[float]) -> None:
    assert batch(layout, [payload, payload + b"\x00"]) == [values, values]


def test_short_frames_and_mixed_lengths() -> None:
    decoder = BatchDecoder([FieldSpec(0, 16, T.UNSIGNED16), FieldSpec(16, 8, T.INTEGER8)])
    payloads = [b"\x01\x02\xff", b"\x01\x02", b"\x03\x04\x05\x06\x07\x08\x09\x0a", b""]
    assert decoder.length == 3
    assert decoder.short(payloads).tolist() == [False, True, False, True]
    keep = payloads[0], payloads[2]
    assert [c.tolist() for c in decoder.decode(decoder.words(keep))] == [[0x201, 0x403], [-1, 5]]
    assert decoder.words([]).size == 0


@pytest.mark.parametrize(
    ("times", "after", "expected"),
    [
        ([1.0, 2.0, 3.0], None, [1.0, 2.0, 3.0]),
        ([1.0, 2.0], 1.0, [1.000001, 2.0]),
        ([5.0, 5.0, 5.0], None, [5.0, 5.000001, 5.000002]),
        ([1.0, 0.5, 0.6, 0.7, 2.0], None, [1.0, 1.000001, 1.000002, 1.000003, 2.0]),  # step back
        ([1.0, 1.0, 1.0000005, 3.0], None, [1.0, 1.000001, 1.000002, 3.0]),
        ([0.5, 0.6], 1.0, [1.000001, 1.000002]),
        ([], 1.0, []),
    ],
)
def test_strictly_increasing(times: list[float], after: float | None, expected: Any) -> None:
    out = strictly_increasing(arr(*times), after)
    assert out.tolist() == pytest.approx(expected, abs=1e-12)
    assert (np.diff(out) > 0).all()


@pytest.mark.parametrize(
    ("data", "data_type", "value"),
    [
        (b"\xfe\xff", T.INTEGER16, -2.0),
        (b"\xfe\xff\x00\x00", T.INTEGER16, -2.0),  # expedited upload without a size: 4 bytes
        (b"\x05\xaa\xbb\xcc", T.UNSIGNED8, 5.0),
        (b"\x01", T.BOOLEAN, 1.0),
        (b"\xff\x00\x00\x00", T.BOOLEAN, 1.0),  # true as the TPDO decode reads it
        (struct.pack("<f", -0.5), T.REAL32, -0.5),
        (struct.pack("<d", 1e300), T.REAL64, 1e300),
        (b"\xff\xff\xff\xff", None, 4294967295.0),
        (b"MDi-S1-C servo drive, firmware 2.31.7 " * 8, T.VISIBLE_STRING, math.nan),
        (b"\x00" * 300, T.DOMAIN, math.nan),
        (b"\x01\x02\x00\x00", T.DOMAIN, 513.0),  # a short domain: its bytes as a number
        (b"abc", T.VISIBLE_STRING, math.nan),
    ],
)
def test_sdo_value(data: bytes, data_type: int | None, value: float) -> None:
    np.testing.assert_array_equal(sdo_value(data, data_type), value)


def feed(trigger: Trigger, batches: Batches) -> Hit:
    """The first hit over the batches (times 0, 1, 2, … across them)."""
    start = 0
    for values in batches:
        fired = trigger.feed(arr(*range(start, start + len(values))), arr(*values))
        start += len(values)
        if fired is not None:
            return fired.time, fired.words
    return None


@pytest.mark.parametrize(
    ("trigger", "batches", "hit"),
    [
        (lv("rising"), [[0, 4, 5, 9, 2, 7]], (2.0, "pos rose to 5 (5)")),
        (lv("rising"), [[0, 1, 4.9], [], [5.1, 6]], (3.0, "pos rose to 5 (5.1)")),  # 2 batches
        (lv("rising"), [[6, 7, 8]], None),  # no predecessor: the first sample is no crossing
        (lv("rising"), [[9, 4], [3, 2]], None),
        (lv("falling"), [[9, 8], [5, 1]], (2.0, "pos fell to 5 (5)")),
        (lv("falling"), [[1, 7, 6], [3]], (3.0, "pos fell to 5 (3)")),
        (lv("either"), [[9, 7], [2, 8]], (2.0, "pos fell to 5 (2)")),
        (lv("either"), [[1, 5, 5, 9, 3]], (1.0, "pos rose to 5 (5)")),
        (bt(3, "rising"), [[8, 0], [15]], (2.0, "sw bit 3 set")),
        (bt(3, "falling"), [[8, 9], [1]], (2.0, "sw bit 3 cleared")),
        (bt(3, "either"), [[8, 8], [8, 0]], (3.0, "sw bit 3 cleared")),
        (bt(3, "rising"), [[15, 15], [8]], None),
        (bt(15, "rising"), [[0, -1]], (1.0, "sw bit 15 set")),  # signed values: two's complement
        (bt(63, "rising"), [[0, 2.0**63]], (1.0, "sw bit 63 set")),  # an UNSIGNED64 above 2^63
        (bt(62, "rising"), [[0, 2.0**64 - 2.0**11]], (1.0, "sw bit 62 set")),
        (bt(10, "rising"), [[0, 2.0**64 - 2.0**11]], None),
        (sw(None), [[DISABLED, DISABLED, READY]], (2.0, "402: Ready to switch on")),
        (sw(None), [[DISABLED], [DISABLED | 0x80, READY]], (2.0, "402: Ready to switch on")),
        (sw(S(4)), [[DISABLED, READY], [ON, ENABLED]], (3.0, "402: Operation enabled")),
        (sw(S(4)), [[ENABLED, ENABLED], [ENABLED]], None),  # 4: operation enabled
        (sw(S.FAULT), [[ENABLED], [NONE, FAULT]], (2.0, "402: Fault")),
        (sw(None), [[ENABLED], [NONE]], (1.0, "402: no CiA 402 state")),
    ],
)
def test_triggers(trigger: Trigger, batches: Batches, hit: Hit) -> None:
    assert feed(trigger, batches) == hit


def test_states_state_changes_and_state_names() -> None:
    words = arr(DISABLED, READY, READY, NONE, FAULT, 0x0000, 0x0207, 0x021F)
    assert tr.states_of(words).tolist() == [1, 2, 2, tr.NO_STATE, S.FAULT, 0, 5, 6]
    changes, last = tr.state_changes(arr(0, 1, 2, 3), arr(DISABLED, DISABLED, READY, READY), None)
    assert (changes, last) == ([(0.0, S.SWITCH_ON_DISABLED), (2.0, S.READY_TO_SWITCH_ON)], 2)
    changes, last = tr.state_changes(arr(4, 5), arr(READY, ENABLED), last)  # carries on
    assert (changes, last) == ([(5.0, S.OPERATION_ENABLED)], 4)
    assert tr.state_changes(arr(), arr(), last) == ([], last)
    for name in ("operation enabled", "OPERATION_ENABLED", " Operation-enabled "):
        assert tr.parse_state(name) is S.OPERATION_ENABLED
    with pytest.raises(ValueError, match="no CiA 402 state 'enabled': one of not ready to"):
        tr.parse_state("enabled")
