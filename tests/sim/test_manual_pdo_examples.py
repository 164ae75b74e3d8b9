"""Every PDO example sequence the three manuals print, frame for frame, against the simulated
drive it describes: MDi-S1-C CANopen manual §2.5 (procedure, §2.5.3 examples, tables 2.40/2.41),
Kinco servo CANopen manual §5.4.4–§5.4.6, Nanotec CANopen article (PDO mapping example)."""

from __future__ import annotations

import pytest

from servodesk_sim.frames import Frame, frame
from tests.sim.drive_rig import DriveRig

Exchange = tuple[str, str]  # (SDO request, the drive's answer), hex


def run(rig: DriveRig, exchanges: list[Exchange]) -> None:
    for request, answer in exchanges:
        assert (request, rig.sdo(request)) == (request, answer)


def tpdos(frames: list[Frame], can_id: int) -> list[Frame]:
    return [f for f in frames if f.can_id == can_id]


# ----------------------------------------------------------------------------- MDi-S1-C


# §2.5 steps 2–6 for TPDO3 of node 4 (§2.5.3 1): invalid = 80000384h, valid = 384h).
MDI_TPDO3_NODE4: list[Exchange] = [
    ("23 02 18 01 84 03 00 80", "60 02 18 01 00 00 00 00"),  # 2: COB-ID bit 31 = 1
    ("2F 02 1A 00 00 00 00 00", "60 02 1A 00 00 00 00 00"),  # 3: sub 0 = 0
    ("23 02 1A 01 10 00 41 60", "60 02 1A 01 00 00 00 00"),  # 4: 6041h, 10h = 16 bits
    ("23 02 1A 02 20 00 64 60", "60 02 1A 02 00 00 00 00"),  #    6064h, 20h = 32 bits
    ("2F 02 1A 00 02 00 00 00", "60 02 1A 00 00 00 00 00"),  # 5: sub 0 = 2
    ("23 02 18 01 84 03 00 00", "60 02 18 01 00 00 00 00"),  # 6: COB-ID 384h, valid
]


def test_mdi_mapping_procedure_tpdo3_of_node_4() -> None:
    rig = DriveRig(4, "mdi-s1c")
    assert rig.read(0x1802, 1) == 0xC0000384  # factory: invalid, no RTR
    run(rig, MDI_TPDO3_NODE4)
    assert tpdos(rig.nmt(0x01), 0x384) == [frame(0x384, "50 02 00 00 00 00")]  # type 255
    rig.write_ok(0x6040, 0, 0x06, 2)
    assert tpdos(rig.advance(0.002), 0x384) == [frame(0x384, "31 02 00 00 00 00")]


@pytest.mark.parametrize(
    ("invalid_first", "sent", "answer"),
    [
        # mapping and type of a valid PDO: refused (§5.2: only while the PDO is invalid)
        (False, "2F 02 1A 00 00 00 00 00", "80 02 1A 00 00 00 01 06"),
        (False, "2F 02 18 02 01 00 00 00", "80 02 18 02 00 00 01 06"),
        # §2.5.3 1): the CAN id is the node's, only bit 31 may change
        (False, "23 02 18 01 85 03 00 80", "80 02 18 01 30 00 09 06"),
        # table 2.41: lengths 08h/10h/20h only, no bit mapping
        (True, "23 02 1A 01 01 00 41 60", "80 02 1A 01 41 00 04 06"),
        # table 2.40: 241–253 are not offered
        (True, "2F 02 18 02 FC 00 00 00", "80 02 18 02 30 00 09 06"),
    ],
)
def test_mdi_refusals_around_the_procedure(invalid_first: bool, sent: str, answer: str) -> None:
    rig = DriveRig(4, "mdi-s1c")
    run(rig, MDI_TPDO3_NODE4)
    if invalid_first:
        run(rig, MDI_TPDO3_NODE4[:2])  # steps 2 and 3 again: invalid, count 0
    assert rig.sdo(sent) == answer


