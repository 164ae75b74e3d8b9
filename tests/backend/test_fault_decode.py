"""EMCY decoding layered over the drives' own tables: every MDi alarm and every Kinco code of
the profile data decodes to the manual's text; frames from the simulator's encoder round-trip."""

from __future__ import annotations

import dataclasses
import re

import pytest

import servodesk_data
from servodesk.faults import FaultRecord, decode_emcy, decode_kinco_bits, fault_words
from servodesk_data import DriveData
from servodesk_protocol.emcy import make_alarm_number, make_cia301, make_kinco
from servodesk_sim.emcy import Fault, emcy_payload

MDI = servodesk_data.load("mdi-s1c")
KINCO = servodesk_data.load("kinco")
CIA402 = servodesk_data.load("cia402")


@pytest.mark.parametrize("entry", MDI.faults, ids=lambda e: f"alarm{e.code}")
def test_every_mdi_alarm_decodes_to_the_manual_text(entry: servodesk_data.FaultEntry) -> None:
    record = decode_emcy(MDI, 1, make_alarm_number(entry.code), time=12.5)
    assert (record.source, record.code, record.name_zh) == ("vendor", entry.code, entry.name)
    assert record.name_en == entry.name_en
    assert record.check is not None
    assert entry.description in record.check
    assert entry.what_to_check.rstrip(".") in record.check
    assert "MDi-S1-C CANopen manual §4.1" in record.check
    assert (record.time, record.node, record.error_register) == (12.5, 1, None)
    assert record.code_hex == f"0x{entry.code:04X}"


@pytest.mark.parametrize("entry", KINCO.faults, ids=lambda e: f"{e.code:#x}")
def test_every_kinco_code_decodes_to_the_manual_text(entry: servodesk_data.FaultEntry) -> None:
    record = decode_emcy(KINCO, 2, make_kinco(entry.code))
    assert record.source == "vendor"
    assert record.code == entry.code & 0xFFFF  # only the low 16 bits travel (manual §8)
    assert entry.name_en in record.name_en.split(" / ")
    assert record.check is not None
    assert f"2600h:02 bit {entry.kinco_bit:#x} {entry.name}" in record.check
    assert "Kinco servo CANopen manual §8" in record.check


def test_kinco_exact_code_comes_first_and_shared_codes_say_so() -> None:
    record = decode_emcy(KINCO, 2, make_kinco(0x7305))
    assert record.name_en == "Motor encoder non-equivalence error / Motor encoder counting error"
    shared = decode_emcy(KINCO, 2, bytes.fromhex("20 23 00 00 00 00 00 00"))
    assert shared.name_en.startswith("Short circuit phase A / Short circuit phase B")
    assert shared.check is not None
    assert "12320h, 22320h, 32320h" in shared.check


def test_kinco_fault_bits() -> None:
    found = decode_kinco_bits(KINCO, 0x2000 | 0x2)
    assert [e.name for e in found] == ["FAULT_REGLERWD_BIT", "FAULT_FOLLOWINGERROR_BIT"]


@pytest.mark.parametrize(
    ("data", "source", "code", "name", "register", "manufacturer"),
    [
        ("11 86 21 00 00 00 00 00", "vendor", 0x8611, "Following error", 0x21, "00 00 00 00 00"),
        ("50 82 11 01 02 03 04 05", "cia301", 0x8250, "RPDO timeout",
         0x11, "01 02 03 04 05"),
        ("01 8F 81 AA 00 00 00 00", "unknown", 0x8F01, "Unknown monitoring code 0x8F01", 0x81,
         "AA 00 00 00 00"),
        ("00 00 00 00 00 00 00 00", "cia301", 0, "Error reset / no error", 0, "00 00 00 00 00"),
    ],
)  # fmt: skip
def test_cia301_format_exact_frames(
    data: str, source: str, code: int, name: str, register: int, manufacturer: str
) -> None:
    record = decode_emcy(CIA402, 3, bytes.fromhex(data))
    assert (record.source, record.code, record.name_en) == (source, code, name)
    assert (record.error_register, record.manufacturer_hex, record.raw_hex) == (
        register, manufacturer, data.upper()
    )  # fmt: skip


