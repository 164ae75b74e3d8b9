"""EMCY code tables: exact codes per table, the class of unknown codes, error register words."""

from __future__ import annotations

import pytest

from servodesk_protocol.emcy_codes import (
    CIA301_CODES,
    CIA402_CODES,
    RESET_TEXT,
    CodeSource,
    code_class,
    describe,
    error_register_words,
    is_reset,
)


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
