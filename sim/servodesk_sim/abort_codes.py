"""The exception every object-dictionary access of a simulated drive raises to make the SDO
server answer with an abort frame. The codes themselves are in servodesk_protocol.sdo_abort."""

from __future__ import annotations


class SdoAbort(Exception):
    """An object-dictionary access that the SDO server must answer with an abort frame."""

    def __init__(self, code: int, reason: str = "") -> None:
        super().__init__(f"SDO abort {code:#010x}{': ' + reason if reason else ''}")
        self.code = code
        self.reason = reason
