"""ObjectStore: values, SDO access rules, store/restore (1010h/1011h) and the NMT resets."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import canopen
import pytest
from canopen.objectdictionary import ObjectDictionary, ODArray, ODRecord, ODVariable
from canopen.objectdictionary import datatypes as dt

from servodesk_protocol.sdo_abort import (
    CANNOT_STORE,
    DEVICE_STATE,
    GENERAL_ERROR,
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
from servodesk_sim.od_store import LengthCheck, ObjectStore, Value
from servodesk_sim.values import ValueStore

NODE = 3
SAVE = (0x65766173).to_bytes(4, "little")  # "save"
LOAD = (0x64616F6C).to_bytes(4, "little")  # "load"


def _var(
    index: int,
    sub: int,
    data_type: int,
    access: str = "rw",
    default: Value | None = None,
    *,
    low: int | None = None,
    high: int | None = None,
) -> ODVariable:
    var = ODVariable(f"obj_{index:04X}_{sub:02X}", index, sub)
    var.data_type = data_type
    var.access_type = access
    # canopen annotates `default` as int, but its EDS import stores str/bytes/float there too.
    untyped: Any = var
    untyped.default = default
    var.min = low
    var.max = high
    return var


def _container(
    container: ODArray | ODRecord, members: list[ODVariable], od: ObjectDictionary
) -> None:
    for member in members:
        container.add_member(member)
    od.add_object(container)


def make_od() -> ObjectDictionary:
    od = canopen.import_od(None)  # an empty dictionary, filled in below
    od.node_id = NODE
    od.add_object(_var(0x1000, 0, dt.UNSIGNED32, "ro", 0x00020192))  # Device type
    od.add_object(_var(0x1008, 0, dt.VISIBLE_STRING, "const", "DVS_CANOPEN"))  # Device name
    for index in (0x1010, 0x1011):  # Store parameters / Restore default parameters
        subs = [_var(index, 0, dt.UNSIGNED8, "ro", 4)]
        subs += [_var(index, sub, dt.UNSIGNED32, "rw") for sub in range(1, 5)]
        _container(ODArray(f"obj_{index:04X}", index), subs, od)
    errors = [_var(0x1003, sub, dt.UNSIGNED32, "ro") for sub in range(3)]  # no sub 0 default
    _container(ODArray("Pre-defined error field", 0x1003), errors, od)
    od.add_object(_var(0x1017, 0, dt.UNSIGNED16, "rw", 0))  # Producer heartbeat time
    cob_id = _var(0x1400, 1, dt.UNSIGNED32, "rw", 0x200 + NODE)  # RPDO1 COB-ID ($NODEID+0x200)
    cob_id.relative = True
    rpdo = [_var(0x1400, 0, dt.UNSIGNED8, "ro"), cob_id, _var(0x1400, 2, dt.UNSIGNED8, "rw", 255)]
    _container(ODRecord("RPDO1 communication parameter", 0x1400), rpdo, od)
    mapping = [_var(0x1600, sub, dt.UNSIGNED32, "rw") for sub in range(3)]  # no sub 0 default
    _container(ODRecord("RPDO1 mapping parameter", 0x1600), mapping, od)
    max_speed = _var(0x2006, 8, dt.UNSIGNED16, "rw", 6000, low=0, high=6000)  # MDi-S1-C manual P-08
    _container(
        ODRecord("obj_2006", 0x2006), [_var(0x2006, 0, dt.UNSIGNED8, "ro", 8), max_speed], od
    )
    od.add_object(_var(0x2010, 0, dt.UNSIGNED32, "wo"))  # a write-only command
    od.add_object(_var(0x2100, 0, dt.REAL32, "rw", 1.5))
    od.add_object(_var(0x2200, 0, dt.DOMAIN, "rw", b""))
    od.add_object(_var(0x2300, 0, dt.UNSIGNED16, "rw", low=10, high=20))  # no default
    od.add_object(_var(0x5FF0, 0, dt.UNSIGNED16, "rw", 0))  # SIM inject fault
    od.add_object(_var(0x6040, 0, dt.UNSIGNED16, "rw", 0))  # Controlword
    od.add_object(_var(0x6041, 0, dt.UNSIGNED16, "ro", 0x0250))  # Statusword
    od.add_object(_var(0x6060, 0, dt.INTEGER8, "rw", 0))  # Modes of operation
    od.add_object(_var(0x607A, 0, dt.INTEGER32, "rw", 0, low=-1_000_000, high=1_000_000))
    od.add_object(_var(0x60FF, 0, dt.INTEGER32, "rw", 0))  # Target velocity
    return od


def make_store(length_check: LengthCheck = LengthCheck.GENERIC) -> ObjectStore:
    return ObjectStore(make_od(), NODE, length_check=length_check)


def abort_code(store: ObjectStore, index: int, sub: int, data: bytes) -> int | None:
    try:
        store.write_bytes(index, sub, data)
    except SdoAbort as exc:
        return exc.code
    return None


# ------------------------------------------------------------------------- lookup and values


def test_store_is_a_value_store() -> None:
    store: ValueStore = make_store()
    store.set(0x6040, 0, 0x0F)
    assert store.get(0x6040) == 0x0F


@pytest.mark.parametrize(
    ("index", "sub", "code"),
    [
        (0x3000, 0, NO_OBJECT),
        (0x6040, 1, NO_SUBINDEX),  # a VAR has only sub-index 0
        (0x1400, 3, NO_SUBINDEX),  # a RECORD only has the sub-indices the OD lists
        (0x1010, 5, NO_SUBINDEX),  # nor does an ARRAY (canopen would invent 1010h:05)
    ],
)
def test_missing_entries_abort_with_object_or_subindex_code(
    index: int, sub: int, code: int
) -> None:
    store = make_store()
    assert not store.has(index, sub)
    with pytest.raises(SdoAbort) as raised:
        store.variable(index, sub)
    assert raised.value.code == code
    with pytest.raises(SdoAbort) as raised:
        store.read_bytes(index, sub)
    assert raised.value.code == code
    with pytest.raises(SdoAbort) as raised:
        store.write_bytes(index, sub, b"\0\0")
    assert raised.value.code == code


def test_internal_access_to_missing_entries_raises_key_error() -> None:
    store = make_store()
    with pytest.raises(KeyError):
        store.get(0x3000)
    with pytest.raises(KeyError):
        store.set(0x3000, 0, 1)


def test_get_refuses_a_non_integer_value() -> None:
    with pytest.raises(TypeError):
        make_store().get(0x1008)


@pytest.mark.parametrize(
    ("index", "sub", "value"),
    [
        (0x1000, 0, 0x00020192),
        (0x1008, 0, "DVS_CANOPEN"),
        (0x1010, 0, 4),
        (0x1010, 1, 1),  # 1010h:n reads 1: the device saves on command
        (0x1011, 3, 1),
        (0x1400, 0, 2),  # RECORD sub 0 without default: its highest sub-index
        (0x1003, 0, 0),  # ... except counts of entries in use: number of errors
        (0x1600, 0, 0),  # ... and number of mapped objects
        (0x1400, 1, 0x203),
        (0x2006, 8, 6000),
        (0x2100, 0, 1.5),
        (0x2200, 0, b""),
        (0x2300, 0, 10),  # no default: zero moved into the limits 10..20
        (0x6041, 0, 0x0250),
    ],
)
def test_initial_values_come_from_the_od(index: int, sub: int, value: Value) -> None:
    assert make_store().get_value(index, sub) == value


def test_signed_default_written_as_bit_pattern_reads_back_negative(tmp_path: Path) -> None:
    od = canopen.import_od(str(write_eds(tmp_path)), NODE)
    store = ObjectStore(od, NODE, length_check=LengthCheck.GENERIC)
    assert store.get(0x60C2, 2) == -3  # EDS DefaultValue=0xFD on an INTEGER8
    assert store.read_bytes(0x60C2, 2) == b"\xfd"


@pytest.mark.parametrize(
    ("index", "sub", "data"),
    [
        (0x1000, 0, bytes.fromhex("92 01 02 00")),
        (0x1008, 0, b"DVS_CANOPEN"),
        (0x1010, 2, bytes.fromhex("01 00 00 00")),
        (0x1400, 1, bytes.fromhex("03 02 00 00")),
        (0x2006, 8, bytes.fromhex("70 17")),  # MDi-S1-C manual table 2.31
        (0x2100, 0, bytes.fromhex("00 00 c0 3f")),  # REAL32 1.5
        (0x6041, 0, bytes.fromhex("50 02")),
    ],
)
def test_read_bytes_encodes_the_current_value(index: int, sub: int, data: bytes) -> None:
    assert make_store().read_bytes(index, sub) == data


def test_read_of_write_only_entry_aborts() -> None:
    with pytest.raises(SdoAbort) as raised:
        make_store().read_bytes(0x2010, 0)
    assert raised.value.code == WRITE_ONLY


def test_value_the_type_cannot_encode_reads_as_general_error() -> None:
    store = make_store()
    store.set_value(0x6040, 0, 0x1_0000)  # a drive bug: too big for UNSIGNED16
    with pytest.raises(SdoAbort) as raised:
        store.read_bytes(0x6040, 0)
    assert raised.value.code == GENERAL_ERROR


# ------------------------------------------------------------------------------- write_bytes


@pytest.mark.parametrize(
    ("index", "data", "value"),
    [
        (0x60FF, bytes.fromhex("e8 03 00 00"), 1000),
        (0x60FF, bytes.fromhex("18 fc ff ff"), -1000),
        (0x6060, bytes.fromhex("fe"), -2),
        (0x6040, bytes.fromhex("0f 00"), 0x0F),
        (0x2010, bytes.fromhex("01 00 00 00"), 1),  # write-only takes writes
        (0x2100, bytes.fromhex("00 00 20 40"), 2.5),
        (0x2200, bytes(100), bytes(100)),  # DOMAIN: any length
        (0x607A, (1_000_000).to_bytes(4, "little", signed=True), 1_000_000),  # at the limit
    ],
)
def test_write_bytes_decodes_and_stores(index: int, data: bytes, value: Value) -> None:
    store = make_store()
    store.write_bytes(index, 0, data)
    assert store.get_value(index) == value


@pytest.mark.parametrize(
    ("length_check", "index", "data", "code"),
    [
        (
            LengthCheck.GENERIC,
            0x60FF,
            bytes.fromhex("e8 03"),
            TYPE_MISMATCH,
        ),  # MDi-S1-C manual t2.18
        (LengthCheck.GENERIC, 0x6040, bytes.fromhex("0f 00 00 00"), TYPE_MISMATCH),
        (LengthCheck.SPECIFIC, 0x60FF, bytes.fromhex("e8 03"), LENGTH_TOO_LOW),  # Nanotec article
        (LengthCheck.SPECIFIC, 0x6040, bytes.fromhex("0f 00 00 00"), LENGTH_TOO_HIGH),
        (LengthCheck.SPECIFIC, 0x6060, b"", LENGTH_TOO_LOW),
        (LengthCheck.GENERIC, 0x1000, bytes(4), READ_ONLY),
        (LengthCheck.GENERIC, 0x1008, b"OTHER", READ_ONLY),  # const
        (LengthCheck.GENERIC, 0x6041, bytes(2), READ_ONLY),
        (LengthCheck.GENERIC, 0x607A, (1_000_001).to_bytes(4, "little"), VALUE_TOO_HIGH),
        (
            LengthCheck.GENERIC,
            0x607A,
            (-1_000_001).to_bytes(4, "little", signed=True),
            VALUE_TOO_LOW,
        ),
        (LengthCheck.GENERIC, 0x2006, b"\x09", READ_ONLY),  # RECORD sub 0
    ],
)
def test_write_bytes_abort_paths(
    length_check: LengthCheck, index: int, data: bytes, code: int
) -> None:
    store = make_store(length_check)
    before = store.get_value(index) if store.has(index) else None
    assert abort_code(store, index, 0, data) == code
    if before is not None:
        assert store.get_value(index) == before  # a refused write changes nothing


def test_limits_checked_on_subindex() -> None:
    store = make_store()
    assert abort_code(store, 0x2006, 8, (6001).to_bytes(2, "little")) == VALUE_TOO_HIGH
    assert store.get(0x2006, 8) == 6000


def test_validators_run_in_order_with_the_decoded_value_and_may_refuse() -> None:
    store = make_store()
    calls: list[str] = []

    def first(sub: int, value: Value) -> None:
        calls.append(f"first {sub} {value!r}")

    def refuse_negative(sub: int, value: Value) -> None:
        calls.append("second")
        if isinstance(value, int) and value < 0:
            raise SdoAbort(DEVICE_STATE)

    store.add_validator(0x60FF, first)
    store.add_validator(0x60FF, refuse_negative)
    store.add_write_hook(0x60FF, lambda _sub, _value: calls.append("hook"))
    assert abort_code(store, 0x60FF, 0, (-5).to_bytes(4, "little", signed=True)) == DEVICE_STATE
    assert calls == ["first 0 -5", "second"]
    assert store.get(0x60FF) == 0  # refused: not stored, no hook
    calls.clear()
    store.write_bytes(0x60FF, 0, (7).to_bytes(4, "little"))
    assert calls == ["first 0 7", "second", "hook"]
    assert store.get(0x60FF) == 7


def test_validators_do_not_run_for_writes_the_store_refuses() -> None:
    store = make_store()
    seen: list[Value] = []
    store.add_validator(0x607A, lambda _sub, value: seen.append(value))
    assert abort_code(store, 0x607A, 0, (2_000_000).to_bytes(4, "little")) == VALUE_TOO_HIGH
    assert seen == []


def test_hook_sees_the_stored_value() -> None:
    store = make_store()
    seen: list[tuple[int, Value, int]] = []
    store.add_write_hook(0x2006, lambda sub, value: seen.append((sub, value, store.get(0x2006, 8))))
    store.write_bytes(0x2006, 8, (3000).to_bytes(2, "little"))
    assert seen == [(8, 3000, 3000)]


def test_internal_set_bypasses_access_checks_and_hooks() -> None:
    store = make_store()
    store.add_write_hook(0x6041, lambda _sub, _value: pytest.fail("hook ran for an internal set"))
    store.add_validator(0x6041, lambda _sub, _value: pytest.fail("validator ran"))
    store.set(0x6041, 0, 0x0237)  # read-only to SDO, published by the drive
    assert store.read_bytes(0x6041, 0) == bytes.fromhex("37 02")


# ------------------------------------------------------------------------- store and restore


def test_save_all_survives_reset_node() -> None:
    store = make_store()
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    store.write_bytes(0x1017, 0, (100).to_bytes(2, "little"))
    store.write_bytes(0x2006, 8, (3000).to_bytes(2, "little"))
    store.write_bytes(0x1010, 1, SAVE)
    store.write_bytes(0x6040, 0, bytes.fromhex("0f 00"))
    store.write_bytes(0x1017, 0, (500).to_bytes(2, "little"))
    store.write_bytes(0x2006, 8, (10).to_bytes(2, "little"))
    store.reset_node()
    assert (store.get(0x6040), store.get(0x1017), store.get(0x2006, 8)) == (6, 100, 3000)


def test_unsaved_changes_are_lost_on_reset_node() -> None:
    store = make_store()
    store.write_bytes(0x6040, 0, bytes.fromhex("0f 00"))
    store.set(0x6041, 0, 0x0237)  # read-only values go back to their defaults too
    store.reset_node()
    assert (store.get(0x6040), store.get(0x6041)) == (0, 0x0250)


@pytest.mark.parametrize(
    ("sub", "saved"),
    [
        (1, {0x1017: 100, 0x2006: 3000, 0x6040: 6}),
        (2, {0x1017: 100, 0x2006: 6000, 0x6040: 0}),  # communication 1000h–1FFFh
        (3, {0x1017: 0, 0x2006: 6000, 0x6040: 6}),  # application 6000h–9FFFh
        (4, {0x1017: 0, 0x2006: 3000, 0x6040: 0}),  # manufacturer 2000h–5FFFh
    ],
)
def test_save_per_area(sub: int, saved: dict[int, int]) -> None:
    store = make_store()
    store.write_bytes(0x1017, 0, (100).to_bytes(2, "little"))
    store.write_bytes(0x2006, 8, (3000).to_bytes(2, "little"))
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    store.write_bytes(0x1010, sub, SAVE)
    store.reset_node()
    got = {0x1017: store.get(0x1017), 0x2006: store.get(0x2006, 8), 0x6040: store.get(0x6040)}
    assert got == saved


@pytest.mark.parametrize(
    ("index", "sub", "data"),
    [
        (0x1010, 1, LOAD),  # the other signature
        (0x1010, 1, bytes(4)),
        (0x1010, 2, b"SAVE"),  # case matters
        (0x1011, 1, SAVE),
        (0x1011, 3, bytes.fromhex("01 00 00 00")),
    ],
)
def test_wrong_signature_cannot_store(index: int, sub: int, data: bytes) -> None:
    store = make_store()
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    assert abort_code(store, index, sub, data) == CANNOT_STORE
    store.reset_node()
    assert store.get(0x6040) == 0  # nothing was saved
    assert store.read_bytes(index, sub) == bytes.fromhex("01 00 00 00")


def test_store_command_reads_back_one() -> None:
    store = make_store()
    store.write_bytes(0x1010, 1, SAVE)
    store.write_bytes(0x1011, 1, LOAD)
    assert store.read_bytes(0x1010, 1) == bytes.fromhex("01 00 00 00")
    assert store.read_bytes(0x1011, 1) == bytes.fromhex("01 00 00 00")


def test_store_command_with_wrong_length_is_a_length_error() -> None:
    assert abort_code(make_store(), 0x1010, 1, b"sav") == TYPE_MISMATCH


def test_restore_defaults_takes_effect_at_the_next_reset() -> None:
    store = make_store()
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    store.write_bytes(0x1010, 1, SAVE)
    store.write_bytes(0x1011, 1, LOAD)
    assert store.get(0x6040) == 6  # CiA 301: restore acts after reset
    store.reset_node()
    assert store.get(0x6040) == 0


@pytest.mark.parametrize(
    ("sub", "after"),
    [
        (1, {0x1017: 0, 0x2006: 6000, 0x6040: 0}),
        (2, {0x1017: 0, 0x2006: 3000, 0x6040: 6}),
        (3, {0x1017: 100, 0x2006: 3000, 0x6040: 0}),
        (4, {0x1017: 100, 0x2006: 6000, 0x6040: 6}),
    ],
)
def test_restore_defaults_per_area(sub: int, after: dict[int, int]) -> None:
    store = make_store()
    store.write_bytes(0x1017, 0, (100).to_bytes(2, "little"))
    store.write_bytes(0x2006, 8, (3000).to_bytes(2, "little"))
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    store.write_bytes(0x1010, 1, SAVE)
    store.write_bytes(0x1011, sub, LOAD)
    store.reset_node()
    got = {0x1017: store.get(0x1017), 0x2006: store.get(0x2006, 8), 0x6040: store.get(0x6040)}
    assert got == after


def test_simulator_only_objects_are_never_stored() -> None:
    store = make_store()
    store.write_bytes(0x5FF0, 0, (0x7380).to_bytes(2, "little"))
    store.write_bytes(0x1010, 1, SAVE)
    store.write_bytes(0x1010, 4, SAVE)
    store.reset_node()
    assert store.get(0x5FF0) == 0


def test_validator_can_refuse_a_save() -> None:
    store = make_store()

    def busy(_sub: int, _value: Value) -> None:
        raise SdoAbort(DEVICE_STATE)

    store.add_validator(0x1010, busy)
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    assert abort_code(store, 0x1010, 1, SAVE) == DEVICE_STATE
    store.reset_node()
    assert store.get(0x6040) == 0


def test_commit_stored_keeps_one_value_over_resets() -> None:
    store = make_store()
    store.set(0x2006, 8, 4500)
    store.commit_stored(0x2006, 8)
    store.set(0x2006, 8, 1)
    store.reset_node()
    assert store.get(0x2006, 8) == 4500


def test_reset_communication_touches_only_the_communication_area() -> None:
    store = make_store()
    store.write_bytes(0x1017, 0, (100).to_bytes(2, "little"))
    store.write_bytes(0x6040, 0, bytes.fromhex("06 00"))
    store.write_bytes(0x2006, 8, (3000).to_bytes(2, "little"))
    store.reset_communication(NODE)
    assert (store.get(0x1017), store.get(0x6040), store.get(0x2006, 8)) == (0, 6, 3000)


def test_reset_communication_resolves_nodeid_defaults_for_the_new_id() -> None:
    store = make_store()
    store.reset_communication(5)
    assert store.node_id == 5
    assert store.get(0x1400, 1) == 0x205
    store.reset_node()  # keeps the new id
    assert store.get(0x1400, 1) == 0x205


@pytest.mark.parametrize(
    ("saved", "after"),
    [
        (0x80000203, 0x80000209),  # node-relative CAN-ID, PDO invalid: follows the new id
        (0x00000203, 0x00000209),
        (0x80000301, 0x80000301),  # a CAN-ID the master chose stays as stored
    ],
)
def test_stored_nodeid_cob_id_after_node_id_change(saved: int, after: int) -> None:
    store = make_store()
    store.write_bytes(0x1400, 1, saved.to_bytes(4, "little"))
    store.write_bytes(0x1010, 2, SAVE)
    store.reset_communication(9)
    assert store.get(0x1400, 1) == after


EDS = """\
[FileInfo]
FileName=test.eds
EDSVersion=4.0

