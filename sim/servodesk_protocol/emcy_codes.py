"""EMCY error codes in words: the CiA 402 drive codes (also the values of 603Fh), the CiA 301
communication codes, the CiA 301 classes an unknown code falls into, and the error register
(1001h) bits. Pure lookups; the layering with a drive's own alarm table is the app's
(servodesk.faults.decode).

Sources (see the project's code tables): CiA 301 §7.2.7.1 classes and 81xx/82xx codes;
IEC 61800-7-201 (= CiA 402) error codes; CiA 301 §7.5.2.2 error register bits.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from types import MappingProxyType

from servodesk_protocol.emcy import ErrorRegister


class CodeSource(StrEnum):
    """Which table named a code (the API's `source`)."""

    VENDOR = "vendor"  # the drive's own alarm table (profile.toml)
    CIA402 = "cia402"
    CIA301 = "cia301"
    UNKNOWN = "unknown"  # in no table: only its class is known


RESET_TEXT = "Error reset / no error"


def _expand(rows: Iterable[tuple[int, int, str] | tuple[int, int, str, int]]) -> dict[int, str]:
    """(first, last, text[, first number]) rows -> {code: text}; a range names each code with
    its number ("Contact {n}": 5441h is contact 1)."""
    out: dict[int, str] = {}
    for first, last, text, *start in rows:
        number = start[0] if start else 1
        for code in range(first, last + 1):
            out[code] = text.format(n=code - first + number) if first != last else text
    return out


# CiA 402 / IEC 61800-7-201 drive error codes (exact codes; ranges expanded)
CIA402_CODES: Mapping[int, str] = MappingProxyType(
    _expand(
        [
            (0x2110, 0x2110, "Short circuit/earth leakage (input)"),
            (0x2120, 0x2120, "Earth leakage (input)"),
            (0x2121, 0x2123, "Earth leakage phase L{n}"),
            (0x2130, 0x2130, "Short circuit (input)"),
            (0x2131, 0x2131, "Short circuit phases L1-L2"),
            (0x2132, 0x2132, "Short circuit phases L2-L3"),
            (0x2133, 0x2133, "Short circuit phases L3-L1"),
            (0x2211, 0x2212, "Internal current no. {n}"),
            (0x2213, 0x2213, "Over-current in ramp function"),
            (0x2214, 0x2214, "Over-current in the sequence"),
            (0x2220, 0x2220, "Continuous over-current (device internal)"),
            (0x2221, 0x2222, "Continuous over-current no. {n}"),
            (0x2230, 0x2230, "Short circuit/earth leakage (device internal)"),
            (0x2240, 0x2240, "Earth leakage (device internal)"),
            (0x2250, 0x2250, "Short circuit (device internal)"),
            (0x2310, 0x2310, "Continuous over-current"),
            (0x2311, 0x2312, "Continuous over-current no. {n}"),
            (0x2320, 0x2320, "Short circuit/earth leakage (motor side)"),
            (0x2330, 0x2330, "Earth leakage (motor side)"),
            (0x2331, 0x2331, "Earth leakage phase U"),
            (0x2332, 0x2332, "Earth leakage phase V"),
            (0x2333, 0x2333, "Earth leakage phase W"),
            (0x2340, 0x2340, "Short circuit (motor side)"),
            (0x2341, 0x2341, "Short circuit phases U-V"),
            (0x2342, 0x2342, "Short circuit phases V-W"),
            (0x2343, 0x2343, "Short circuit phases W-U"),
            (0x2350, 0x2350, "Load level fault (I²t, thermal state)"),
            (0x2351, 0x2351, "Load level warning (I²t, thermal state)"),
            (0x3110, 0x3110, "Mains over-voltage"),
            (0x3111, 0x3113, "Mains over-voltage phase L{n}"),
            (0x3120, 0x3120, "Mains under-voltage"),
            (0x3121, 0x3123, "Mains under-voltage phase L{n}"),
            (0x3130, 0x3130, "Phase failure"),
            (0x3131, 0x3133, "Phase failure L{n}"),
            (0x3134, 0x3134, "Phase sequence"),
            (0x3140, 0x3140, "Mains frequency"),
            (0x3141, 0x3141, "Mains frequency too great"),
            (0x3142, 0x3142, "Mains frequency too small"),
            (0x3210, 0x3210, "DC-link over-voltage"),
            (0x3211, 0x3212, "Over-voltage no. {n}"),
            (0x3220, 0x3220, "DC-link under-voltage"),
            (0x3221, 0x3222, "Under-voltage no. {n}"),
            (0x3230, 0x3230, "Load error"),
            (0x3310, 0x3310, "Output over-voltage"),
            (0x3311, 0x3311, "Output over-voltage phase U"),
            (0x3312, 0x3312, "Output over-voltage phase V"),
            (0x3313, 0x3313, "Output over-voltage phase W"),
            (0x3320, 0x3320, "Armature circuit"),
            (0x3321, 0x3321, "Armature circuit interrupted"),
            (0x3330, 0x3330, "Field circuit"),
            (0x3331, 0x3331, "Field circuit interrupted"),
            (0x4110, 0x4110, "Excess ambient temperature"),
            (0x4120, 0x4120, "Too low ambient temperature"),
            (0x4130, 0x4130, "Temperature supply air"),
            (0x4140, 0x4140, "Temperature air outlet"),
            (0x4210, 0x4210, "Excess temperature device"),
            (0x4220, 0x4220, "Too low temperature device"),
            (0x4300, 0x4300, "Temperature drive"),
            (0x4310, 0x4310, "Excess temperature drive"),
            (0x4320, 0x4320, "Too low temperature drive"),
            (0x4400, 0x4400, "Temperature supply"),
            (0x4410, 0x4410, "Excess temperature supply"),
            (0x4420, 0x4420, "Too low temperature supply"),
            (0x5100, 0x5100, "Supply"),
            (0x5110, 0x5110, "Supply low voltage"),
            (0x5111, 0x5111, "U1 = ±15 V supply"),
            (0x5112, 0x5112, "U2 = +24 V supply"),
            (0x5113, 0x5113, "U3 = +5 V supply"),
            (0x5114, 0x5119, "Supply U{n} (manufacturer-specific)", 4),
            (0x5120, 0x5120, "Supply intermediate circuit"),
            (0x5200, 0x5200, "Control"),
            (0x5210, 0x5210, "Measurement circuit"),
            (0x5220, 0x5220, "Computing circuit"),
            (0x5300, 0x5300, "Operating unit"),
            (0x5400, 0x5400, "Power section"),
            (0x5410, 0x5410, "Output stages"),
            (0x5420, 0x5420, "Chopper"),
            (0x5430, 0x5430, "Input stages"),
            (0x5440, 0x5440, "Contacts"),
            (0x5441, 0x5445, "Contact {n} (manufacturer-specific)"),
            (0x5450, 0x5450, "Fuses"),
            (0x5451, 0x5453, "Fuse S{n} = L{n}"),
            (0x5454, 0x5459, "Fuse S{n} (manufacturer-specific)", 4),
            (0x5500, 0x5500, "Hardware memory"),
            (0x5510, 0x5510, "RAM"),
            (0x5520, 0x5520, "ROM/EPROM"),
            (0x5530, 0x5530, "EEPROM"),
            (0x6010, 0x6010, "Software reset (watchdog)"),
            (0x6301, 0x630F, "Data record no. {n}"),
            (0x6310, 0x6310, "Loss of parameters"),
            (0x6320, 0x6320, "Parameter error"),
            (0x7100, 0x7100, "Power"),
            (0x7110, 0x7110, "Brake chopper"),
            (0x7111, 0x7111, "Failure brake chopper"),
            (0x7112, 0x7112, "Over-current brake chopper"),
            (0x7113, 0x7113, "Protective circuit brake chopper"),
            (0x7120, 0x7120, "Motor"),
            (0x7121, 0x7121, "Motor blocked"),
            (0x7122, 0x7122, "Motor error or commutation malfunction"),
            (0x7123, 0x7123, "Motor tilted"),
            (0x7200, 0x7200, "Measurement circuit"),
            (0x7300, 0x7300, "Sensor"),
            (0x7301, 0x7301, "Tacho fault"),
            (0x7302, 0x7302, "Tacho wrong polarity"),
            (0x7303, 0x7304, "Resolver {n} fault"),
            (0x7305, 0x7307, "Incremental sensor {n} fault"),
            (0x7310, 0x7310, "Speed"),
            (0x7320, 0x7320, "Position"),
            (0x7400, 0x7400, "Computation circuit"),
            (0x7500, 0x7500, "Communication"),
            (0x7510, 0x7510, "Serial interface no. 1"),
            (0x7520, 0x7520, "Serial interface no. 2"),
            (0x7600, 0x7600, "Data storage (external)"),
            (0x8300, 0x8300, "Torque control"),
            (0x8311, 0x8311, "Excess torque"),
            (0x8312, 0x8312, "Difficult start-up"),
            (0x8313, 0x8313, "Standstill torque"),
            (0x8321, 0x8321, "Insufficient torque"),
            (0x8331, 0x8331, "Torque fault"),
            (0x8400, 0x8400, "Velocity speed controller"),
            (0x8500, 0x8500, "Position controller"),
            (0x8600, 0x8600, "Positioning controller"),
            (0x8611, 0x8611, "Following error"),
            (0x8612, 0x8612, "Reference limit"),
            (0x8700, 0x8700, "Sync controller"),
            (0x8800, 0x8800, "Winding controller"),
            (0x8900, 0x8900, "Process data monitoring"),
            (0x8A00, 0x8A00, "Control"),
            (0xF001, 0xF001, "Deceleration"),
            (0xF002, 0xF002, "Sub-synchronous run"),
            (0xF003, 0xF003, "Stroke operation"),
            (0xF004, 0xF004, "Control"),
        ]
    )
)

# CiA 301 §7.2.7.1: the communication and protocol codes it names exactly
CIA301_CODES: Mapping[int, str] = MappingProxyType(
    {
        0x1000: "Generic error",
        0x8110: "CAN overrun (objects lost)",
        0x8120: "CAN in error-passive mode",
        0x8130: "Life guard error or heartbeat error",
        0x8140: "Recovered from bus-off",
        0x8150: "CAN-ID collision",
        0x8210: "PDO not processed due to length error",
        0x8220: "PDO length exceeded",
        0x8230: "DAM MPDO not processed, destination object not available",
        0x8240: "Unexpected SYNC data length",
        0x8250: "RPDO timeout",
    }
)

# CiA 301 classes by the code's high byte (xx00 ranges) and, failing that, its high nibble
_BYTE_CLASSES: Mapping[int, str] = MappingProxyType(
    {
        0x21: "current, device input side",
        0x22: "current inside the device",
        0x23: "current, device output side",
        0x31: "mains voltage",
        0x32: "voltage inside the device",
        0x33: "output voltage",
        0x41: "ambient temperature",
        0x42: "device temperature",
        0x61: "internal software",
        0x62: "user software",
        0x63: "data set",
        0x81: "communication",
        0x82: "protocol error",
        0xF0: "additional functions",
        0xFF: "device specific",
    }
)
_NIBBLE_CLASSES: Mapping[int, str] = MappingProxyType(
    {
        0x1: "generic error",
        0x2: "current",
        0x3: "voltage",
        0x4: "temperature",
        0x5: "device hardware",
        0x6: "device software",
        0x7: "additional modules",
        0x8: "monitoring",
        0x9: "external error",
        0xF: "additional functions",
    }
)

# 1001h bits in words (CiA 301 §7.5.2.2)
ERROR_REGISTER_BITS: tuple[tuple[ErrorRegister, str], ...] = (
    (ErrorRegister.GENERIC, "generic"),
    (ErrorRegister.CURRENT, "current"),
    (ErrorRegister.VOLTAGE, "voltage"),
    (ErrorRegister.TEMPERATURE, "temperature"),
    (ErrorRegister.COMMUNICATION, "communication"),
    (ErrorRegister.DEVICE_PROFILE, "device profile"),
    (ErrorRegister.RESERVED, "reserved bit 6"),
    (ErrorRegister.MANUFACTURER, "manufacturer"),
)


def is_reset(code: int) -> bool:
    """00xxh: "error reset or no error" (CiA 301; python-canopen tests the high byte too)."""
    return code & 0xFF00 == 0


def code_class(code: int) -> str:
    """The CiA 301 class of any EMCY code, most specific first: 0x8130 -> "monitoring /
    communication", 0x5123 -> "device hardware", 0x0000 -> "error reset"."""
    if is_reset(code):
        return "error reset"
    nibble = _NIBBLE_CLASSES.get(code >> 12)
    specific = _BYTE_CLASSES.get(code >> 8)
    if specific is None:
        return nibble or "reserved"
    if nibble is None or code >> 12 == 0xF or specific.startswith(nibble):  # Fxxx: own classes
        return specific
    return f"{nibble} / {specific}"


@dataclass(frozen=True, slots=True)
class CodeText:
    source: CodeSource
    text: str  # what the table says; for an unknown code its class
    code_class: str


def describe(code: int, *, cia402: bool = True) -> CodeText:
    """A CiA EMCY code in words: the CiA 402 table (when the device is a drive), then CiA 301,
    then the class alone ("Unknown monitoring code 0x8F01"): never nothing. `cia402` False
    skips the drive table, whose codes mean other things for CiA 401 I/O devices."""
    cls = code_class(code)
    if is_reset(code):
        return CodeText(CodeSource.CIA301, RESET_TEXT, cls)
    if cia402 and code in CIA402_CODES:
        return CodeText(CodeSource.CIA402, CIA402_CODES[code], cls)
    if code in CIA301_CODES:
        return CodeText(CodeSource.CIA301, CIA301_CODES[code], cls)
    if code >= 0xFF00:  # CiA 301 and CiA 402 leave FFxxh to the manufacturer
        return CodeText(CodeSource.UNKNOWN, f"Manufacturer-specific code 0x{code:04X}", cls)
    return CodeText(CodeSource.UNKNOWN, f"Unknown {cls} code 0x{code:04X}", cls)


def error_register_words(register: int) -> list[str]:
    """The set 1001h bits in words, bit 0 first: 0x21 -> ["generic", "device profile"]."""
    return [words for bit, words in ERROR_REGISTER_BITS if register & bit]