def test_unknown_node_uses_cia_tables_and_class() -> None:
    assert decode_emcy(None, 9, make_cia301(0x3210, 0x05)).name_en == "DC-link over-voltage"
    assert decode_emcy(None, 9, make_cia301(0x3210, 0x05)).source == "cia402"
    unknown = decode_emcy(None, 9, make_cia301(0x5123, 0x81))
    assert unknown.name_en == "Unknown device hardware code 0x5123"
    assert unknown.check == "Error register 81h: generic, manufacturer."
    # a 2-byte EMCY of an unidentified node still decodes its code
    assert decode_emcy(None, 9, bytes.fromhex("11 86")).name_en == "Following error"


def test_never_nothing() -> None:
    assert decode_emcy(MDI, 1, make_alarm_number(999)).name_en == (
        "Unknown alarm 999 (not in the MDi-S1-C CANopen manual §4.1)"
    )
    assert decode_emcy(MDI, 1, b"\x04").name_en.startswith("Malformed EMCY (1 data bytes")
    assert decode_emcy(MDI, 1, make_alarm_number(0)).name_en == "Error reset / no error"


@pytest.mark.parametrize("profile", [MDI, KINCO, CIA402], ids=lambda p: p.profile)
def test_simulator_frames_round_trip(profile: DriveData) -> None:
    """The simulated drive's EMCY payload for every fault of its table decodes back to it."""
    for entry in profile.faults:
        fault = Fault(entry.code, entry.emcy_code, entry.error_register, entry.kinco_bit)
        data = emcy_payload(profile.quirks.emcy_format, fault, entry.error_register)
        record = decode_emcy(profile, 1, data)
        assert record.source == "vendor"
        assert entry.name_en in record.name_en.split(" / ")
        if profile is CIA402:
            assert record.error_register == entry.error_register
    reset = decode_emcy(profile, 1, emcy_payload(profile.quirks.emcy_format, None, 0))
    assert reset.name_en == "Error reset / no error"


def test_fault_words() -> None:
    assert fault_words(decode_emcy(MDI, 1, make_alarm_number(4)), MDI) == (
        "alarm 4 位置超差 Position deviation too large"
    )
    assert fault_words(decode_emcy(CIA402, 3, make_cia301(0x8611, 0x21)), CIA402) == (
        "0x8611 Following error"
    )


def test_record_is_the_api_shape() -> None:
    record = decode_emcy(MDI, 1, make_alarm_number(62), time=1.0)
    assert set(record.as_dict()) == {
        "time", "node", "code", "code_hex", "source", "name_en", "name_zh", "name_zh_source",
        "check", "check_zh", "error_register", "manufacturer_hex", "raw_hex",
    }  # fmt: skip
    assert record.name_zh == "同步帧丢失异常"
    assert record.name_zh_source == "manual"


# Chinese names: the MDi's from its manual; Kinco's and the CiA tables' are ServoDesk's
# translation of the English, which stays the source's words


@pytest.mark.parametrize("entry", MDI.faults, ids=lambda e: f"alarm{e.code}")
def test_an_mdi_alarm_s_chinese_is_the_manual_s(entry: servodesk_data.FaultEntry) -> None:
    record = decode_emcy(MDI, 1, make_alarm_number(entry.code))
    assert (record.name_zh, record.name_zh_source) == (entry.name, "manual")


def test_a_kinco_emcy_gets_servodesk_s_translation() -> None:
    record = decode_emcy(KINCO, 2, make_kinco(0x8611))
    assert record.name_en == "Following error too high"  # the manual's words
    assert (record.name_zh, record.name_zh_source) == ("跟随误差过大", "translation")
    # a shared low 16 bits names each entry, in English and in Chinese alike
    shared = decode_emcy(KINCO, 2, make_kinco(0x12320))
    assert shared.name_zh is not None
    assert shared.name_en.count(" / ") == shared.name_zh.count(" / ") == 2
    assert shared.name_zh_source == "translation"


@pytest.mark.parametrize("entry", KINCO.faults + CIA402.faults, ids=lambda e: f"{e.code:#x}")
def test_every_translated_entry_decodes_with_its_chinese(entry: servodesk_data.FaultEntry) -> None:
    profile = KINCO if entry.kinco_bit else CIA402
    data = make_kinco(entry.code) if entry.kinco_bit else make_cia301(entry.code, 0x01)
    record = decode_emcy(profile, 2, data)
    assert entry.name_zh is not None
    assert entry.name_zh in (record.name_zh or "")
    assert entry.name_en in record.name_en
    assert record.name_zh_source == "translation"


