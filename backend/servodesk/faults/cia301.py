"""CiA 301's generic emergency error codes (CiA 301 Table 21, the xx00h heads of each class):
what servodesk_protocol.emcy_codes names exactly (its 81xxh/82xxh codes) plus the class heads
a device sends when it says no more than the class (2000h "Current – generic error").

A code in no table keeps the most specific class it falls into ("Unknown monitoring /
communication code 0x81FD", servodesk_protocol.emcy_codes.describe).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from servodesk_protocol.emcy_codes import CodeSource, CodeText, code_class, describe

# CiA 301 Table 21 (the project's code tables, (b1)): the generic code of each class
GENERIC_CODES: Mapping[int, str] = MappingProxyType(
    {
        0x1000: "Generic error",
        0x2000: "Current – generic error",
        0x2100: "Current, device input side – generic",
        0x2200: "Current inside the device – generic",
        0x2300: "Current, device output side – generic",
        0x3000: "Voltage – generic error",
        0x3100: "Mains voltage – generic",
        0x3200: "Voltage inside the device – generic",
        0x3300: "Output voltage – generic",
        0x4000: "Temperature – generic error",
        0x4100: "Ambient temperature – generic",
        0x4200: "Device temperature – generic",
        0x5000: "Device hardware – generic error",
        0x6000: "Device software – generic error",
        0x6100: "Internal software – generic",
        0x6200: "User software – generic",
        0x6300: "Data set – generic",
        0x7000: "Additional modules – generic error",
        0x8000: "Monitoring – generic error",
        0x8100: "Communication – generic",
        0x8200: "Protocol error – generic",
        0x9000: "External error – generic error",
        0xF000: "Additional functions – generic error",
        0xFF00: "Device specific – generic error",
    }
)


def cia_text(code: int, *, cia402: bool = True) -> CodeText:
    """A CiA EMCY code in words: CiA 402 (for a drive), CiA 301's exact codes, the generic code
    of a class, then the class alone."""
    found = describe(code, cia402=cia402)
    if found.source is CodeSource.UNKNOWN and code in GENERIC_CODES:
        return CodeText(CodeSource.CIA301, GENERIC_CODES[code], code_class(code))
    return found
