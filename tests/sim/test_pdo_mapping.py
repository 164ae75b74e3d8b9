"""Mapping entries, store values packed, COB-ID / transmission-type checks (pdo_mapping.py)."""

from __future__ import annotations

import pytest

from servodesk_protocol.pdo import Direction, MapEntry, pack
from servodesk_protocol.sdo_abort import (
    INVALID_VALUE,
    NO_OBJECT,
    NO_SUBINDEX,
    NOT_MAPPABLE,
    PARAMETER_INCOMPATIBLE,
    PDO_LENGTH_EXCEEDED,
    VALUE_TOO_HIGH,
)
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.pdo_mapping import (
    check_cob_id,
    check_count,
    check_entry,
    check_transmission_type,
    read_fields,
)
from tests.sim.pdo_od import make_store

RX = Direction.RECEIVE
TX = Direction.TRANSMIT


@pytest.mark.parametrize(
    ("raw", "direction", "byte_granular", "code"),
    [
        (0x60400010, RX, True, None),  # Controlword into an RPDO
        (0x60410010, TX, True, None),  # Statusword from a TPDO
        (0x60FE0120, RX, True, None),  # record member
        (0x20100008, RX, False, NO_OBJECT),  # no such object
        (0x60FE0220, RX, False, NO_SUBINDEX),  # no such sub-index
        (0x20000008, RX, False, NOT_MAPPABLE),  # exists, not mappable
        (0x60410010, RX, False, NOT_MAPPABLE),  # RPDO target read-only
        (0x22000010, TX, False, NOT_MAPPABLE),  # TPDO source write-only
        (0x22000010, RX, False, None),  # ... but a fine RPDO target
        (0x60400008, RX, False, PARAMETER_INCOMPATIBLE),  # 8 bits of a 16-bit object
        (0x60400020, RX, False, PARAMETER_INCOMPATIBLE),  # 32 bits of a 16-bit object
        (0x21000001, RX, False, None),  # BOOLEAN as one bit
        (0x21000008, RX, False, None),  # BOOLEAN as one byte (python-canopen maps it so)
        (0x21000001, RX, True, NOT_MAPPABLE),  # MDi: whole bytes only (MDi-S1-C manual §5.2)
        (0x21000008, RX, True, None),
        (0x21000002, RX, False, PARAMETER_INCOMPATIBLE),
    ],
)
def test_entry_checks(
    raw: int, direction: Direction, byte_granular: bool, code: int | None
) -> None:
    store = make_store()
    entry = MapEntry.from_raw(raw)
    if code is None:
        check_entry(store, entry, direction, byte_granular=byte_granular)
    else:
        with pytest.raises(SdoAbort) as caught:
            check_entry(store, entry, direction, byte_granular=byte_granular)
        assert caught.value.code == code


@pytest.mark.parametrize(
    ("dummies", "raw", "code"),
    [
        (True, 0x00050008, None),  # Dummy0005 declared: an 8-bit gap
        (True, 0x00050010, PARAMETER_INCOMPATIBLE),  # wrong size for UNSIGNED8
        (False, 0x00050008, NO_OBJECT),  # not declared in the OD
    ],
)
def test_dummy_entries(dummies: bool, raw: int, code: int | None) -> None:
    store = make_store(dummies=dummies)
    entry = MapEntry.from_raw(raw)
    if code is None:
        check_entry(store, entry, RX, byte_granular=True)
    else:
        with pytest.raises(SdoAbort) as caught:
            check_entry(store, entry, RX, byte_granular=True)
        assert caught.value.code == code


