"""EMCY code tables: exact codes per table, the class of unknown codes, error register words,
and ServoDesk's Chinese translation of each beside the untouched English."""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Mapping

import pytest

from servodesk_protocol import emcy_codes
from servodesk_protocol.emcy_codes import (
    CIA301_CODES,
    CIA301_CODES_ZH,
    CIA402_CODES,
    CIA402_CODES_ZH,
    ERROR_REGISTER_BITS,
    ERROR_REGISTER_BITS_ZH,
    RESET_TEXT,
    RESET_TEXT_ZH,
    CodeSource,
    code_class,
    code_class_zh,
    describe,
    error_register_words,
    error_register_words_zh,
    is_reset,
)

_CJK = re.compile(r"[\u3400-\u9fff]")


@pytest.mark.parametrize(
    ("code", "source", "text"),
    [
        (0x8611, CodeSource.CIA402, "Following error"),
        (0x8612, CodeSource.CIA402, "Reference limit"),
        (0x2310, CodeSource.CIA402, "Continuous over-current"),
        (0x3210, CodeSource.CIA402, "DC-link over-voltage"),
        (0x7305, CodeSource.CIA402, "Incremental sensor 1 fault"),
        (0x7307, CodeSource.CIA402, "Incremental sensor 3 fault"),
        (0x5441, CodeSource.CIA402, "Contact 1 (manufacturer-specific)"),
        (0x5459, CodeSource.CIA402, "Fuse S9 (manufacturer-specific)"),
        (0x6301, CodeSource.CIA402, "Data record no. 1"),
        (0x630F, CodeSource.CIA402, "Data record no. 15"),
        (0x8130, CodeSource.CIA301, "Life guard error or heartbeat error"),
        (0x8120, CodeSource.CIA301, "CAN in error-passive mode"),  # not "heartbeat" (pitfall)
        (0x8140, CodeSource.CIA301, "Recovered from bus-off"),
        (0x8250, CodeSource.CIA301, "RPDO timeout"),
        (0x1000, CodeSource.CIA301, "Generic error"),
        (0x0000, CodeSource.CIA301, RESET_TEXT),
        (0x0012, CodeSource.CIA301, RESET_TEXT),  # 00xxh
        (0x8F01, CodeSource.UNKNOWN, "Unknown monitoring code 0x8F01"),
        (0x5123, CodeSource.UNKNOWN, "Unknown device hardware code 0x5123"),
        (0x2999, CodeSource.UNKNOWN, "Unknown current code 0x2999"),
        (0x81FD, CodeSource.UNKNOWN, "Unknown monitoring / communication code 0x81FD"),
        (0xFF12, CodeSource.UNKNOWN, "Manufacturer-specific code 0xFF12"),
        (0xA000, CodeSource.UNKNOWN, "Unknown reserved code 0xA000"),
    ],
)
def test_describe(code: int, source: CodeSource, text: str) -> None:
    described = describe(code)
    assert (described.source, described.text) == (source, text)


def test_cia401_devices_skip_the_drive_table() -> None:
    # 2320h is "short circuit at outputs" for CiA 401: without the 402 table only the class
    assert describe(0x2320, cia402=False).source is CodeSource.UNKNOWN
    assert describe(0x2320, cia402=False).code_class == "current, device output side"


@pytest.mark.parametrize(
    ("code", "cls"),
    [
        (0x8611, "monitoring"),
        (0x8130, "monitoring / communication"),
        (0x8210, "monitoring / protocol error"),
        (0x2110, "current, device input side"),
        (0x4210, "temperature / device temperature"),
        (0x5530, "device hardware"),
        (0x6320, "device software / data set"),
        (0x9000, "external error"),
        (0xF001, "additional functions"),
        (0xFF00, "device specific"),
        (0x0000, "error reset"),
    ],
)
def test_code_class(code: int, cls: str) -> None:
    assert code_class(code) == cls


def test_every_code_has_text_and_no_table_overlaps_the_other() -> None:
    assert all(text for text in CIA402_CODES.values())
    assert not set(CIA402_CODES) & set(CIA301_CODES)
    assert len(CIA402_CODES) == 178


@pytest.mark.parametrize(
    ("register", "words"),
    [
        (0x00, []),
        (0x01, ["generic"]),
        (0x21, ["generic", "device profile"]),
        (0x05, ["generic", "voltage"]),
        (0x91, ["generic", "communication", "manufacturer"]),
        (0xFF, ["generic", "current", "voltage", "temperature", "communication",
                "device profile", "reserved bit 6", "manufacturer"]),
    ],
)  # fmt: skip
def test_error_register_words(register: int, words: list[str]) -> None:
    assert error_register_words(register) == words


