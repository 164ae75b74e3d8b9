"""Write CAN frames as a pcap file with link type 227 (LINKTYPE_CAN_SOCKETCAN), which Wireshark
and tshark open directly: the same frames a log holds, for an independent second opinion.

Record layout (tcpdump.org LINKTYPE_CAN_SOCKETCAN): CAN id + flags as a 32-bit big-endian
word, data length, 3 padding/reserved bytes, then the data padded to 8 bytes.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable
from pathlib import Path
from typing import BinaryIO

LINKTYPE_CAN_SOCKETCAN = 227
_GLOBAL = struct.Struct("<IHHiIII")  # magic, version 2.4, zone, sigfigs, snaplen, link type
_RECORD = struct.Struct("<IIII")  # seconds, microseconds, captured length, original length
_CAN = struct.Struct(">IB3x8s")  # id + flags, length, pad/res0/res1, data
_MAGIC = 0xA1B2C3D4
_EFF = 0x80000000  # extended frame format flag
_RTR = 0x40000000  # remote transmission request flag
FrameTuple = tuple[float, int, bytes]  # (time s, CAN id, data)
# Wireshark's CANopen fields for what our decoder also reads: NMT, heartbeat, SDO, EMCY
TSHARK_FIELDS = (
    "frame.number",
    "canopen.nmt_ctrl.cd",
    "canopen.nmt_ctrl.node_id",
    "canopen.nmt_guard.state",
    "canopen.sdo.ccs",
    "canopen.sdo.scs",
    "canopen.sdo.main_idx",
    "canopen.sdo.sub_idx",
    "canopen.sdo.abort_code",
    "canopen.em.err_code",
    "canopen.em.err_reg",
)


def tshark_command(tshark: str, pcap: Path) -> list[str]:
    """tshark decoding `pcap` as CANopen, one tab-separated line of TSHARK_FIELDS per frame
    (the CAN dissector hands frames to CANopen only when told to)."""
    command = [tshark, "-r", str(pcap), "-d", "can.subdissector,canopen", "-T", "fields"]
    command += ["-E", "separator=\t", "-E", "occurrence=f"]
    for name in TSHARK_FIELDS:
        command += ["-e", name]
    return command


class PcapWriter:
    """Appends frames to an open binary file; write the header first (done by `open_pcap`)."""

    def __init__(self, out: BinaryIO) -> None:
        self._out = out
        out.write(_GLOBAL.pack(_MAGIC, 2, 4, 0, 0, 0xFFFF, LINKTYPE_CAN_SOCKETCAN))

    def write(
        self, time: float, can_id: int, data: bytes, *, extended: bool = False, rtr: bool = False
    ) -> None:
        seconds = int(time)
        micros = min(round((time - seconds) * 1e6), 999_999)
        word = can_id | (_EFF if extended else 0) | (_RTR if rtr else 0)
        record = _CAN.pack(word, len(data), bytes(data))
        self._out.write(_RECORD.pack(seconds, micros, _CAN.size, _CAN.size) + record)


def write_pcap(path: Path, frames: Iterable[FrameTuple]) -> int:
    """Write `frames` to `path`; returns how many were written."""
    count = 0
    with path.open("wb") as out:
        writer = PcapWriter(out)
        for time, can_id, data in frames:
            writer.write(time, can_id, data)
            count += 1
    return count
