"""SDO abort codes (CiA 301 §7.2.4.3.17): one named constant per code and its meaning.

The simulated drives answer with these codes and the app puts the meaning beside the raw code.
Vendors also use codes of their own: an unknown code is described as such, never guessed.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

TOGGLE_NOT_ALTERNATED = 0x05030000
PROTOCOL_TIMED_OUT = 0x05040000
COMMAND_NOT_VALID = 0x05040001
INVALID_BLOCK_SIZE = 0x05040002
INVALID_SEQUENCE = 0x05040003
CRC_ERROR = 0x05040004
OUT_OF_MEMORY = 0x05040005
UNSUPPORTED_ACCESS = 0x06010000
WRITE_ONLY = 0x06010001  # read of a write-only object
READ_ONLY = 0x06010002  # write of a read-only object
NO_OBJECT = 0x06020000
NOT_MAPPABLE = 0x06040041
PDO_LENGTH_EXCEEDED = 0x06040042
PARAMETER_INCOMPATIBLE = 0x06040043
INTERNAL_INCOMPATIBILITY = 0x06040047
HARDWARE_ERROR = 0x06060000
TYPE_MISMATCH = 0x06070010
LENGTH_TOO_HIGH = 0x06070012
LENGTH_TOO_LOW = 0x06070013
NO_SUBINDEX = 0x06090011
INVALID_VALUE = 0x06090030
VALUE_TOO_HIGH = 0x06090031
VALUE_TOO_LOW = 0x06090032
MAX_BELOW_MIN = 0x06090036
NO_SDO_CONNECTION = 0x060A0023
GENERAL_ERROR = 0x08000000
CANNOT_STORE = 0x08000020
LOCAL_CONTROL = 0x08000021
DEVICE_STATE = 0x08000022
NO_OBJECT_DICTIONARY = 0x08000023
NO_DATA = 0x08000024

UNKNOWN_MEANING = "Unknown abort code (vendor-specific or not in CiA 301)"

# Texts as CiA 301 words them (the project's reference tables).
MEANINGS: Mapping[int, str] = MappingProxyType(
    {
        TOGGLE_NOT_ALTERNATED: "Toggle bit not alternated",
        PROTOCOL_TIMED_OUT: "SDO protocol timed out",
        COMMAND_NOT_VALID: "Client/server command specifier not valid or unknown",
        INVALID_BLOCK_SIZE: "Invalid block size (block mode only)",
        INVALID_SEQUENCE: "Invalid sequence number (block mode only)",
        CRC_ERROR: "CRC error (block mode only)",
        OUT_OF_MEMORY: "Out of memory",
        UNSUPPORTED_ACCESS: "Unsupported access to an object",
        WRITE_ONLY: "Attempt to read a write-only object",
        READ_ONLY: "Attempt to write a read-only object",
        NO_OBJECT: "Object does not exist in the object dictionary",
        NOT_MAPPABLE: "Object cannot be mapped to the PDO",
        PDO_LENGTH_EXCEEDED: (
            "The number and length of the objects to be mapped would exceed the PDO length"
        ),
        PARAMETER_INCOMPATIBLE: "General parameter incompatibility reason",
        INTERNAL_INCOMPATIBILITY: "General internal incompatibility in the device",
        HARDWARE_ERROR: "Access failed due to a hardware error",
        TYPE_MISMATCH: "Data type does not match, length of service parameter does not match",
        LENGTH_TOO_HIGH: "Data type does not match, length of service parameter too high",
        LENGTH_TOO_LOW: "Data type does not match, length of service parameter too low",
        NO_SUBINDEX: "Sub-index does not exist",
        INVALID_VALUE: "Invalid value for parameter (download only)",
        VALUE_TOO_HIGH: "Value of parameter written too high (download only)",
        VALUE_TOO_LOW: "Value of parameter written too low (download only)",
        MAX_BELOW_MIN: "Maximum value is less than minimum value",
        NO_SDO_CONNECTION: "Resource not available: SDO connection",
        GENERAL_ERROR: "General error",
        CANNOT_STORE: "Data cannot be transferred or stored to the application",
        LOCAL_CONTROL: (
            "Data cannot be transferred or stored to the application because of local control"
        ),
        DEVICE_STATE: (
            "Data cannot be transferred or stored to the application because of the present "
            "device state"
        ),
        NO_OBJECT_DICTIONARY: (
            "Object dictionary dynamic generation fails or no object dictionary is present"
        ),
        NO_DATA: "No data available",
    }
)


def describe(code: int) -> str:
    """The CiA 301 meaning of `code`; an unknown code says so (callers show the raw hex too)."""
    return MEANINGS.get(code, UNKNOWN_MEANING)