def test_is_reset() -> None:
    assert is_reset(0x0000)
    assert is_reset(0x00FF)
    assert not is_reset(0x0100)


def _digest(table: Mapping[int, str]) -> str:
    return hashlib.sha256(
        json.dumps(sorted(table.items()), ensure_ascii=False).encode()
    ).hexdigest()


# the English tables are the standards' words: the Chinese ones sit beside them and change none
# (a deliberate correction of the English updates its digest here)
BYTES, NIBBLES = emcy_codes._BYTE_CLASSES, emcy_codes._NIBBLE_CLASSES
ENGLISH = [
    (CIA402_CODES, 178, "2aeda0288dd6d9cb095b9b0c79ea2c6fe687378c6b292b3e2b39de84d7314dc2"),
    (CIA301_CODES, 11, "cdefb12ebaad7f1ee3d47ab1e0ae2737d9f67becc7da7c67c47d5180e587c752"),
    (BYTES, 15, "a48a2a282e78af093a30cd0487c4f64a168b5b97af9a62f64bcafa9ee4ff4c21"),
    (NIBBLES, 10, "7628007f674c2414a57141c77550d9bd340bd113af0a2ce497576cb90156948e"),
]  # fmt: skip


@pytest.mark.parametrize(("table", "count", "digest"), ENGLISH)
def test_the_english_tables_are_unchanged(
    table: Mapping[int, str], count: int, digest: str
) -> None:
    assert (len(table), _digest(table)) == (count, digest)


@pytest.mark.parametrize(
    ("english", "chinese"),
    [
        (CIA402_CODES, CIA402_CODES_ZH),
        (CIA301_CODES, CIA301_CODES_ZH),
        (emcy_codes._BYTE_CLASSES, emcy_codes._BYTE_CLASSES_ZH),
        (emcy_codes._NIBBLE_CLASSES, emcy_codes._NIBBLE_CLASSES_ZH),
    ],
    ids=["cia402", "cia301", "byte-classes", "nibble-classes"],
)
def test_every_code_and_class_has_chinese(
    english: Mapping[int, str], chinese: Mapping[int, str]
) -> None:
    assert set(chinese) == set(english)
    for code, text in chinese.items():
        assert text.strip(), f"{code:#x}"
        assert _CJK.search(text), f"{code:#x}: {text!r}"


def test_error_register_bits_and_reset_have_chinese() -> None:
    assert [bit for bit, _ in ERROR_REGISTER_BITS_ZH] == [bit for bit, _ in ERROR_REGISTER_BITS]
    assert all(_CJK.search(words) for _, words in ERROR_REGISTER_BITS_ZH)
    assert error_register_words_zh(0x21) == ["通用", "设备子协议"]
    assert error_register_words(0x21) == ["generic", "device profile"]  # the English as it was
    assert _CJK.search(RESET_TEXT_ZH)


@pytest.mark.parametrize(
    ("code", "source", "text", "text_zh"),
    [
        (0x8611, CodeSource.CIA402, "Following error", "跟随误差过大"),
        (0x3210, CodeSource.CIA402, "DC-link over-voltage", "直流母线过压"),
        (0x3220, CodeSource.CIA402, "DC-link under-voltage", "直流母线欠压"),
        (0x7305, CodeSource.CIA402, "Incremental sensor 1 fault", "增量编码器 1 故障"),
        (0x5453, CodeSource.CIA402, "Fuse S3 = L3", "熔断器 S3 = L3"),
        (0x8130, CodeSource.CIA301, "Life guard error or heartbeat error",
         "节点保护错误或心跳错误"),
        (0x0000, CodeSource.CIA301, RESET_TEXT, RESET_TEXT_ZH),
        (0x8F01, CodeSource.UNKNOWN, "Unknown monitoring code 0x8F01",
         "未知代码 0x8F01（监控）"),
        (0xFF12, CodeSource.UNKNOWN, "Manufacturer-specific code 0xFF12",
         "制造商自定义代码 0xFF12"),
    ],
)  # fmt: skip
def test_describe_gives_the_translation_beside_the_text(
    code: int, source: CodeSource, text: str, text_zh: str
) -> None:
    described = describe(code)
    assert (described.source, described.text, described.text_zh) == (source, text, text_zh)


@pytest.mark.parametrize(
    ("code", "cls"),
    [(0x8130, "监控 / 通信"), (0x2110, "电流，设备输入侧"), (0x4210, "温度 / 设备温度"),
     (0xF001, "附加功能"), (0xA000, "保留"), (0x0000, "错误复位")],
)  # fmt: skip
def test_code_class_zh(code: int, cls: str) -> None:
    assert code_class_zh(code) == cls