def test_a_cia402_emcy_gets_servodesk_s_translation() -> None:
    # the cia402 profile's table, and the CiA 402 table itself for a node of unknown identity
    for profile in (CIA402, None):
        record = decode_emcy(profile, 3, make_cia301(0x3210, 0x05))
        assert (record.name_zh, record.name_zh_source) == ("直流母线过压", "translation")
    record = decode_emcy(None, 3, make_cia301(0x8611, 0x21))
    assert (record.source, record.name_en) == ("cia402", "Following error")
    assert (record.name_zh, record.name_zh_source) == ("跟随误差过大", "translation")


def test_a_cia301_emcy_gets_servodesk_s_translation() -> None:
    record = decode_emcy(None, 5, make_cia301(0x8130, 0x11))
    assert (record.source, record.name_en) == ("cia301", "Life guard error or heartbeat error")
    assert (record.name_zh, record.name_zh_source) == ("节点保护错误或心跳错误", "translation")
    generic = decode_emcy(None, 5, make_cia301(0x2000, 0x03))
    assert (generic.name_en, generic.name_zh) == ("Current – generic error", "电流 – 通用错误")


def test_no_chinese_no_source() -> None:
    cleared = decode_emcy(MDI, 1, make_alarm_number(0))  # the MDi's alarm 0 as before
    assert (cleared.name_en, cleared.name_zh) == ("Error reset / no error", None)
    reset = decode_emcy(KINCO, 2, make_kinco(0))
    assert (reset.name_zh, reset.name_zh_source) == ("错误复位 / 无错误", "translation")


def test_fault_words_keep_the_source_s_words() -> None:
    # a timeline line: the manual's Chinese yes, ServoDesk's translation no
    assert fault_words(decode_emcy(KINCO, 2, make_kinco(0x8611)), KINCO) == (
        "0x8611 Following error too high"
    )


def test_what_servodesk_says_itself_has_its_chinese() -> None:
    record = decode_emcy(MDI, 1, make_alarm_number(99))  # not in the manual's table
    assert (record.name_zh, record.name_zh_source) == (
        "未知报警 99（MDi-S1-C CANopen 手册 §4.1 中没有）",
        "translation",
    )
    malformed = decode_emcy(None, 1, b"\x01")
    assert (malformed.name_zh, malformed.name_zh_source) == (
        "EMCY 格式错误（1 个数据字节，错误代码需要 2 个）",
        "translation",
    )
    assert (record.check, record.check_zh, malformed.check, malformed.check_zh) == (None,) * 4


# check_zh: the parts of check, in the same order, with Chinese labels (the page splits at them)
ZH_LABEL = re.compile(
    r"(?:^|\s)(原因|检查|来源|CiA 类别|CiA 代码 [0-9A-F]+h|错误寄存器 [0-9A-F]+h)："
)
EN_LABEL = re.compile(
    r"(?:^|\s)(Cause|Check|Source|CiA class|CiA code [0-9A-F]+h|Error register [0-9A-F]+h):"
)
EN_TO_ZH = {"Cause": "原因", "Check": "检查", "Source": "来源", "CiA class": "CiA 类别"}


def zh_labels(record: FaultRecord) -> list[str]:
    assert record.check_zh is not None
    assert "  " not in record.check_zh  # one space between parts
    assert not EN_LABEL.search(record.check_zh)  # never half English
    parts = [p for p in ZH_LABEL.split(record.check_zh) if p]
    assert all(text.endswith("。") for text in parts[1::2]), parts
    return ZH_LABEL.findall(record.check_zh)


def en_labels_in_chinese(record: FaultRecord) -> list[str]:
    assert record.check is not None
    return [
        EN_TO_ZH.get(label)
        or label.replace("CiA code", "CiA 代码").replace("Error register", "错误寄存器")
        for label in EN_LABEL.findall(record.check)
    ]


@pytest.mark.parametrize(
    ("profile", "data"),
    [(MDI, make_alarm_number(e.code)) for e in MDI.faults]
    + [(KINCO, make_kinco(e.code)) for e in KINCO.faults]
    + [(CIA402, make_cia301(e.code, e.error_register)) for e in CIA402.faults],
    ids=lambda v: v.hex() if isinstance(v, bytes) else v.profile,
)
def test_every_shipped_fault_has_its_check_in_chinese(profile: DriveData, data: bytes) -> None:
    record = decode_emcy(profile, 1, data)
    assert zh_labels(record) == en_labels_in_chinese(record)


