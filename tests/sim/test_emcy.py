"""EMCY frames per drive family and the fault objects 603Fh, 1001h, 1003h, 2600h:02 (emcy.py)."""

from __future__ import annotations

import pytest
from canopen.objectdictionary import ObjectDictionary, ODArray, ODRecord, ODVariable
from canopen.objectdictionary.datatypes import UNSIGNED8, UNSIGNED16, UNSIGNED32

from servodesk_protocol.emcy import EmcyFormat
from servodesk_protocol.sdo_abort import READ_ONLY, VALUE_TOO_HIGH
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.emcy import Fault, FaultManager, emcy_payload
from servodesk_sim.frames import frame
from servodesk_sim.od_store import LengthCheck, ObjectStore

NODE_ID = 1
# MDi alarm 1 "超速" (MDi-S1-C manual §4.1), classed as velocity controller 8400h
MDI_OVERSPEED = Fault(code=1, emcy_code=0x8400, error_register=0x20)
# Kinco: following error 8611h is 2600h:02 bit 2000h; motor encoder counting 0x00017305 is 8h
KINCO_FOLLOWING = Fault(code=0x8611, emcy_code=0x8611, error_register=0x20, kinco_bits=0x2000)
KINCO_ENCODER = Fault(code=0x17305, emcy_code=0x7305, error_register=0x20, kinco_bits=0x8)
FOLLOWING = Fault(code=0x8611, emcy_code=0x8611, error_register=0x20)
OVERVOLTAGE = Fault(code=0x3210, emcy_code=0x3210, error_register=0x04)


def _var(index: int, sub: int, data_type: int, access: str, default: int) -> ODVariable:
    var = ODVariable(f"obj_{index:04X}_{sub}", index, sub)
    var.data_type = data_type
    var.access_type = access
    var.default = default
    return var


def make_store(*, emcy_cob: bool = True, history: int = 4) -> ObjectStore:
    od = ObjectDictionary()  # type: ignore[no-untyped-call]  # canopen leaves it unannotated
    od.add_object(_var(0x1001, 0, UNSIGNED8, "ro", 0))  # Error register
    errors = ODArray("Pre-defined error field", 0x1003)
    errors.add_member(_var(0x1003, 0, UNSIGNED8, "rw", 0))
    for sub in range(1, history + 1):
        errors.add_member(_var(0x1003, sub, UNSIGNED32, "ro", 0))
    od.add_object(errors)
    if emcy_cob:
        od.add_object(_var(0x1014, 0, UNSIGNED32, "rw", 0x80 + NODE_ID))  # COB-ID EMCY
    od.add_object(_var(0x603F, 0, UNSIGNED16, "ro", 0))  # Error code
    kinco = ODRecord("Kinco faults", 0x2600)
    kinco.add_member(_var(0x2600, 0, UNSIGNED8, "ro", 2))
    kinco.add_member(_var(0x2600, 1, UNSIGNED32, "ro", 0))
    kinco.add_member(_var(0x2600, 2, UNSIGNED32, "ro", 0))  # Detected_Faults
    od.add_object(kinco)
    return ObjectStore(od, NODE_ID, length_check=LengthCheck.GENERIC)


def history(store: ObjectStore) -> list[int]:
    return [store.get(0x1003, sub) for sub in range(1, store.get(0x1003, 0) + 1)]


@pytest.mark.parametrize(
    ("fmt", "fault", "raised", "reset"),
    [
        # MDi-S1-C manual §2.7: 2 bytes, alarm number low byte first; reset = alarm 0
        (EmcyFormat.ALARM_NUMBER, MDI_OVERSPEED, "01 00", "00 00"),
        # Kinco manual §5.6/§8: low 2 bytes of the 603Fh code, 6 unused bytes
        (EmcyFormat.KINCO, KINCO_ENCODER, "05 73 00 00 00 00 00 00", "00 00 00 00 00 00 00 00"),
        # Nanotec article: code, 1001h (20h + generic bit), 5 manufacturer bytes; reset all zero
        (EmcyFormat.CIA301, FOLLOWING, "11 86 21 00 00 00 00 00", "00 00 00 00 00 00 00 00"),
    ],
)
def test_emcy_frames_per_format(fmt: EmcyFormat, fault: Fault, raised: str, reset: str) -> None:
    store = make_store()
    manager = FaultManager(store, fmt, history=False, kinco_fault_bits=False)
    assert manager.raise_fault(fault, 0.0, may_send=True) == [frame(0x81, raised)]
    assert store.get(0x603F) == fault.code & 0xFFFF
    assert store.get(0x1001) == fault.error_register | 0x01
    assert manager.active == fault
    assert manager.clear(0.1, may_send=True) == [frame(0x81, reset)]
    assert (store.get(0x603F), store.get(0x1001)) == (0, 0)
    assert manager.active is None


def test_payload_builder_without_fault_objects() -> None:
    assert emcy_payload(EmcyFormat.CIA301, OVERVOLTAGE, 0x05) == bytes.fromhex("10 32 05") + bytes(
        5
    )
    assert emcy_payload(EmcyFormat.ALARM_NUMBER, Fault(62, 0x8700, 0x10), 0x11) == b"\x3e\x00"


