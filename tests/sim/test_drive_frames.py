"""Whole simulated drives, frame for frame: the manuals' examples and the behaviour that needs
several services together (NMT + SDO + store + reset, faults + EMCY, error control, SYNC)."""

from __future__ import annotations

import pytest

from servodesk_data import PROFILE_NAMES
from servodesk_sim.frames import Frame, frame
from tests.sim.drive_rig import LOAD, SAVE, DriveRig


def hexes(frames: list[Frame]) -> list[str]:
    return [str(f) for f in frames]


# ---------------------------------------------------------------- the manuals' example frames


def test_mdi_manual_sdo_examples() -> None:
    rig = DriveRig(4, "mdi-s1c")
    # table 2.16 / 2.17: write 60FFh = 1000
    assert rig.send(0x604, "23 FF 60 00 E8 03 00 00") == [frame(0x584, "60 FF 60 00 00 00 00 00")]
    # table 2.18: data type mismatch (2 bytes into INTEGER32)
    assert rig.send(0x604, "2B FF 60 00 E8 03 00 00") == [frame(0x584, "80 FF 60 00 10 00 07 06")]
    # tables 2.30 / 2.31: max speed 2006h:08 = 6000 rpm
    assert rig.send(0x604, "40 06 20 08 00 00 00 00") == [frame(0x584, "4B 06 20 08 70 17 00 00")]
    # table 2.32: an unknown command specifier
    assert rig.send(0x604, "E0 06 20 08 00 00 00 00") == [frame(0x584, "80 06 20 08 01 00 04 05")]


def test_mdi_segmented_upload_of_the_device_name() -> None:
    rig = DriveRig(4, "mdi-s1c")
    assert rig.send(0x604, "40 08 10 00 00 00 00 00") == [frame(0x584, "41 08 10 00 0B 00 00 00")]
    assert rig.send(0x604, "60 00 00 00 00 00 00 00") == [frame(0x584, "00 44 56 53 5F 43 41 4E")]
    assert rig.send(0x604, "70 00 00 00 00 00 00 00") == [frame(0x584, "17 4F 50 45 4E 00 00 00")]
    # the same toggle twice is refused (MDi-S1-C manual table 2.34: the toggle must alternate)
    rig.send(0x604, "40 08 10 00 00 00 00 00")
    rig.send(0x604, "60 00 00 00 00 00 00 00")
    assert rig.send(0x604, "60 00 00 00 00 00 00 00") == [frame(0x584, "80 08 10 00 00 00 03 05")]


def test_kinco_manual_statusword_read() -> None:
    rig = DriveRig(1, "kinco")
    (answer,) = rig.send(0x601, "40 41 60 00 00 00 00 00")
    assert answer.can_id == 0x581
    assert answer.data[:4] == bytes.fromhex("4B 41 60 00")
    assert answer.data[6:] == b"\x00\x00"


def test_kinco_manual_controlword_write() -> None:
    rig = DriveRig(1, "kinco")
    assert rig.send(0x601, "2B 40 60 00 06 00 00 00") == [frame(0x581, "60 40 60 00 00 00 00 00")]


def test_nanotec_article_examples() -> None:
    rig = DriveRig(3, "cia402")
    assert rig.send(0x603, "23 7A 60 00 E8 03 00 00") == [frame(0x583, "60 7A 60 00 00 00 00 00")]
    (answer,) = rig.send(0x603, "40 41 60 00 00 00 00 00")
    assert answer.data[:4] == bytes.fromhex("4B 41 60 00")
    # too long / too short are told apart (Nanotec article SDO error table)
    assert rig.sdo("23 40 60 00 06 00 00 00") == "80 40 60 00 12 00 07 06"
    assert rig.sdo("2F 7A 60 00 01 00 00 00") == "80 7A 60 00 13 00 07 06"


@pytest.mark.parametrize(
    ("profile", "answer"),
    [
        ("mdi-s1c", "80 08 10 00 01 00 04 05"),  # MDi-S1-C manual: expedited and segmented only
        ("kinco", "80 08 10 00 01 00 04 05"),
        ("cia402", "C6 08 10 00 08 00 00 00"),  # Nanotec article: block transfer; "C5-E-SIM", CRC
    ],
)
def test_block_upload_per_profile(profile: str, answer: str) -> None:
    rig = DriveRig(1, profile)
    assert rig.sdo("A4 08 10 00 7F 00 00 00") == answer


# ---------------------------------------------------------------- NMT


