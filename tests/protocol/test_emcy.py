"""EMCY data in the three formats, exact bytes both ways, and the error register bits."""

from __future__ import annotations

import pytest

from servodesk_protocol.emcy import (
    Emcy,
    EmcyFormat,
    ErrorRegister,
    decode,
    history_entry,
    make_alarm_number,
    make_cia301,
    make_kinco,
    make_payload,
    split_history_entry,
)

ALARM = EmcyFormat.ALARM_NUMBER
KINCO = EmcyFormat.KINCO
CIA301 = EmcyFormat.CIA301
R = ErrorRegister


@pytest.mark.parametrize(
    ("fmt", "code", "register", "data", "decoded"),
    [
        # MDi-S1-C CANopen manual §2.7: 2 bytes, alarm number low byte first; 0 = reset
        (ALARM, 1, 0x21, "01 00", Emcy(1, None, b"")),
        (ALARM, 62, 0x11, "3E 00", Emcy(62, None, b"")),  # §4.1 alarm 62, SYNC lost
        (ALARM, 0, 0, "00 00", Emcy(0, None, b"")),
        # Kinco servo CANopen manual §5.6/§8: low 2 bytes of 603Fh, 6 unused bytes
        (KINCO, 0x17305, 0x21, "05 73 00 00 00 00 00 00", Emcy(0x7305, None, b"")),
        (KINCO, 0x8611, 0x21, "11 86 00 00 00 00 00 00", Emcy(0x8611, None, b"")),
        # Nanotec CANopen article: code, 1001h, 5 manufacturer bytes
        (CIA301, 0x8611, 0x21, "11 86 21 00 00 00 00 00",
         Emcy(0x8611, R.GENERIC | R.DEVICE_PROFILE, bytes(5))),
        (CIA301, 0x3210, 0x05, "10 32 05 00 00 00 00 00",
         Emcy(0x3210, R.GENERIC | R.VOLTAGE, bytes(5))),
        (CIA301, 0, 0, "00 00 00 00 00 00 00 00", Emcy(0, R(0), bytes(5))),
    ],
)  # fmt: skip
def test_payload_and_decode(
    fmt: EmcyFormat, code: int, register: int, data: str, decoded: Emcy
) -> None:
    assert make_payload(fmt, code, register) == bytes.fromhex(data)
    assert decode(fmt, bytes.fromhex(data)) == decoded
    assert decoded.is_reset is (decoded.code == 0)


def test_builders() -> None:
    assert make_alarm_number(0x1234) == bytes.fromhex("34 12")
    assert make_kinco(0x00023200) == bytes.fromhex("00 32 00 00 00 00 00 00")
    assert make_cia301(0xFF00, 0x81, b"\x01\x02") == bytes.fromhex("00 FF 81 01 02 00 00 00")
    with pytest.raises(ValueError, match="at most 5"):
        make_cia301(0x1000, 0x01, bytes(6))


def test_decode_keeps_manufacturer_bytes() -> None:
    emcy = decode(CIA301, bytes.fromhex("00 50 81 DE AD BE EF 01"))
    assert emcy == Emcy(0x5000, R.GENERIC | R.MANUFACTURER, bytes.fromhex("DE AD BE EF 01"))


@pytest.mark.parametrize(("fmt", "data"), [(ALARM, "01"), (KINCO, ""), (CIA301, "11 86")])
def test_decode_refuses_short_data(fmt: EmcyFormat, data: str) -> None:
    with pytest.raises(ValueError, match="too short"):
        decode(fmt, bytes.fromhex(data))


def test_history_entry() -> None:
    assert history_entry(0x8611, 0x21) == 0x00218611
    assert split_history_entry(0x00218611) == (0x8611, 0x21)


@pytest.mark.parametrize(
    ("register", "flags"),
    [
        (0x01, R.GENERIC),
        (0x03, R.GENERIC | R.CURRENT),
        (0x11, R.GENERIC | R.COMMUNICATION),
        (0x29, R.GENERIC | R.TEMPERATURE | R.DEVICE_PROFILE),
    ],
)
def test_error_register_bits(register: int, flags: ErrorRegister) -> None:
    assert ErrorRegister(register) == flags
