"""A commissioning session recorded from the simulated drives, frame for frame and without
threads: a scripted master talks raw CANopen to `SimDrive`s on an explicit clock, and every
frame on the "bus" (master's and drives') is recorded as (time, CAN id, data).

Nodes 1 mdi-s1c, 2 kinco, 3 cia402. The script: boot-ups; identity reads (expedited), the MDi's
device name (segmented upload); heartbeats on at 100 ms; a segmented download; an aborted write;
NMT start; SYNCs (PDOs); faults injected through 5FF0h:00 (EMCY per format); node 2's
heartbeat switched off (a heartbeat loss); a fault reset on node 3 (error-reset EMCY).
"""

from __future__ import annotations

from pathlib import Path

import can

from servodesk_sim.drive import SimDrive, create_drive
from servodesk_sim.frames import Frame

START = 1_700_000_000.0  # an absolute stamp, as candump writes them
DRIVES = ((1, "mdi-s1c"), (2, "kinco"), (3, "cia402"))
Recorded = tuple[float, int, bytes]


class Session:
    def __init__(self) -> None:
        self.drives: list[SimDrive] = [create_drive(n, p) for n, p in DRIVES]
        self.now = START
        self.frames: list[Recorded] = []
        for drive in self.drives:
            self._record(drive.boot(self.now), drive)

    def _record(self, frames: list[Frame], sender: SimDrive | None) -> None:
        """Put `frames` on the bus; every other drive sees them (and may answer)."""
        for frame in frames:
            self.frames.append((self.now, frame.can_id, bytes(frame.data)))
            self.now += 0.0002  # ~1 frame time at 500 kbit/s
            for drive in self.drives:
                if drive is not sender:
                    self._record(drive.on_frame(frame, self.now), drive)

    def send(self, can_id: int, hex_data: str) -> None:
        self._record([Frame(can_id, bytes.fromhex(hex_data))], None)

    def run(self, seconds: float, *, sync_every: float | None = None) -> None:
        end = self.now + seconds
        next_sync = self.now if sync_every else end + 1
        while self.now < end:
            self.now += 0.001
            if sync_every and self.now >= next_sync:
                self.send(0x080, "")
                next_sync += sync_every
            for drive in self.drives:
                self._record(drive.poll(self.now), drive)

    # ------------------------------------------------------------------ SDO client (raw)

    def upload(self, node: int, index: int, sub: int) -> None:
        self.send(0x600 + node, f"40 {index & 0xFF:02X} {index >> 8:02X} {sub:02X} 00 00 00 00")
        last = self.frames[-1]
        # segmented: request segments until the server sets the c bit
        toggle = 0
        while last[1] == 0x580 + node and last[2][0] >> 5 in (0, 2) and not _upload_done(last):
            self.send(0x600 + node, f"{0x60 | toggle << 4:02X} 00 00 00 00 00 00 00")
            last = self.frames[-1]
            toggle ^= 1

    def download(self, node: int, index: int, sub: int, value: int, size: int) -> None:
        n = (4 - size) << 2
        data = value.to_bytes(size, "little") + bytes(4 - size)
        cmd = 0x23 | n
        self.send(
            0x600 + node,
            f"{cmd:02X} {index & 0xFF:02X} {index >> 8:02X} {sub:02X} {data.hex(' ')}",
        )

    def download_segmented(self, node: int, index: int, sub: int, payload: bytes) -> None:
        head = f"21 {index & 0xFF:02X} {index >> 8:02X} {sub:02X}"
        self.send(0x600 + node, f"{head} {len(payload).to_bytes(4, 'little').hex(' ')}")
        toggle = 0
        for start in range(0, len(payload), 7):
            chunk = payload[start : start + 7]
            last = start + 7 >= len(payload)
            cmd = toggle << 4 | (7 - len(chunk)) << 1 | int(last)
            padded = chunk.ljust(7, bytes(1))
            self.send(0x600 + node, f"{cmd:02X} {padded.hex(' ')}")
            toggle ^= 1


def _upload_done(frame: Recorded) -> bool:
    b0 = frame[2][0]
    if b0 >> 5 == 2:  # initiate response: done when expedited
        return bool(b0 & 0x02)
    return bool(b0 & 0x01)  # segment: c bit


def record() -> list[Recorded]:
    s = Session()
    s.run(0.05)
    for node, _ in DRIVES:
        s.upload(node, 0x1000, 0)  # Device type
        s.upload(node, 0x1018, 1)  # Identity: Vendor-ID
        s.upload(node, 0x1018, 2)  # Identity: Product code
        s.download(node, 0x1017, 0, 100, 2)  # Producer heartbeat time = 100 ms
    s.upload(1, 0x1008, 0)  # Manufacturer device name: segmented
    s.download_segmented(3, 0x6081, 0, (1000).to_bytes(4, "little"))  # Profile velocity
    s.download(1, 0x605A, 0, 3, 2)  # Quick stop option 3: the MDi refuses it (06090030)
    s.upload(3, 0x6041, 0)  # Statusword
    s.send(0x000, "01 00")  # NMT start all
    s.run(0.35, sync_every=0.01)
    s.download(1, 0x5FF0, 0, 4, 4)  # SIM inject: MDi alarm 4 (position deviation)
    s.download(2, 0x5FF0, 0, 0x8611, 4)  # Kinco following error
    s.download(3, 0x5FF0, 0, 0x8611, 4)  # CiA 402 following error
    s.upload(3, 0x6041, 0)  # Statusword: Fault
    s.run(0.25, sync_every=0.01)
    s.download(2, 0x1017, 0, 0, 2)  # node 2's heartbeat off: a heartbeat loss
    s.download(3, 0x6040, 0, 0x80, 2)  # fault reset: the error-reset EMCY
    s.send(0x000, "80 03")  # node 3 to Pre-operational
    s.run(0.6)
    return s.frames


def write_log(frames: list[Recorded], path: Path) -> None:
    """Write with python-can's own writer for the path's suffix (.log, .asc, .blf, .trc)."""
    with can.Logger(path) as writer:
        for time, can_id, data in frames:
            writer.on_message_received(
                can.Message(
                    timestamp=time,
                    arbitration_id=can_id,
                    data=data,
                    is_extended_id=False,
                    channel="can0",
                )
            )