@pytest.mark.parametrize("profile", PROFILE_NAMES)
def test_boot_up_and_services_per_nmt_state(profile: str) -> None:
    rig = DriveRig(6, profile)
    assert rig.boot_frames == [frame(0x706, "00")]
    assert rig.read(0x1000) == rig.drive.store.get(0x1000)  # SDO in Pre-operational
    rig.nmt(0x02)  # stop
    assert rig.send(0x606, "40 00 10 00 00 00 00 00") == []  # no SDO in Stopped (table 2.8)
    assert rig.rtr(0x706) == [frame(0x706, "04")]  # error control still answers
    rig.nmt(0x01, node=0)  # broadcast start
    assert rig.rtr(0x706) == [frame(0x706, "85")]  # toggle bit alternates
    rig.nmt(0x80)
    assert rig.rtr(0x706) == [frame(0x706, "7F")]
    rig.nmt(0x01, node=7)  # addressed to another node: ignored
    assert rig.rtr(0x706) == [frame(0x706, "FF")]


@pytest.mark.parametrize("profile", PROFILE_NAMES)
def test_reset_node_keeps_stored_values_and_restore_brings_defaults(profile: str) -> None:
    rig = DriveRig(2, profile)
    rig.write_ok(0x6081, 0, 12345, 4)  # Profile velocity
    rig.write_ok(0x1017, 0, 250, 2)  # Producer heartbeat time
    assert rig.nmt(0x81) == [frame(0x702, "00")]
    assert rig.read(0x6081) != 12345  # not stored: back to the default
    rig.write_ok(0x6081, 0, 12345, 4)
    rig.write_ok(0x1017, 0, 250, 2)
    rig.write_ok(0x1010, 1, SAVE, 4)
    rig.nmt(0x81)
    assert rig.read(0x6081) == 12345
    assert rig.read(0x1017) == 250
    assert rig.write(0x1010, 1, 0x12345678, 4) == "80 10 10 01 20 00 00 08"  # bad signature
    rig.write_ok(0x1011, 1, LOAD, 4)
    assert rig.read(0x6081) == 12345  # restore takes effect at the next reset (CiA 301)
    rig.nmt(0x81)
    assert rig.read(0x6081) != 12345
    assert rig.read(0x1017) == 0


def test_reset_communication_restores_communication_area_only() -> None:
    rig = DriveRig(2, "mdi-s1c")
    rig.write_ok(0x6081, 0, 777, 4)
    rig.write_ok(0x1017, 0, 300, 2)
    assert rig.nmt(0x82) == [frame(0x702, "00")]
    assert rig.read(0x1017) == 0
    assert rig.read(0x6081) == 777


# ---------------------------------------------------------------- node id and bitrate


def test_mdi_node_address_pa105_takes_effect_after_store_and_reset() -> None:
    rig = DriveRig(1, "mdi-s1c")
    rig.write_ok(0x2006, 0x0A, 9, 2)  # PA-105 CANopen address
    assert rig.drive.node_id == 1  # not before a reset
    rig.write_ok(0x1010, 1, SAVE, 4)
    assert rig.nmt(0x81) == [frame(0x709, "00")]
    assert rig.send(0x601, "40 00 10 00 00 00 00 00") == []
    assert rig.read(0x1014) == 0x89  # EMCY COB-ID follows the new node id
    assert rig.read(0x1800, 1) == 0x40000189
    assert rig.read(0x1018, 4) == 0x53440001  # the serial number is the device's: it stays


def test_kinco_node_offset_adds_to_the_dip_switch_address() -> None:
    rig = DriveRig(5, "kinco")
    rig.write_ok(0x2F80, 0, 3, 1)  # Node offset
    rig.write_ok(0x1010, 1, SAVE, 4)
    assert rig.nmt(0x81) == [frame(0x708, "00")]
    assert rig.read(0x2F80) == 3


def test_mdi_bitrate_pa106_change_makes_the_drive_fall_silent_after_reset() -> None:
    rig = DriveRig(1, "mdi-s1c", bus_bitrate=500_000)
    assert rig.read(0x2006, 0x0B) == 5  # PA-106: 500 kbit/s
    rig.write_ok(0x2006, 0x0B, 6, 2)  # 1 Mbit/s
    rig.write_ok(0x1010, 1, SAVE, 4)
    assert rig.nmt(0x81) == []  # boots at 1 Mbit/s: nothing on a 500 kbit/s bus
    assert rig.drive.silent
    assert rig.advance(0.05) == []


# ---------------------------------------------------------------- faults and EMCY