def test_mdi_alarm_check_in_chinese() -> None:
    record = decode_emcy(MDI, 1, make_alarm_number(4))
    assert zh_labels(record) == ["原因", "检查", "CiA 类别", "来源"]
    assert record.check_zh == (
        "原因：位置偏差计数器的数值超过设定值。"  # the manual's own words
        " 检查：跟随误差窗口 6065h、加速度是否超出电机转矩能力、机械卡死或抱闸未松开、"
        "电机相线接线、增益。"
        " CiA 类别：ServoDesk 将其映射为 8611h 跟随误差过大（驱动器的 EMCY 只携带报警号）。"
        " 来源：MDi-S1-C CANopen 手册 §4.1。"
    )


def test_kinco_shared_code_check_in_chinese() -> None:
    record = decode_emcy(KINCO, 2, make_kinco(0x22320))  # 12320h/22320h/32320h: 2320h
    assert zh_labels(record) == ["原因", "检查", "检查", "检查", "来源"]
    assert record.check_zh is not None
    assert record.check_zh.startswith(
        "原因：电机 A 相短路或对地短路。 EMCY 只携带 603Fh 的低 16 位"
    )
    assert "（12320h、22320h、32320h 共用）" in record.check_zh
    assert "（2600h:02 位 0x400 FAULT_B_ERROR_BIT）。" in record.check_zh
    assert record.check_zh.endswith(" 来源：步科伺服 CANopen 手册 §8。")
    overspeed = decode_emcy(KINCO, 2, make_kinco(0x8400))  # not in the manual
    assert overspeed.check_zh is not None
    assert " 来源：ServoDesk 仿真驱动器；步科伺服 CANopen 手册 §8 标注" in overspeed.check_zh


def test_cia402_profile_check_in_chinese() -> None:
    record = decode_emcy(CIA402, 3, make_cia301(0x8611, 0x21))
    assert zh_labels(record) == ["原因", "检查", "来源"]
    assert record.check_zh == (
        "原因：位置误差超出跟随误差窗口 6065h。"
        " 检查：6065h、加速度是否超出可用转矩、机械卡死、抱闸、增益。"
        " 来源：Nanotec CANopen 文章。"
    )


def test_cia_code_part_in_chinese() -> None:
    # a vendor code whose CiA code differs (no shipped table has one): "CiA 代码 XXXXh："
    entry = dataclasses.replace(CIA402.faults[0], code=0xFF01, emcy_code=0x8611)
    profile = dataclasses.replace(CIA402, faults=(entry,))
    record = decode_emcy(profile, 3, make_cia301(0xFF01, 0x21))
    assert zh_labels(record) == ["原因", "检查", "CiA 代码 8611h", "来源"]
    assert record.check_zh is not None
    assert " CiA 代码 8611h：跟随误差过大。 " in record.check_zh


def test_unknown_node_cia301_check_in_chinese() -> None:
    record = decode_emcy(None, 5, make_cia301(0x8130, 0x11))
    assert (
        record.check
        == "CiA class: monitoring / communication. Error register 11h: generic, communication."
    )
    assert record.check_zh == "CiA 类别：监控 / 通信。 错误寄存器 11h：通用、通信。"
    assert zh_labels(record) == ["CiA 类别", "错误寄存器 11h"]
    unknown = decode_emcy(None, 9, make_cia301(0x5123, 0x81))
    assert unknown.check_zh == "错误寄存器 81h：通用、制造商自定义。"
    reset = decode_emcy(None, 9, make_cia301(0, 0))
    assert (reset.check, reset.check_zh) == (None, None)


def test_no_chinese_check_without_every_part_in_chinese() -> None:
    # a user's profile without description_zh / what_to_check_zh: English only, never mixed
    entry = MDI.fault(4)
    assert entry is not None
    bare = dataclasses.replace(entry, description_zh=None)
    profile = dataclasses.replace(MDI, faults=(bare,))
    record = decode_emcy(profile, 1, make_alarm_number(4))
    assert record.check == decode_emcy(MDI, 1, make_alarm_number(4)).check
    assert record.check_zh is None
    # one of several entries sharing a Kinco code without its check in Chinese
    shared = [e for e in KINCO.faults if e.code & 0xFFFF == 0x2320]
    faults = (*shared[:2], dataclasses.replace(shared[2], what_to_check_zh=None))
    record = decode_emcy(dataclasses.replace(KINCO, faults=faults), 2, make_kinco(0x12320))
    assert record.check is not None
    assert record.check_zh is None