[DeviceInfo]
VendorName=Test

[MandatoryObjects]
SupportedObjects=2
1=0x1000
2=0x1010

[OptionalObjects]
SupportedObjects=2
1=0x1800
2=0x60C2

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
PDOMapping=0

[1010]
ParameterName=Store parameters
ObjectType=0x8
SubNumber=4

[1010sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=3
PDOMapping=0

[1010sub1]
ParameterName=Save all parameters
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=1
PDOMapping=0

[1010sub2]
ParameterName=Save communication parameters
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=1
PDOMapping=0

[1010sub3]
ParameterName=Save application parameters
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=1
PDOMapping=0

[1800]
ParameterName=TPDO1 communication parameter
ObjectType=0x9
SubNumber=2

[1800sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=1
PDOMapping=0

[1800sub1]
ParameterName=COB-ID
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x40000180
PDOMapping=0

[60C2]
ParameterName=Interpolation time period
ObjectType=0x9
SubNumber=3

[60C2sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2
PDOMapping=0

[60C2sub1]
ParameterName=Interpolation time units
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=1
PDOMapping=0

[60C2sub2]
ParameterName=Interpolation time index
ObjectType=0x7
DataType=0x0002
AccessType=rw
DefaultValue=0xFD
PDOMapping=0
"""


def write_eds(tmp_path: Path) -> Path:
    path = tmp_path / "test.eds"
    path.write_text(EDS)
    return path


@pytest.mark.parametrize(("imported_as", "node_id"), [(3, 3), (3, 12), (None, 12)])
def test_eds_nodeid_default_is_re_resolved(
    tmp_path: Path, imported_as: int | None, node_id: int
) -> None:
    od = canopen.import_od(str(write_eds(tmp_path)), imported_as)
    store = ObjectStore(od, node_id, length_check=LengthCheck.SPECIFIC)
    assert store.get(0x1800, 1) == 0x40000180 + node_id
    store.reset_communication(0x21)
    assert store.get(0x1800, 1) == 0x400001A1


def test_eds_without_manufacturer_store_subindex(tmp_path: Path) -> None:
    od = canopen.import_od(str(write_eds(tmp_path)), NODE)
    store = ObjectStore(od, NODE, length_check=LengthCheck.SPECIFIC)
    assert abort_code(store, 0x1010, 4, SAVE) == NO_SUBINDEX
    assert store.read_bytes(0x1010, 0) == b"\x03"
    assert abort_code(store, 0x1010, 3, SAVE) is None