def test_persisting_fault_sends_one_emcy() -> None:
    """Kinco manual §5.6: a persisting fault generates one EMCY, again only after a reset."""
    store = make_store()
    manager = FaultManager(store, EmcyFormat.CIA301, history=True, kinco_fault_bits=False)
    assert len(manager.raise_fault(FOLLOWING, 0.0, may_send=True)) == 1
    assert manager.raise_fault(FOLLOWING, 0.001, may_send=True) == []
    assert history(store) == [0x00218611]  # recorded once
    manager.clear(0.002, may_send=True)
    assert manager.raise_fault(FOLLOWING, 0.003, may_send=True) == [
        frame(0x81, "11 86 21 00 00 00 00 00")
    ]


def test_emcy_switched_off_or_not_allowed() -> None:
    store = make_store()
    manager = FaultManager(store, EmcyFormat.CIA301, history=False, kinco_fault_bits=False)
    assert manager.raise_fault(FOLLOWING, 0.0, may_send=False) == []  # e.g. NMT Stopped
    assert store.get(0x603F) == 0x8611  # the fault is still recorded
    manager.clear(0.0, may_send=False)
    store.write_bytes(0x1014, 0, (0x80000081).to_bytes(4, "little"))  # bit 31: EMCY off
    assert manager.raise_fault(FOLLOWING, 0.1, may_send=True) == []
    assert manager.clear(0.2, may_send=True) == []
    store.write_bytes(0x1014, 0, (0x85).to_bytes(4, "little"))  # another COB-ID
    assert manager.raise_fault(FOLLOWING, 0.3, may_send=True) == [
        frame(0x85, "11 86 21 00 00 00 00 00")
    ]


def test_emcy_cob_id_defaults_to_80h_plus_node_id() -> None:
    store = make_store(emcy_cob=False)
    manager = FaultManager(store, EmcyFormat.ALARM_NUMBER, history=False, kinco_fault_bits=False)
    assert manager.raise_fault(MDI_OVERSPEED, 0.0, may_send=True) == [frame(0x81, "01 00")]


def test_clear_without_fault_sends_nothing() -> None:
    manager = FaultManager(make_store(), EmcyFormat.KINCO, history=False, kinco_fault_bits=True)
    assert manager.clear(0.0, may_send=True) == []


def test_kinco_fault_bits() -> None:
    """Kinco manual §8: 2600h:02 shows one bit per active fault; 603Fh the latest code."""
    store = make_store()
    manager = FaultManager(store, EmcyFormat.KINCO, history=False, kinco_fault_bits=True)
    manager.raise_fault(KINCO_FOLLOWING, 0.0, may_send=True)
    assert manager.raise_fault(KINCO_ENCODER, 0.1, may_send=True) == [
        frame(0x81, "05 73 00 00 00 00 00 00")
    ]
    assert store.get(0x2600, 2) == 0x2008
    assert store.get(0x603F) == 0x7305  # UNSIGNED16 here: the low 16 bits of 00017305h
    assert manager.active == KINCO_ENCODER
    manager.clear(0.2, may_send=True)
    assert store.get(0x2600, 2) == 0


def test_kinco_bits_untouched_for_other_profiles() -> None:
    store = make_store()
    manager = FaultManager(store, EmcyFormat.CIA301, history=False, kinco_fault_bits=False)
    manager.raise_fault(KINCO_FOLLOWING, 0.0, may_send=True)
    assert store.get(0x2600, 2) == 0


def test_history_newest_first_and_kept_by_reset() -> None:
    store = make_store()
    manager = FaultManager(store, EmcyFormat.CIA301, history=True, kinco_fault_bits=False)
    manager.raise_fault(FOLLOWING, 0.0, may_send=True)
    assert manager.raise_fault(OVERVOLTAGE, 0.1, may_send=True) == [
        frame(0x81, "10 32 25 00 00 00 00 00")  # 1001h now holds both faults' bits
    ]
    assert store.get(0x1001) == 0x25
    assert history(store) == [0x00253210, 0x00218611]
    manager.clear(0.2, may_send=True)
    assert history(store) == [0x00253210, 0x00218611]


def test_history_drops_the_oldest_when_full() -> None:
    store = make_store(history=4)
    manager = FaultManager(store, EmcyFormat.CIA301, history=True, kinco_fault_bits=False)
    for code in (0x2310, 0x3210, 0x4210, 0x5530, 0x8611):
        manager.raise_fault(Fault(code, code, 0x00), 0.0, may_send=True)
        manager.clear(0.0, may_send=True)
    assert [entry & 0xFFFF for entry in history(store)] == [0x8611, 0x5530, 0x4210, 0x3210]


@pytest.mark.parametrize(
    ("sub", "value", "code"),
    [
        (0, 0, None),  # clears the history
        (0, 1, VALUE_TOO_HIGH),  # Nanotec article abort table: only 0 may be written
        (0, 2, VALUE_TOO_HIGH),
        (1, 0, READ_ONLY),
    ],
)
def test_history_writes(sub: int, value: int, code: int | None) -> None:
    store = make_store()
    manager = FaultManager(store, EmcyFormat.CIA301, history=True, kinco_fault_bits=False)
    manager.raise_fault(FOLLOWING, 0.0, may_send=True)
    data = value.to_bytes(1 if sub == 0 else 4, "little")
    if code is None:
        store.write_bytes(0x1003, sub, data)
        assert store.get(0x1003, 0) == 0
        assert store.get(0x1003, 1) == 0
    else:
        with pytest.raises(SdoAbort) as caught:
            store.write_bytes(0x1003, sub, data)
        assert caught.value.code == code
        assert history(store) == [0x00218611]
