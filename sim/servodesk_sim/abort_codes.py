"""SDO abort codes (CiA 301 §7.2.4.3.17) that the simulated drives send, and the exception
every object-dictionary access raises to make the SDO server answer with one."""

from __future__ import annotations

TOGGLE_NOT_ALTERNATED = 0x05030000
PROTOCOL_TIMED_OUT = 0x05040000
COMMAND_NOT_VALID = 0x05040001
INVALID_BLOCK_SIZE = 0x05040002
INVALID_SEQUENCE = 0x05040003
CRC_ERROR = 0x05040004
OUT_OF_MEMORY = 0x05040005
UNSUPPORTED_ACCESS = 0x06010000
WRITE_ONLY = 0x06010001
READ_ONLY = 0x06010002
NO_OBJECT = 0x06020000
NOT_MAPPABLE = 0x06040041
PDO_LENGTH_EXCEEDED = 0x06040042
PARAMETER_INCOMPATIBLE = 0x06040043
TYPE_MISMATCH = 0x06070010
LENGTH_TOO_HIGH = 0x06070012
LENGTH_TOO_LOW = 0x06070013
NO_SUBINDEX = 0x06090011
INVALID_VALUE = 0x06090030
VALUE_TOO_HIGH = 0x06090031
VALUE_TOO_LOW = 0x06090032
GENERAL_ERROR = 0x08000000
CANNOT_STORE = 0x08000020
DEVICE_STATE = 0x08000022


class SdoAbort(Exception):
    """An object-dictionary access that the SDO server must answer with an abort frame."""

    def __init__(self, code: int, reason: str = "") -> None:
        super().__init__(f"SDO abort {code:#010x}{': ' + reason if reason else ''}")
        self.code = code
        self.reason = reason
