"""SYNC producer (1005h/1006h/1019h) and the SYNC-loss watchdog (sync.py)."""

from __future__ import annotations

import pytest
from canopen.objectdictionary import ObjectDictionary, ODVariable
from canopen.objectdictionary.datatypes import UNSIGNED8, UNSIGNED32

from servodesk_protocol.sdo_abort import DEVICE_STATE, INVALID_VALUE, VALUE_TOO_LOW
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.frames import Frame, frame
from servodesk_sim.od_store import LengthCheck, ObjectStore
from servodesk_sim.sync import SyncProducer, SyncRules, sync_counter

MDI = SyncRules(min_period_us=500, require_period_before_enable=True)
CIA402 = SyncRules(min_period_us=0, require_period_before_enable=False)


def _var(index: int, data_type: int, default: int) -> ODVariable:
    var = ODVariable(f"obj_{index:04X}", index, 0)
    var.data_type = data_type
    var.access_type = "rw"
    var.default = default
    return var


def make_store(*, counter: bool = True) -> ObjectStore:
    od = ObjectDictionary()  # type: ignore[no-untyped-call]  # canopen leaves it unannotated
    od.add_object(_var(0x1005, UNSIGNED32, 0x80))  # COB-ID SYNC (MDi-S1-C manual §5.2 factory 80h)
    od.add_object(_var(0x1006, UNSIGNED32, 0))  # Communication cycle period
    if counter:
        od.add_object(_var(0x1019, UNSIGNED8, 0))  # Synchronous counter overflow value
    return ObjectStore(od, 1, length_check=LengthCheck.GENERIC)


def abort_of(store: ObjectStore, index: int, value: int) -> int | None:
    try:
        store.write_bytes(index, 0, store.variable(index).encode_raw(value))
    except SdoAbort as abort:
        return abort.code
    return None


def run(producer: SyncProducer, times: list[float]) -> list[tuple[float, Frame]]:
    out: list[tuple[float, Frame]] = []
    for now in times:
        sync = producer.poll(now)
        if sync is not None:
            out.append((now, sync))
    return out


def test_mdi_manual_producer_procedure() -> None:
    """MDi-S1-C manual §2.6: 1005h = 80h, 1006h = period, 1005h = 40000080h."""
    store = make_store()
    producer = SyncProducer(store, MDI)
    assert abort_of(store, 0x1005, 0x80) is None
    assert abort_of(store, 0x1006, 1000) is None  # 1 ms
    assert producer.poll(0.0) is None
    assert abort_of(store, 0x1005, 0x40000080) is None
    sent = run(producer, [0.0, 0.0005, 0.00099, 0.001, 0.0015, 0.002, 0.0025])
    assert sent == [(0.001, frame(0x80)), (0.002, frame(0x80))]


@pytest.mark.parametrize(
    ("rules", "index", "value", "code"),
    [
        (MDI, 0x1005, 0x40000080, DEVICE_STATE),  # producer on while 1006h = 0
        (CIA402, 0x1005, 0x40000080, None),
        (MDI, 0x1006, 499, VALUE_TOO_LOW),  # MDi-S1-C manual §2.6 note: not below 500 µs
        (MDI, 0x1006, 1, VALUE_TOO_LOW),
        (MDI, 0x1006, 500, None),
        (MDI, 0x1006, 0, None),
        (CIA402, 0x1006, 1, None),
        (MDI, 0x1005, 0x20000080, INVALID_VALUE),  # 29-bit id
        (MDI, 0x1019, 1, INVALID_VALUE),  # reserved counter overflow values
        (MDI, 0x1019, 241, INVALID_VALUE),
        (MDI, 0x1019, 240, None),
    ],
)
def test_parameter_checks(rules: SyncRules, index: int, value: int, code: int | None) -> None:
    store = make_store()
    SyncProducer(store, rules)
    assert abort_of(store, index, value) == code


def test_counter_and_its_write_rule() -> None:
    store = make_store()
    producer = SyncProducer(store, CIA402)
    assert abort_of(store, 0x1019, 3) is None
    assert abort_of(store, 0x1006, 1000) is None
    assert abort_of(store, 0x1019, 4) == DEVICE_STATE  # CiA 301: only while 1006h = 0
    assert abort_of(store, 0x1005, 0x40000080) is None
    sent = run(producer, [n * 0.001 for n in range(7)])
    assert [f for _, f in sent] == [frame(0x80, f"{n:02X}") for n in (1, 2, 3, 1, 2, 3)]
    assert [sync_counter(f) for _, f in sent] == [1, 2, 3, 1, 2, 3]
    assert sync_counter(frame(0x80)) is None


def test_absolute_deadlines_no_drift_and_no_burst_after_a_stall() -> None:
    store = make_store()
    producer = SyncProducer(store, CIA402)
    store.set(0x1006, 0, 1000)
    store.set(0x1005, 0, 0x40000080)
    late_polls = [0.0, 0.0013, 0.0021, 0.0034, 0.0041, 0.0101, 0.0105, 0.011]
    sent = [now for now, _ in run(producer, late_polls)]
    # due at 1, 2, 3, 4 ms (seen late), then 5–10 ms missed in a stall: one SYNC, then 11 ms
    assert sent == [0.0013, 0.0021, 0.0034, 0.0041, 0.0101, 0.011]


def test_cob_id_changes_and_stopping() -> None:
    store = make_store()
    producer = SyncProducer(store, CIA402)
    assert abort_of(store, 0x1005, 0x85) is None
    assert producer.cob_id() == 0x85
    assert abort_of(store, 0x1006, 1000) is None
    assert abort_of(store, 0x1005, 0x40000085) is None
    assert abort_of(store, 0x1005, 0x40000086) == INVALID_VALUE  # not while producing
    assert run(producer, [0.0, 0.001]) == [(0.001, frame(0x85))]
    assert abort_of(store, 0x1005, 0x85) is None  # producer off, still consuming 85h
    assert run(producer, [0.002, 0.003]) == []
    assert producer.cob_id() == 0x85


def test_reset_restarts_the_schedule() -> None:
    store = make_store()
    producer = SyncProducer(store, CIA402)
    store.set(0x1006, 0, 1000)
    store.set(0x1005, 0, 0x40000080)
    assert run(producer, [0.0, 0.0009]) == []
    producer.reset()
    assert run(producer, [0.0009, 0.001, 0.0019]) == [(0.0019, frame(0x80))]