@pytest.mark.parametrize(
    ("raws", "count", "code"),
    [
        # Kinco manual §5.4.4: 6041h (16) + 6063h (32) + 60FDh (32) = 80 bits > 64
        ([0x60410010, 0x60630020, 0x60FD0020], 3, PDO_LENGTH_EXCEEDED),
        ([0x60410010, 0x60630020, 0x60FD0020], 2, None),  # the first two: 48 bits
        ([0x60630020, 0x60FD0020], 2, None),  # exactly 64 bits
        ([0x60410010] * 8, 9, VALUE_TOO_HIGH),  # more than 8 entries
        ([0x60410010, 0x20000008], 2, NOT_MAPPABLE),  # a bad entry is caught at sub 0 too
        ([], 0, None),  # disabling the mapping
    ],
)
def test_count_checks(raws: list[int], count: int, code: int | None) -> None:
    store = make_store()
    for sub, raw in enumerate(raws, start=1):
        store.set(0x1A00, sub, raw)
    if code is None:
        check_count(store, 0x1A00, count, TX, byte_granular=True)
    else:
        with pytest.raises(SdoAbort) as caught:
            check_count(store, 0x1A00, count, TX, byte_granular=True)
        assert caught.value.code == code


@pytest.mark.parametrize(
    ("values", "raws", "expected"),
    [
        # Statusword 0237h then position −2: little-endian fields in mapping order
        ({0x6041: 0x0237, 0x6064: -2}, [0x60410010, 0x60640020], "37 02 FE FF FF FF"),
        ({0x6060: -3, 0x6041: 0x1234}, [0x60600008, 0x60410010], "FD 34 12"),
        # three 1-bit switches then a byte: bits 0, 1, 2, then bits 3..10
        (
            {0x2100: 1, 0x2101: 0, 0x2102: 1, 0x6060: 0x7F},
            [0x21000001, 0x21010001, 0x21020001, 0x60600008],
            "FD 03",
        ),
    ],
)
def test_pack_store_values(values: dict[int, int], raws: list[int], expected: str) -> None:
    store = make_store()
    for index, value in values.items():
        store.set(index, 0, value)
    entries = tuple(MapEntry.from_raw(raw) for raw in raws)
    assert pack(read_fields(store, entries)) == bytes.fromhex(expected)


@pytest.mark.parametrize(
    ("value", "current", "fixed_id", "code"),
    [
        (0x80000181, 0x40000181, 0x181, None),  # fixed: invalidate
        (0x40000181, 0xC0000181, 0x181, None),  # fixed: validate, bit 30 kept
        (0x00000181, 0x40000181, 0x181, None),  # fixed: bit 30 may change
        (0x80000185, 0x40000181, 0x181, INVALID_VALUE),  # fixed: CAN id cannot move
        (0xA0000181, 0x40000181, 0x181, INVALID_VALUE),  # 29-bit frame
        (0x800001A5, 0xC0000000, None, None),  # free: new id while invalid
        (0x000001A5, 0x800001A5, None, None),  # free: validate it
        (0x000001A6, 0x000001A5, None, INVALID_VALUE),  # free: id of a valid PDO fixed
        (0x000001A5, 0x000001A5, None, None),  # rewriting the same value is fine
        (0x00000605, 0x80000605, None, INVALID_VALUE),  # SDO range is reserved
        (0x00000705, 0x80000705, None, INVALID_VALUE),  # heartbeat range is reserved
        (0x00000085, 0x80000085, None, None),  # 81h–FFh may carry PDOs (CiA 301 §7.3.5)
    ],
)
def test_cob_id_checks(value: int, current: int, fixed_id: int | None, code: int | None) -> None:
    if code is None:
        check_cob_id(value, current, fixed_id=fixed_id)
    else:
        with pytest.raises(SdoAbort) as caught:
            check_cob_id(value, current, fixed_id=fixed_id)
        assert caught.value.code == code


@pytest.mark.parametrize(
    ("value", "direction", "rtr", "ok"),
    [
        (0, RX, False, True),
        (240, TX, False, True),
        (241, TX, True, False),
        (252, TX, False, False),  # MDi: no RTR transmission
        (252, TX, True, True),
        (253, TX, True, True),
        (253, RX, True, False),  # RTR types are TPDO-only
        (254, RX, False, True),
        (255, TX, False, True),
    ],
)
def test_transmission_types(value: int, direction: Direction, rtr: bool, ok: bool) -> None:
    if ok:
        check_transmission_type(value, direction, rtr=rtr)
    else:
        with pytest.raises(SdoAbort) as caught:
            check_transmission_type(value, direction, rtr=rtr)
        assert caught.value.code == INVALID_VALUE