def test_mdi_inhibit_time_example_tpdo2() -> None:
    """§2.5.3 3): TPDO2 with inhibit time 300 is never sent less than 30 ms apart."""
    rig = DriveRig(4, "mdi-s1c")
    run(
        rig,
        [
            ("23 01 18 01 84 02 00 80", "60 01 18 01 00 00 00 00"),
            ("2F 01 1A 00 00 00 00 00", "60 01 1A 00 00 00 00 00"),
            ("23 01 1A 01 10 00 41 60", "60 01 1A 01 00 00 00 00"),
            ("2F 01 1A 00 01 00 00 00", "60 01 1A 00 00 00 00 00"),
            ("2F 01 18 02 FF 00 00 00", "60 01 18 02 00 00 00 00"),
            ("2B 01 18 03 2C 01 00 00", "60 01 18 03 00 00 00 00"),  # 300 × 100 µs
            ("23 01 18 01 84 02 00 00", "60 01 18 01 00 00 00 00"),
        ],
    )
    assert tpdos(rig.nmt(0x01), 0x284) == [frame(0x284, "50 02")]
    rig.write_ok(0x6040, 0, 0x06, 2)  # statusword changes at once
    assert tpdos(rig.advance(0.029), 0x284) == []
    assert tpdos(rig.advance(0.001), 0x284) == [frame(0x284, "31 02")]


# ----------------------------------------------------------------------------- Kinco

# §5.4.4 as printed: TPDO1 stays valid at 181h; type FEh, inhibit 100 (10 ms), then the
# entries, then the count 3. The drive's mapping count starts at 0 (§5.4.3 "当前值 00h").
KINCO_TPDO1: list[Exchange] = [
    ("23 00 18 01 81 01 00 00", "60 00 18 01 00 00 00 00"),  # 1800h:01 = 00000181h
    ("2F 00 18 02 FE 00 00 00", "60 00 18 02 00 00 00 00"),  # 1800h:02 = FEh
    ("2B 00 18 03 64 00 00 00", "60 00 18 03 00 00 00 00"),  # 1800h:03 = 100
    ("23 00 1A 01 10 00 41 60", "60 00 1A 01 00 00 00 00"),  # 60410010h Statusword
    ("23 00 1A 02 20 00 63 60", "60 00 1A 02 00 00 00 00"),  # 60630020h Position actual
    ("23 00 1A 03 20 00 FD 60", "60 00 1A 03 00 00 00 00"),  # 60FD0020h Digital inputs
    # 2 + 4 + 4 = 10 bytes: more than the 8 bytes §5.4.3 allows one PDO, so 06040042h
    ("2F 00 1A 00 03 00 00 00", "80 00 1A 00 42 00 04 06"),
]


def test_kinco_tpdo1_example() -> None:
    rig = DriveRig(1, "kinco")
    run(rig, KINCO_TPDO1)
    # What fits: statusword and position; the PDO was never invalidated
    run(rig, [("2F 00 1A 00 02 00 00 00", "60 00 1A 00 00 00 00 00")])
    assert rig.nmt(0x01) == [frame(0x181, "50 02 00 00 00 00")]
    rig.write_ok(0x6040, 0, 0x06, 2)  # §5.4.5 "轴松开"
    assert tpdos(rig.advance(0.008), 0x181) == []  # inhibit time: 10 ms after the last one
    assert tpdos(rig.advance(0.003), 0x181) == [frame(0x181, "31 02 00 00 00 00")]


# §5.4.5 as printed: the interpolation-mode PDOs, every PDO valid throughout.
KINCO_INTERPOLATION: list[Exchange] = [
    ("23 00 18 01 81 01 00 00", "60 00 18 01 00 00 00 00"),  # TPDO1 COB-ID 181h
    ("2F 00 18 02 01 00 00 00", "60 00 18 02 00 00 00 00"),  # TPDO1 synchronous
    ("23 00 14 01 01 02 00 00", "60 00 14 01 00 00 00 00"),  # RPDO1 COB-ID 201h
    ("2F 00 14 02 01 00 00 00", "60 00 14 02 00 00 00 00"),  # RPDO1 synchronous
    ("23 00 16 01 10 00 40 60", "60 00 16 01 00 00 00 00"),  # Controlword
    ("23 00 16 02 20 00 7A 60", "60 00 16 02 00 00 00 00"),  # Target position
    ("2F 00 16 00 02 00 00 00", "60 00 16 00 00 00 00 00"),  # RPDO1 count 2
    ("23 00 1A 01 10 00 41 60", "60 00 1A 01 00 00 00 00"),  # Statusword
    ("23 00 1A 02 20 00 63 60", "60 00 1A 02 00 00 00 00"),  # Position actual value
    ("2F 00 1A 00 02 00 00 00", "60 00 1A 00 00 00 00 00"),  # TPDO1 count 2
    ("2F 60 60 00 07 00 00 00", "60 60 60 00 00 00 00 00"),  # 6060h = 7 by SDO
]


