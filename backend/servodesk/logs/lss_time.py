"""LSS (CiA 305, COB-IDs 7E5h master → slaves, 7E4h slave → master) and TIME (CiA 301
§7.2.6, COB-ID 100h) frames in words. Pure: one frame in, (command specifier or None, text)
out; the decoder makes events of them.
"""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass

from servodesk_protocol import cob_id

TIME_EPOCH = dt.datetime(1984, 1, 1, tzinfo=dt.UTC)  # CiA 301 TIME_OF_DAY: days since then
_MS_MASK = 0x0FFFFFFF  # 28 bits of milliseconds after midnight, 4 reserved
_IDENTITY = ("vendor-ID", "product code", "revision number", "serial number")
_MODES = {0: "waiting", 1: "configuration"}
# CiA 305 bit timing table 0 (standard CiA bit timings), by table index
_BIT_TIMINGS = {
    0: "1000 kbit/s", 1: "800 kbit/s", 2: "500 kbit/s", 3: "250 kbit/s", 4: "125 kbit/s",
    6: "50 kbit/s", 7: "20 kbit/s", 8: "10 kbit/s", 9: "automatic bit rate detection",
}  # fmt: skip
_RESULTS = {
    0x11: {0: "done", 1: "node-ID out of range"},
    0x13: {0: "done", 1: "bit rate not supported"},
    0x17: {0: "done", 1: "store configuration not supported", 2: "storage media access error"},
}


@dataclass(frozen=True, slots=True)
class TimeOfDay:
    days: int  # since 1984-01-01
    ms: int  # after midnight

    @property
    def moment(self) -> dt.datetime:
        return TIME_EPOCH + dt.timedelta(days=self.days, milliseconds=self.ms)

    def text(self) -> str:
        stamp = self.moment.strftime("%Y-%m-%d %H:%M:%S")
        return f"TIME {stamp}.{self.ms % 1000:03d} (day {self.days} since 1984-01-01)"


def time_of_day(data: bytes) -> TimeOfDay | None:
    """The TIME_OF_DAY of a TIME frame (6 bytes), None for another length."""
    if len(data) != 6:
        return None
    ms = int.from_bytes(data[0:4], "little") & _MS_MASK
    return TimeOfDay(int.from_bytes(data[4:6], "little"), ms)


def _u32(data: bytes) -> int:
    return int.from_bytes(data[1:5].ljust(4, b"\0"), "little")


def lss_text(can_id: int, data: bytes) -> tuple[int | None, str]:
    """(command specifier, words) of an LSS frame; who sent it from its COB-ID."""
    master = can_id == cob_id.LSS_MASTER
    who = "LSS master" if master else "LSS slave"
    if not data:
        return None, f"{who}: empty frame"
    cs = data[0]
    b1 = data[1] if len(data) > 1 else 0
    b2 = data[2] if len(data) > 2 else 0
    if cs == 0x04:
        what = f"switch state global → {_MODES.get(b1, f'mode {b1}')}"
    elif cs in _RESULTS and not master:
        name = {0x11: "configure node-ID", 0x13: "configure bit timing", 0x17: "store"}[cs]
        result = _RESULTS[cs].get(b1, f"error {b1}" + (f" (specific {b2})" if b1 == 0xFF else ""))
        what = f"{name}: {result}"
    elif cs == 0x11:
        what = f"configure node-ID {b1}" + (" (unconfigured)" if b1 == 0xFF else "")
    elif cs == 0x13:
        timing = _BIT_TIMINGS.get(b2, f"index {b2}") if b1 == 0 else f"table {b1} index {b2}"
        what = f"configure bit timing {timing}"
    elif cs == 0x15:
        what = f"activate bit timing (switch delay {int.from_bytes(data[1:3], 'little')} ms)"
    elif cs == 0x17:
        what = "store configuration"
    elif 0x40 <= cs <= 0x43:
        what = f"switch state selective, {_IDENTITY[cs - 0x40]} {_u32(data):08X}h"
    elif cs == 0x44:
        what = "switch state selective: done"
    elif 0x46 <= cs <= 0x4B:
        part = ("vendor-ID", "product code", "revision number low", "revision number high",
                "serial number low", "serial number high")[cs - 0x46]  # fmt: skip
        what = f"identify remote slave, {part} {_u32(data):08X}h"
    elif cs == 0x4C:
        what = "identify non-configured remote slave"
    elif cs == 0x4F:
        what = "identify slave: present"
    elif cs == 0x50:
        what = "identify non-configured slave: present"
    elif cs == 0x51:
        fields = f"ID {_u32(data):08X}h, bit check {data[5] if len(data) > 5 else 0}"
        what = f"fastscan ({fields})"
    elif 0x5A <= cs <= 0x5D:
        part = _IDENTITY[cs - 0x5A]
        what = f"inquire {part}" if master else f"{part} {_u32(data):08X}h"
    elif cs == 0x5E:
        what = "inquire node-ID" if master else f"node-ID {b1}"
    else:
        what = f"command specifier {cs:02X}h"
    return cs, f"{who}: {what}"
