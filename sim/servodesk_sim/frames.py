"""The frame type every pure core speaks: no python-can objects below the runner."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Frame:
    """One classic CAN frame with an 11-bit identifier (CANopen uses no extended ids here)."""

    can_id: int
    data: bytes = b""
    rtr: bool = False
    # Data length code of a remote frame (RTR frames carry no data but ask for `dlc` bytes).
    dlc: int = 0

    def __post_init__(self) -> None:
        if not 0 <= self.can_id <= 0x7FF:
            raise ValueError(f"CAN id {self.can_id:#x} is not an 11-bit identifier")
        if len(self.data) > 8:
            raise ValueError(f"classic CAN frames carry at most 8 bytes, got {len(self.data)}")

    def __str__(self) -> str:
        if self.rtr:
            return f"{self.can_id:03X} RTR [{self.dlc}]"
        return f"{self.can_id:03X} [{len(self.data)}] {self.data.hex(' ').upper()}"


def frame(can_id: int, hex_bytes: str = "") -> Frame:
    """Build a frame from a hex string such as ``"40 41 60 00 00 00 00 00"`` (tests, tables)."""
    return Frame(can_id, bytes.fromhex(hex_bytes))