def test_kinco_interpolation_example() -> None:
    rig = DriveRig(1, "kinco")
    run(rig, KINCO_INTERPOLATION)
    assert rig.nmt(0x01) == []  # synchronous PDOs only
    sent: list[Frame] = []
    # §5.4.5 commands by PDO: 6h release, Fh lock, 1Fh enable interpolation; each applies at
    # the next SYNC, and every SYNC brings TPDO1
    for controlword in ("06 00", "0F 00", "1F 00"):
        assert rig.send(0x201, controlword + " 00 00 00 00") == []
        rig.send(0x080)
        rig.advance(0.001)
        sent += rig.send(0x080)
    assert sent == [
        frame(0x181, "31 02 00 00 00 00"),  # Ready to switch on
        frame(0x181, "37 06 00 00 00 00"),  # Operation enabled, target reached
        frame(0x181, "37 16 00 00 00 00"),  # bit 12: interpolation active
    ]


# §5.4.6 as printed (after §5.4.5's 6h has released the axis): homing method 17.
KINCO_HOMING: list[Exchange] = [
    ("2B 40 60 00 0F 00 00 00", "60 40 60 00 00 00 00 00"),  # Controlword Fh
    ("2F 98 60 00 11 00 00 00", "60 98 60 00 00 00 00 00"),  # Homing method 17
    ("2F 60 60 00 06 00 00 00", "60 60 60 00 00 00 00 00"),  # Modes of operation: homing
    ("2B 40 60 00 1F 00 00 00", "60 40 60 00 00 00 00 00"),  # Controlword 1Fh: start
]


def test_kinco_homing_example() -> None:
    rig = DriveRig(1, "kinco")
    rig.write_ok(0x6040, 0, 0x06, 2)
    run(rig, KINCO_HOMING)
    for _ in range(20):  # the axis travels to N-OT and back: a few seconds
        if rig.read(0x6041) & 0x8000:
            break
        rig.advance(0.5)
    # "reference found" 8000h, homing attained (bit 12), target reached (bit 10)
    assert rig.read(0x6041) & 0x9400 == 0x9400


# ----------------------------------------------------------------------------- Nanotec

# The article's example mapping: RPDO1 = 6040h + 607Ah, TPDO1 = 6041h + 6064h, configured in
# Pre-operational ("必须在预操作 NMT 状态下配置 PDO"), each mapping switched off with sub 0 = 0.
NANOTEC_MAPPING: list[Exchange] = [
    ("2F 00 16 00 00 00 00 00", "60 00 16 00 00 00 00 00"),
    ("23 00 16 01 10 00 40 60", "60 00 16 01 00 00 00 00"),  # 60400010h
    ("23 00 16 02 20 00 7A 60", "60 00 16 02 00 00 00 00"),  # 607A0020h
    ("2F 00 16 00 02 00 00 00", "60 00 16 00 00 00 00 00"),
    ("2F 00 1A 00 00 00 00 00", "60 00 1A 00 00 00 00 00"),
    ("23 00 1A 01 10 00 41 60", "60 00 1A 01 00 00 00 00"),  # 60410010h
    ("23 00 1A 02 20 00 64 60", "60 00 1A 02 00 00 00 00"),  # 60640020h
    ("2F 00 1A 00 02 00 00 00", "60 00 1A 00 00 00 00 00"),
]


def test_nanotec_mapping_example() -> None:
    rig = DriveRig(3, "cia402")
    for request, answer in NANOTEC_MAPPING:  # node 3: 603h / 583h
        run(rig, [(request, answer)])
    assert tpdos(rig.nmt(0x01), 0x183) == [frame(0x183, "50 02 00 00 00 00")]  # on start
    # RPDO1: the first two bytes into 6040h, the next four into 607Ah
    assert rig.send(0x203, "06 00 E8 03 00 00") == []
    assert (rig.read(0x6040), rig.read(0x607A)) == (0x0006, 1000)
    assert tpdos(rig.advance(0.011), 0x183) == [frame(0x183, "31 02 00 00 00 00")]
    # In Operational the mapping is locked (article, SDO abort 08000022h)
    assert rig.sdo("2F 00 1A 00 00 00 00 00") == "80 00 1A 00 22 00 00 08"
