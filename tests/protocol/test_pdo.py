"""PDO layout: mapping entries, packing, default and restricted CAN ids, transmission types."""

from __future__ import annotations

import pytest

from servodesk_protocol.pdo import (
    Direction,
    MapEntry,
    comm_index,
    default_can_id,
    frame_length,
    is_synchronous,
    map_index,
    pack,
    restricted_can_id,
    transmission_words,
)

RX = Direction.RECEIVE
TX = Direction.TRANSMIT


@pytest.mark.parametrize(
    ("raw", "entry", "byte_length"),
    [
        (0x60410010, MapEntry(0x6041, 0, 16), 2),  # Statusword
        (0x60FE0120, MapEntry(0x60FE, 1, 32), 4),  # Digital outputs: physical outputs
        (0x21000001, MapEntry(0x2100, 0, 1), 1),  # a 1-bit field still takes a byte alone
        (0x00050008, MapEntry(0x0005, 0, 8), 1),  # UNSIGNED8 dummy
    ],
)
def test_map_entry_round_trip(raw: int, entry: MapEntry, byte_length: int) -> None:
    assert MapEntry.from_raw(raw) == entry
    assert entry.raw == raw
    assert entry.byte_length == byte_length


@pytest.mark.parametrize(
    ("fields", "expected"),
    [
        # Statusword 0237h then position −2: little-endian fields in mapping order
        ([(0x60410010, "37 02"), (0x60640020, "FE FF FF FF")], "37 02 FE FF FF FF"),
        # three 1-bit switches then a byte: bits 0, 1, 2, then bits 3..10
        ([(0x21000001, "01"), (0x21010001, "00"), (0x21020001, "01"), (0x60600008, "7F")], "FD 03"),
        # a dummy transmits zeros whatever bytes it is given
        ([(0x00050008, "AA"), (0x60400010, "0F 00")], "00 0F 00"),
        # a value wider than its field is cut to the field
        ([(0x60600008, "FD FF")], "FD"),
    ],
)  # fmt: skip
def test_pack(fields: list[tuple[int, str]], expected: str) -> None:
    pairs = [(MapEntry.from_raw(raw), bytes.fromhex(value)) for raw, value in fields]
    assert pack(pairs) == bytes.fromhex(expected)
    assert frame_length([entry for entry, _ in pairs]) == len(bytes.fromhex(expected))


""" + open("/tmp/unpack_test.py").read().rstrip() + """


@pytest.mark.parametrize(
    ("direction", "number", "comm", "mapping", "can_id"),
    [
        (RX, 1, 0x1400, 0x1600, 0x200),
        (RX, 4, 0x1403, 0x1603, 0x500),
        (TX, 1, 0x1800, 0x1A00, 0x180),
        (TX, 4, 0x1803, 0x1A03, 0x480),
        (TX, 5, 0x1804, 0x1A04, None),  # PDO 5 and up have no pre-defined CAN id
    ],
)
def test_indices_and_default_ids(
    direction: Direction, number: int, comm: int, mapping: int, can_id: int | None
) -> None:
    assert comm_index(direction, number) == comm
    assert map_index(direction, number) == mapping
    assert default_can_id(direction, number) == can_id


@pytest.mark.parametrize(
    ("can_id", "restricted"),
    [
        (0x000, True),  # NMT
        (0x07F, True),
        # 080h–100h (SYNC, EMCY, TIME defaults) are not in CiA 301's restricted list
        (0x080, False),
        (0x081, False),
        (0x101, True),
        (0x180, True),
        (0x181, False),  # TPDO1
        (0x1A5, False),
        (0x581, True),  # SDO response
        (0x5FF, True),
        (0x601, True),  # SDO request
        (0x680, False),
        (0x6E0, True),
        (0x700, False),
        (0x701, True),  # heartbeat
        (0x7E5, True),  # LSS
    ],
)
def test_restricted_can_ids(can_id: int, restricted: bool) -> None:
    assert restricted_can_id(can_id) is restricted


@pytest.mark.parametrize(
    ("ttype", "direction", "synchronous", "words"),
    [
        (0, TX, True, "synchronous, acyclic (at the next SYNC after a change)"),
        (0, RX, True, "synchronous (applied at the next SYNC)"),
        (1, TX, True, "every SYNC"),
        (2, TX, True, "every 2nd SYNC"),
        (11, TX, True, "every 11th SYNC"),
        (20, TX, True, "every 20th SYNC"),
        (5, RX, True, "synchronous"),
        (241, TX, False, "reserved (241)"),
        (252, TX, True, "sampled at SYNC, sent on remote request"),
        (253, TX, False, "sent on remote request"),
        (254, TX, False, "on change + event timer (manufacturer-specific event)"),
        (255, RX, False, "applied on arrival (device-profile event)"),
    ],
)
def test_transmission_types(
    ttype: int, direction: Direction, synchronous: bool, words: str
) -> None:
    assert is_synchronous(ttype) is synchronous
    assert transmission_words(ttype, direction) == words
