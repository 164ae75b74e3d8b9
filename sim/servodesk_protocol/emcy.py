"""EMCY frames (CiA 301 §7.2.7) in the three formats the supported drives send, and the error
register (1001h) bits. Pure building and decoding of the data bytes; the COB-ID is 80h + node id
unless 1014h says otherwise.

- MDi (MDi-S1-C CANopen manual §2.7): 2 data bytes, the alarm number little-endian (§4.1);
  alarm 0 means "normal" (the error-reset EMCY).
- Kinco (Kinco servo CANopen manual §5.6, §8): 8 bytes, the low 16 bits of the 603Fh code
  little-endian, the other six bytes unused (0).
- CiA 301 (Nanotec CANopen article, EMCY): EMCY error code (2 bytes LE), 1001h error register,
  5 manufacturer-specific bytes.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntFlag, StrEnum

ERROR_REGISTER = 0x1001  # Error register
ERROR_HISTORY = 0x1003  # Pre-defined error field
COB_ID_EMCY = 0x1014  # COB-ID EMCY
INHIBIT_TIME_EMCY = 0x1015  # Inhibit time EMCY (100 µs)

ERROR_RESET = 0x0000  # EMCY error code "error reset or no error"
ALARM_NUMBER_LENGTH = 2
FRAME_LENGTH = 8  # the Kinco and CiA 301 formats always send 8 bytes
MANUFACTURER_LENGTH = 5  # CiA 301 bytes 3–7


class EmcyFormat(StrEnum):
    """How a drive words its EMCY data; the values are the profile.toml spellings."""

    ALARM_NUMBER = "alarm_number"  # MDi: 2 data bytes = alarm number
    KINCO = "kinco"  # 8 bytes: low 16 bits of the 603Fh code, then zeros
    CIA301 = "cia301"  # 8 bytes: code, 1001h, 5 manufacturer bytes


class ErrorRegister(IntFlag):
    """1001h bits (CiA 301 §7.5.2.2). GENERIC is set whenever any error is active."""

    GENERIC = 0x01
    CURRENT = 0x02
    VOLTAGE = 0x04
    TEMPERATURE = 0x08
    COMMUNICATION = 0x10  # overrun, error state
    DEVICE_PROFILE = 0x20  # device-profile specific (CiA 402: e.g. following error)
    RESERVED = 0x40  # always 0
    MANUFACTURER = 0x80


@dataclass(frozen=True, slots=True)
class Emcy:
    """One decoded EMCY. `code` is what the format carries: MDi alarm number, low 16 bits of the
    Kinco 603Fh code, or the CiA 301 EMCY error code."""

    code: int
    error_register: ErrorRegister | None  # only the CiA 301 format carries it
    manufacturer: bytes  # CiA 301 bytes 3–7; empty in the other formats

    @property
    def is_reset(self) -> bool:
        """The "error reset / no error" EMCY a drive sends once its faults are cleared."""
        return self.code == ERROR_RESET


def make_alarm_number(alarm: int) -> bytes:
    """MDi EMCY data: the alarm number, 2 bytes little-endian (0 = error reset)."""
    return (alarm & 0xFFFF).to_bytes(ALARM_NUMBER_LENGTH, "little")


def make_kinco(error_code: int) -> bytes:
    """Kinco EMCY data: only the low 2 bytes of 603Fh travel (manual §8), 6 bytes of 0 follow."""
    return (error_code & 0xFFFF).to_bytes(2, "little") + bytes(FRAME_LENGTH - 2)


def make_cia301(error_code: int, error_register: int, manufacturer: bytes = b"") -> bytes:
    """CiA 301 EMCY data: code LE, error register, manufacturer bytes padded with 0 to 5."""
    if len(manufacturer) > MANUFACTURER_LENGTH:
        raise ValueError(f"{len(manufacturer)} manufacturer bytes, at most 5")
    pad = bytes(MANUFACTURER_LENGTH - len(manufacturer))
    return (
        (error_code & 0xFFFF).to_bytes(2, "little")
        + bytes([error_register & 0xFF])
        + (manufacturer + pad)
    )


def make_payload(fmt: EmcyFormat, code: int, error_register: int) -> bytes:
    """EMCY data in `fmt`; `code` is the format's own code (see Emcy.code), 0 = error reset."""
    if fmt is EmcyFormat.ALARM_NUMBER:
        return make_alarm_number(code)
    if fmt is EmcyFormat.KINCO:
        return make_kinco(code)
    return make_cia301(code, error_register)


def decode(fmt: EmcyFormat, data: bytes) -> Emcy:
    """An EMCY's data read in `fmt`. Raises ValueError when too short to hold the code."""
    if len(data) < 2 or (fmt is EmcyFormat.CIA301 and len(data) < 3):
        raise ValueError(f"{len(data)}-byte EMCY is too short for the {fmt} format")
    code = int.from_bytes(data[:2], "little")
    if fmt is not EmcyFormat.CIA301:
        return Emcy(code, None, b"")
    return Emcy(code, ErrorRegister(data[2]), bytes(data[3:FRAME_LENGTH]))


def history_entry(error_code: int, additional: int = 0) -> int:
    """A 1003h entry: EMCY code in bits 0–15, manufacturer "additional information" in 16–31."""
    return (error_code & 0xFFFF) | ((additional & 0xFFFF) << 16)


def split_history_entry(raw: int) -> tuple[int, int]:
    """(EMCY code, additional information) of a 1003h entry."""
    return raw & 0xFFFF, (raw >> 16) & 0xFFFF
