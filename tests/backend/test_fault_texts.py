"""Fault texts say what the drive sent and what is ServoDesk's own: the MDi-S1-C's EMCY holds
only its alarm number (the CiA class is ServoDesk's mapping, not a code the drive sends), and
the Kinco overspeed entry is the simulated drive's (the manual marks bit 4000h not used)."""

from __future__ import annotations

import json
from pathlib import Path

import servodesk_data
from servodesk.faults.decode import decode_emcy
from servodesk.logs import EventKind, LogAnalysis

MDI = servodesk_data.load("mdi-s1c")
KINCO = servodesk_data.load("kinco")
MAPPED = "CiA class: ServoDesk maps it to 8612h Reference limit (the drive's EMCY carries only"


def test_mdi_alarm_names_the_mapping_as_servodesks() -> None:
    record = decode_emcy(MDI, 1, bytes([7, 0]))  # alarm 7 驱动禁止异常
    assert record.check is not None
    assert MAPPED in record.check
    assert "CiA code 8612h" not in record.check


def test_mdi_alarm_in_a_log_names_the_mapping_too(tmp_path: Path) -> None:
    log = tmp_path / "mdi.log"
    log.write_text("(1700000000.000000) can0 081#0700\n")
    (emcy,) = [e for e in LogAnalysis(log, profiles={1: "mdi-s1c"}).events()
               if e.kind == EventKind.EMCY]  # fmt: skip
    check = json.loads(emcy.data or "{}")["check"]
    assert MAPPED in check
    assert "CiA code" not in check


def test_kinco_overspeed_is_the_simulated_drives() -> None:
    record = decode_emcy(KINCO, 2, bytes.fromhex("0084000000000000"))
    assert record.check is not None
    assert "Source: ServoDesk's simulated drive; the Kinco servo CANopen manual §8 marks" in (
        record.check
    )
    assert "Source: Kinco servo CANopen manual §8." not in record.check


def test_kinco_manual_codes_keep_their_source() -> None:
    record = decode_emcy(KINCO, 2, bytes.fromhex("1186000000000000"))  # following error
    assert record.check is not None
    assert record.check.endswith("Source: Kinco servo CANopen manual §8.")
    assert "CiA code" not in record.check  # 8611h is the code it sent


def test_kinco_8120_names_heartbeat_loss_and_keeps_the_manuals_words() -> None:
    # What the Faults page shows for a Kinco EMCY 8120h: the simulated drive (and the profile)
    # raise it for a lost consumed heartbeat too, not only for node guarding.
    record = decode_emcy(KINCO, 2, bytes.fromhex("2081000000000000"))
    assert record.source == "vendor"
    assert record.code_hex == "0x8120"
    assert record.name_en == "CAN communication interrupted (node guarding or heartbeat lost)"
    # the manual's name is the firmware symbol, not Chinese: the Chinese is ServoDesk's
    assert (record.name_zh, record.name_zh_source) == (
        "CAN 通信中断（节点保护或心跳丢失）",
        "translation",
    )
    assert record.check is not None
    assert record.check.startswith("Cause: The master's node guarding, or a heartbeat the drive")
    assert '"CAN communication interrupted in the Node Guarding mode"' in record.check
    assert "consumer time 1016h" in record.check
    assert record.check.endswith("Source: Kinco servo CANopen manual §8.")


def test_mdi_alarm_7_says_both_inhibit_inputs() -> None:
    record = decode_emcy(MDI, 1, bytes([7, 0]))
    assert (record.name_zh, record.name_en) == ("驱动禁止异常", "Drive inhibit fault")
    assert record.check is not None
    assert "CCW/CW 驱动禁止输入都 OFF" in record.check
    assert "One inhibit input alone raises no alarm" in record.check
