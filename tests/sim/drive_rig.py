"""A whole simulated drive on a fake clock: send frames, advance time, read what it said."""

from __future__ import annotations

from servodesk_sim.drive import SimDrive, create_drive
from servodesk_sim.frames import Frame, frame

SAVE = 0x65766173  # "save" (1010h)
LOAD = 0x64616F6C  # "load" (1011h)


class DriveRig:
    def __init__(self, node_id: int, profile: str, *, bus_bitrate: int | None = None) -> None:
        self.drive: SimDrive = create_drive(node_id, profile, bus_bitrate=bus_bitrate)
        self.now = 0.0
        self.boot_frames = self.drive.boot(self.now)

    def send(self, can_id: int, hex_bytes: str = "") -> list[Frame]:
        return self.drive.on_frame(frame(can_id, hex_bytes), self.now)

    def rtr(self, can_id: int) -> list[Frame]:
        return self.drive.on_frame(Frame(can_id, rtr=True, dlc=1), self.now)

    def advance(self, seconds: float, step: float = 0.001) -> list[Frame]:
        """Poll every `step` for `seconds`; everything the drive sent meanwhile."""
        out: list[Frame] = []
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.now = round(self.now + step, 9)
            out += self.drive.poll(self.now)
        return out

    def sdo(self, request: str) -> str:
        """One SDO request to the drive's current node id; its single answer as hex."""
        node = self.drive.node_id
        replies = [f for f in self.send(0x600 + node, request) if f.can_id == 0x580 + node]
        if len(replies) != 1:
            raise AssertionError(f"expected one SDO answer to {request}, got {replies}")
        return replies[0].data.hex(" ").upper()

    def write(self, index: int, sub: int, value: int, size: int) -> str:
        command = {1: 0x2F, 2: 0x2B, 3: 0x27, 4: 0x23}[size]
        data = bytes([command, index & 0xFF, index >> 8, sub]) + value.to_bytes(4, "little")
        return self.sdo(data.hex())

    def write_ok(self, index: int, sub: int, value: int, size: int) -> None:
        answer = self.write(index, sub, value, size)
        if not answer.startswith("60"):
            raise AssertionError(f"write {index:04X}h:{sub} = {value:#x} refused: {answer}")

    def read(self, index: int, sub: int = 0) -> int:
        answer = bytes.fromhex(
            self.sdo(f"40 {index & 0xFF:02X} {index >> 8:02X} {sub:02X} 00 00 00 00")
        )
        if answer[0] == 0x80:
            raise AssertionError(f"read {index:04X}h:{sub} aborted: {answer.hex(' ')}")
        size = 4 - ((answer[0] >> 2) & 3)
        return int.from_bytes(answer[4 : 4 + size], "little")

    def nmt(self, command: int, node: int | None = None) -> list[Frame]:
        target = self.drive.node_id if node is None else node
        return self.send(0x000, f"{command:02X} {target:02X}")