@pytest.mark.parametrize(
    ("profile", "code", "size", "emcy"),
    [
        (
            "mdi-s1c",
            62,
            4,
            "3E 00",
        ),  # alarm 62 SYNC lost: 2 bytes = alarm number (MDi-S1-C manual §2.7)
        ("kinco", 0x8611, 4, "11 86 00 00 00 00 00 00"),  # following error (Kinco manual §8)
        ("cia402", 0x4210, 4, "10 42 09 00 00 00 00 00"),  # code, 1001h, manufacturer bytes
    ],
)
def test_injected_fault_sends_emcy_faults_the_axis_and_resets(
    profile: str, code: int, size: int, emcy: str
) -> None:
    rig = DriveRig(7, profile)
    answers = rig.send(0x607, bytes([0x23, 0xF0, 0x5F, 0]).hex() + code.to_bytes(4, "little").hex())
    assert answers[0] == frame(0x87, emcy)  # EMCY first, then the SDO confirmation
    assert answers[1] == frame(0x587, "60 F0 5F 00 00 00 00 00")
    assert rig.read(0x6041) & 0x4F == 0x08  # Fault
    assert rig.read(0x603F) == code & 0xFFFF
    assert rig.read(0x1001) & 0x01
    # fault reset on a 0 -> 1 edge of controlword bit 7
    rig.write_ok(0x6040, 0, 0x00, 2)
    reset = rig.send(0x607, "2B 40 60 00 80 00 00 00")
    assert reset[0].can_id == 0x87  # EMCY "error reset"
    assert reset[0].data[:2] == b"\x00\x00"
    assert rig.read(0x6041) & 0x4F == 0x40  # Switch on disabled
    assert rig.read(0x1001) == 0


def test_emcy_disabled_by_1014h_bit_31() -> None:
    rig = DriveRig(7, "cia402")
    rig.write_ok(0x1014, 0, 0x80000087, 4)
    answers = rig.send(0x607, "23 F0 5F 00 10 42 00 00")
    assert answers == [frame(0x587, "60 F0 5F 00 00 00 00 00")]
    assert rig.read(0x1003, 0) == 1  # history still kept (Nanotec article)
    assert rig.read(0x1003, 1) & 0xFFFF == 0x4210
    assert rig.write(0x1003, 0, 1, 1) == "80 03 10 00 31 00 09 06"
    rig.write_ok(0x1003, 0, 0, 1)
    assert rig.read(0x1003, 0) == 0


def test_kinco_fault_bits_in_2600h_02() -> None:
    rig = DriveRig(1, "kinco")
    rig.write_ok(0x5FF0, 0, 0x4210, 4)  # servo amplifier temperature
    assert rig.read(0x2600, 2) != 0
    assert rig.read(0x603F) == 0x4210


# ---------------------------------------------------------------- error control


def test_heartbeat_producer_period() -> None:
    rig = DriveRig(3, "mdi-s1c")
    rig.write_ok(0x1017, 0, 100, 2)
    beats = [f for f in rig.advance(0.35) if f.can_id == 0x703]
    assert beats == [frame(0x703, "7F")] * 3


def test_heartbeat_consumer_faults_the_drive_when_the_master_goes_silent() -> None:
    rig = DriveRig(3, "mdi-s1c")
    rig.write_ok(0x1016, 1, (0x7F << 16) | 200, 4)  # watch node 127, 200 ms
    rig.send(0x77F, "05")
    assert rig.advance(0.15) == []
    rig.send(0x77F, "05")
    emcy = [f for f in rig.advance(0.3) if f.can_id == 0x83]
    assert emcy == [frame(0x83, "3D 00")]  # alarm 61: CAN state abnormal
    # two consumer times for one node are refused (MDi-S1-C manual 1016h)
    assert rig.write(0x1016, 2, (0x7F << 16) | 300, 4) == "80 16 10 02 43 00 04 06"


def test_life_guarding_faults_the_drive_when_guarding_stops() -> None:
    rig = DriveRig(3, "cia402")
    rig.write_ok(0x100C, 0, 100, 2)  # guard time
    rig.write_ok(0x100D, 0, 3, 1)  # life time factor
    assert rig.rtr(0x703) == [frame(0x703, "7F")]
    assert [f for f in rig.advance(0.25) if f.can_id == 0x83] == []
    assert rig.rtr(0x703) == [frame(0x703, "FF")]
    emcy = [f for f in rig.advance(0.4) if f.can_id == 0x83]
    assert len(emcy) == 1
    assert emcy[0].data[:2] == (0x8130).to_bytes(2, "little")  # life guard error


def test_heartbeat_disables_life_guarding() -> None:
    rig = DriveRig(3, "cia402")
    rig.write_ok(0x1017, 0, 1000, 2)
    rig.write_ok(0x100C, 0, 100, 2)
    rig.write_ok(0x100D, 0, 3, 1)
    rig.rtr(0x703)
    assert [f for f in rig.advance(0.5) if f.can_id == 0x83] == []


