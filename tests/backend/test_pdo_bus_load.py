"""Bus load estimates against hand calculations a commissioning engineer can redo on paper."""

from __future__ import annotations

import pytest

from servodesk.pdo.bus_load import PdoRef, bus_load, frame_bits, frames_per_second, pdo_list
from servodesk.pdo.model import MappedObject, PdoConfig

STATUSWORD = MappedObject(0x6041, 0, 16)
POSITION = MappedObject(0x6064, 0, 32)
VELOCITY = MappedObject(0x606C, 0, 32)
EIGHT_BYTES = (POSITION, VELOCITY)
FOUR_BYTES = (POSITION,)


def tpdo(number: int, mapping: tuple[MappedObject, ...], **comm: int | bool) -> PdoConfig:
    fields: dict[str, int | bool] = {"valid": True, "transmission_type": 1} | comm
    return PdoConfig("tpdo", number, 0x180 + number, mapping=mapping, **fields)  # type: ignore[arg-type]


def rpdo(number: int, mapping: tuple[MappedObject, ...], **comm: int | bool) -> PdoConfig:
    fields: dict[str, int | bool] = {"valid": True, "transmission_type": 255} | comm
    return PdoConfig("rpdo", number, 0x200 + number, mapping=mapping, **fields)  # type: ignore[arg-type]