# ---------------------------------------------------------------- SYNC and PDO quirks


def test_mdi_sync_producer_limits_and_period() -> None:
    rig = DriveRig(1, "mdi-s1c")
    assert rig.write(0x1005, 0, 0x40000080, 4).startswith(
        "80"
    )  # 1006h still 0 (MDi-S1-C manual §2.6)
    assert rig.write(0x1006, 0, 400, 4) == "80 06 10 00 32 00 09 06"  # < 500 µs refused
    rig.write_ok(0x1006, 0, 2000, 4)
    rig.write_ok(0x1005, 0, 0x40000080, 4)
    syncs = [f for f in rig.advance(0.0105) if f.can_id == 0x080]
    assert len(syncs) == 5
    assert all(f.data == b"" for f in syncs)


def test_mdi_remapping_a_valid_pdo_is_refused() -> None:
    rig = DriveRig(1, "mdi-s1c")
    assert rig.write(0x1A00, 0, 0, 1) == "80 00 1A 00 00 00 01 06"
    rig.write_ok(0x1800, 1, 0xC0000181, 4)  # invalidate TPDO1 first
    rig.write_ok(0x1A00, 0, 0, 1)
    rig.write_ok(0x1A00, 1, 0x60640020, 4)
    assert rig.write(0x1A00, 2, 0x60410001, 4) == "80 00 1A 02 41 00 04 06"  # bit-wise: refused
    rig.write_ok(0x1A00, 0, 1, 1)
    rig.write_ok(0x1800, 1, 0x40000181, 4)


def test_cia402_pdo_changes_refused_in_operational() -> None:
    rig = DriveRig(1, "cia402")
    rig.nmt(0x01)
    assert rig.write(0x1A04, 0, 0, 1) == "80 04 1A 00 22 00 00 08"
    rig.nmt(0x80)
    rig.write_ok(0x1804, 1, 0xC0000381, 4)
    rig.write_ok(0x1A04, 0, 0, 1)


def test_mdi_sync_loss_in_interpolated_mode_raises_alarm_62() -> None:
    rig = DriveRig(1, "mdi-s1c")
    rig.write_ok(0x6060, 0, 7, 1)  # interpolated position
    rig.write_ok(0x60C2, 1, 2, 1)  # 2 ms
    rig.nmt(0x01)
    for controlword in (0x06, 0x07, 0x0F, 0x1F):
        rig.write_ok(0x6040, 0, controlword, 2)
        rig.advance(0.002)
    for _ in range(5):
        rig.send(0x080)
        assert [f for f in rig.advance(0.002) if f.can_id == 0x81] == []
    emcy = [f for f in rig.advance(0.05) if f.can_id == 0x81]
    assert emcy == [frame(0x81, "3E 00")]


# ---------------------------------------------------------------- resets and identity


def test_mdi_quick_stop_option_takes_only_the_listed_codes() -> None:
    rig = DriveRig(1, "mdi-s1c")
    assert rig.write(0x605A, 0, 3, 2) == "80 5A 60 00 30 00 09 06"  # MDi-S1-C manual §5.3: 1-2, 5-6
    rig.write_ok(0x605A, 0, 5, 2)


def test_reset_communication_keeps_an_active_fault_resettable() -> None:
    rig = DriveRig(7, "cia402")
    rig.write_ok(0x5FF0, 0, 0x4210, 4)
    assert rig.nmt(0x82) == [frame(0x707, "00")]
    assert rig.read(0x6041) & 0x4F == 0x08  # still in Fault: the axis was not reset
    rig.write_ok(0x6040, 0, 0x00, 2)
    rig.write_ok(0x6040, 0, 0x80, 2)
    assert rig.read(0x6041) & 0x4F == 0x40
    assert rig.read(0x603F) == 0


def test_reset_node_restarts_the_axis_in_the_restored_mode() -> None:
    rig = DriveRig(2, "kinco")
    rig.write_ok(0x6060, 0, 3, 1)  # profile velocity
    rig.advance(0.002)
    assert rig.read(0x6061) == 3
    rig.nmt(0x81)
    rig.advance(0.002)
    assert rig.read(0x6060) == 0
    assert rig.read(0x6061) == 0


def test_drives_of_one_profile_have_distinct_serial_numbers() -> None:
    assert DriveRig(1, "mdi-s1c").read(0x1018, 4) != DriveRig(4, "mdi-s1c").read(0x1018, 4)


def test_unlisted_fault_code_is_sent_as_it_is_on_cia402() -> None:
    rig = DriveRig(7, "cia402")
    answers = rig.send(0x607, "23 F0 5F 00 34 12 00 00")
    assert answers[0].data[:2] == bytes.fromhex("34 12")