# 8n + 47 + floor((34 + 8n - 1) / 4)
@pytest.mark.parametrize(
    ("data_bytes", "bits"),
    [
        (0, 0 + 47 + 33 // 4),  # SYNC: 55
        (1, 8 + 47 + 41 // 4),  # 65
        (2, 16 + 47 + 49 // 4),  # 75
        (4, 32 + 47 + 65 // 4),  # 95
        (6, 48 + 47 + 81 // 4),  # 115
        (8, 64 + 47 + 97 // 4),  # 135
    ],
)
def test_worst_case_frame_length(data_bytes: int, bits: int) -> None:
    assert frame_bits(data_bytes) == bits


def test_a_frame_carries_at_most_eight_bytes() -> None:
    with pytest.raises(ValueError, match="0–8 data bytes, not 9"):
        frame_bits(9)


@pytest.mark.parametrize(
    ("pdo", "sync_period_us", "rate"),
    [
        (tpdo(1, EIGHT_BYTES, transmission_type=1), 1000, 1000.0),
        (tpdo(1, EIGHT_BYTES, transmission_type=2), 1000, 500.0),
        (tpdo(1, EIGHT_BYTES, transmission_type=0), 2000, 500.0),  # acyclic: worst case
        (tpdo(1, EIGHT_BYTES, transmission_type=10), None, 0.0),  # no SYNC, never sent
        (tpdo(1, EIGHT_BYTES, transmission_type=255, inhibit_time_100us=100), None, 100.0),
        (tpdo(1, EIGHT_BYTES, transmission_type=254, event_timer_ms=250), None, 4.0),
        # inhibit time bounds the rate even when an event timer is set
        (
            tpdo(1, EIGHT_BYTES, transmission_type=255, inhibit_time_100us=50, event_timer_ms=100),
            1000,
            200.0,
        ),
        (tpdo(1, EIGHT_BYTES, transmission_type=255), 1000, None),
        (tpdo(1, EIGHT_BYTES, transmission_type=252), 1000, 0.0),  # on request only
        (rpdo(1, EIGHT_BYTES), 1000, 1000.0),  # the master: once per SYNC
        (rpdo(1, EIGHT_BYTES), None, 100.0),  # the master: every 10 ms (assumed cycle)
        (rpdo(1, EIGHT_BYTES, transmission_type=1), 1000, 1000.0),
        (tpdo(1, EIGHT_BYTES, valid=False), 1000, 0.0),
    ],
)
def test_frames_per_second(pdo: PdoConfig, sync_period_us: int | None, rate: float | None) -> None:
    assert frames_per_second(pdo, sync_period_us=sync_period_us) == rate


def test_two_drives_at_1_ms_sync_on_500_kbit() -> None:
    # by hand, 500 kbit/s and SYNC every 1 ms:
    #   SYNC, 0 bytes:            55 bits x 1000/s =  55 000 bit/s
    #   node 1 TPDO1, 8 bytes:   135 bits x 1000/s = 135 000 bit/s
    #   node 1 TPDO2, 8 bytes:   135 bits x 1000/s = 135 000 bit/s
    #   node 1 TPDO3: invalid, not counted
    #   total                                        325 000 bit/s = 65.0 %  (under 70 %)
    node1 = [tpdo(1, EIGHT_BYTES), tpdo(2, EIGHT_BYTES), tpdo(3, EIGHT_BYTES, valid=False)]
    load = bus_load({1: node1}, bitrate=500_000, sync_period_us=1000)
    assert load.sync_bits_per_s == 55_000
    assert [(p.number, p.bits_per_frame, p.bits_per_s) for p in load.nodes[0].pdos] == [
        (1, 135, 135_000),
        (2, 135, 135_000),
    ]
    assert load.nodes[0].pdos[0].basis == "every SYNC at 1 ms"
    assert load.total_bits_per_s == 325_000
    assert load.percent == pytest.approx(65.0)
    assert not load.over_threshold
    assert load.notes == []

    #   + node 2 TPDO1, 4 bytes every 2nd SYNC: 95 bits x 500/s = 47 500 bit/s
    #   total                                        372 500 bit/s = 74.5 %  (over 70 %)
    node2 = [tpdo(1, FOUR_BYTES, transmission_type=2)]
    load = bus_load({1: node1, 2: node2}, bitrate=500_000, sync_period_us=1000)
    assert [(n.node, n.bits_per_s) for n in load.nodes] == [(1, 270_000), (2, 47_500)]
    assert load.nodes[1].pdos[0].basis == "every 2nd SYNC at 1 ms"
    assert load.nodes[1].percent == pytest.approx(9.5)
    assert load.total_bits_per_s == 372_500
    assert load.percent == pytest.approx(74.5)
    assert load.over_threshold
    assert load.notes == [
        "the bus would be 74.5 % loaded (over 70 %): lengthen the SYNC period or inhibit times,"
        " or map fewer objects"
    ]


def test_event_driven_pdos_at_250_kbit() -> None:
    # statusword + position (6 bytes, 115 bits) at most every 10 ms: 11 500 bit/s = 4.6 %
    # statusword alone (2 bytes, 75 bits) by a 100 ms event timer: 750 bit/s = 0.3 %
    # the master's RPDO1 (2 bytes, 75 bits) every 10 ms (assumed cycle): 7 500 bit/s = 3.0 %
    # no SYNC; the TPDO without inhibit time is unbounded and named
    pdos = [
        tpdo(1, (STATUSWORD, POSITION), transmission_type=255, inhibit_time_100us=100),
        tpdo(2, (STATUSWORD,), transmission_type=254, event_timer_ms=100),
        tpdo(3, (VELOCITY,), transmission_type=255),
        rpdo(1, (STATUSWORD,)),
    ]
    load = bus_load({4: pdos}, bitrate=250_000, sync_period_us=None)
    assert [(p.frames_per_s, p.bits_per_s, p.basis) for p in load.nodes[0].pdos] == [
        (100.0, 11_500, "at most every 10.0 ms (inhibit time)"),
        (10.0, 750, "event timer 100 ms"),
        (None, 0, "unbounded: event-driven without inhibit time"),
        (100.0, 7_500, "sent by the master every 10 ms (assumed master cycle)"),
    ]
    assert load.sync_bits_per_s == 0
    assert load.percent == pytest.approx(7.9)
    assert load.notes == [
        "node 4 TPDO3: not counted: unbounded: event-driven without inhibit time",
        "node 4 RPDO1: counted at the assumed 10 ms master cycle",
    ]


def test_event_driven_rpdos_of_three_nodes_at_the_master_cycle() -> None:
    # 500 kbit/s, no SYNC, a 20 ms master cycle; every RPDO event-driven (255), sent by the
    # master every 20 ms = 50 frames/s:
    #   node 1 RPDO1–3, 8 bytes:  3 x 135 bits x 50/s = 20 250 bit/s
    #   node 3 RPDO1–4, 4 bytes:  4 x  95 bits x 50/s = 19 000 bit/s
    #   node 3 TPDO1, 2 bytes, event timer 100 ms:  75 bits x 10/s = 750 bit/s
    #   total                                        40 000 bit/s = 8.0 %
    node1 = [rpdo(n, EIGHT_BYTES) for n in (1, 2, 3)]
    node3 = [*(rpdo(n, FOUR_BYTES) for n in (1, 2, 3, 4))]
    node3.append(tpdo(1, (STATUSWORD,), transmission_type=255, event_timer_ms=100))
    load = bus_load({1: node1, 3: node3}, bitrate=500_000, sync_period_us=None, master_period_ms=20)
    assert [(n.node, n.bits_per_s) for n in load.nodes] == [(1, 20_250), (3, 19_750)]
    assert load.nodes[0].pdos[0].basis == "sent by the master every 20 ms (assumed master cycle)"
    assert load.total_bits_per_s == 40_000
    assert load.percent == pytest.approx(8.0)
    assert load.master_period_ms == 20
    # one line for the assumption, naming every PDO it concerns
    assert load.notes == [
        "node 1 RPDO1–3, node 3 RPDO1–4: counted at the assumed 20 ms master cycle"
    ]

    # with SYNC every 2 ms the master is assumed to send them once per SYNC (500/s):
    #   SYNC 55 x 500 = 27 500; node 1: 3 x 135 x 500 = 202 500; node 3: 4 x 95 x 500 = 190 000
    #   + 750 = 420 750 bit/s = 84.15 %
    load = bus_load({1: node1, 3: node3}, bitrate=500_000, sync_period_us=2000, master_period_ms=20)
    assert load.nodes[1].pdos[0].basis == "sent by the master every 2 ms (assumed: once per SYNC)"
    assert load.total_bits_per_s == 420_750
    assert load.notes[0] == (
        "node 1 RPDO1–3, node 3 RPDO1–4: counted once per SYNC (2 ms), as the master is assumed"
        " to send them"
    )
    assert load.over_threshold


def test_pdo_lists_join_runs_per_node() -> None:
    refs: list[PdoRef] = [
        (3, "tpdo", 2),
        (1, "rpdo", 1),
        (1, "rpdo", 2),
        (1, "rpdo", 4),
        (1, "tpdo", 5),
    ]
    assert pdo_list(refs) == "node 1 RPDO1–2, RPDO4 and TPDO5, node 3 TPDO2"


def test_synchronous_pdos_without_a_sync_period_are_named() -> None:
    load = bus_load({2: [tpdo(1, EIGHT_BYTES)]}, bitrate=1_000_000, sync_period_us=0)
    assert load.total_bits_per_s == 0
    assert load.notes == ["node 2 TPDO1: not counted: synchronous, but no SYNC period is set"]


def test_sub_millisecond_sync_and_threshold() -> None:
    # SYNC every 500 µs: 55 x 2000 = 110 000 bit/s = 11 % of 1 Mbit/s, over a 10 % threshold
    load = bus_load({}, bitrate=1_000_000, sync_period_us=500, threshold_percent=10)
    assert (load.sync_bits_per_s, load.over_threshold) == (110_000, True)


def test_bitrate_and_master_period_must_be_positive() -> None:
    with pytest.raises(ValueError, match="bitrate must be positive"):
        bus_load({}, bitrate=0, sync_period_us=1000)
    with pytest.raises(ValueError, match="master period must be positive"):
        bus_load({}, bitrate=500_000, sync_period_us=None, master_period_ms=0)
