"""NMT node control and NMT error control frames (CiA 301 §7.2.8.3): command specifiers, the
state byte of heartbeat / boot-up / node-guarding answers, and their frames' data bytes.

NMT command: COB-ID 000h, [command specifier, node id]; node id 0 addresses every node
(MDi-S1-C CANopen manual §2.3.1 table 2.6, Kinco servo CANopen manual §5.5).
Error control: COB-ID 700h + node id, one byte = state (bit 7 = node-guarding toggle).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import IntEnum
from types import MappingProxyType

COMMAND_LENGTH = 2  # [command specifier, node id]
BROADCAST = 0  # node id 0: every node
GUARD_TOGGLE = 0x80  # bit 7 of a node-guarding answer (MDi-S1-C CANopen manual table 2.11)
STATE_MASK = 0x7F

# error-control objects (CiA 301 §7.5.2.29–§7.5.2.30)
CONSUMER_HEARTBEAT_TIME = 0x1016  # subs 1–n: bits 16–23 the producer's node id, 0–15 time in ms
PRODUCER_HEARTBEAT_TIME = 0x1017  # ms between heartbeats; 0 = no heartbeat
CONSUMER_NODE_SHIFT = 16  # a 1016h entry: node id in bits 16–23, time in ms in bits 0–15
CONSUMER_NODE_MASK = 0xFF
CONSUMER_TIME_MASK = 0xFFFF


def consumer_entry(node_id: int, time_ms: int) -> int:
    """A 1016h sub-value watching `node_id`'s heartbeat for `time_ms` ms (0 for either: the
    entry is unused). Raises ValueError for a node id or time that does not fit its field."""
    if not 0 <= node_id <= CONSUMER_NODE_MASK:
        raise ValueError(f"node id {node_id} does not fit bits 16–23 of a 1016h entry")
    if not 0 <= time_ms <= CONSUMER_TIME_MASK:
        raise ValueError(f"{time_ms} ms does not fit bits 0–15 of a 1016h entry")
    return (node_id << CONSUMER_NODE_SHIFT) | time_ms


def parse_consumer_entry(value: int) -> tuple[int, int]:
    """(node id, time in ms) of a 1016h sub-value; bits 24–31 (reserved) are ignored."""
    return (value >> CONSUMER_NODE_SHIFT) & CONSUMER_NODE_MASK, value & CONSUMER_TIME_MASK


class NmtState(IntEnum):
    """NMT states as the state byte of an error-control frame encodes them."""

    INITIALISING = 0x00  # only ever seen as the boot-up frame
    STOPPED = 0x04
    OPERATIONAL = 0x05
    PRE_OPERATIONAL = 0x7F

    @property
    def allows_sdo(self) -> bool:
        # MDi-S1-C CANopen manual table 2.8: no SDO, PDO, SYNC or EMCY in Stopped
        return self in (NmtState.PRE_OPERATIONAL, NmtState.OPERATIONAL)

    @property
    def allows_pdo(self) -> bool:
        return self is NmtState.OPERATIONAL


BOOT_UP = NmtState.INITIALISING  # the boot-up frame carries state byte 00h


class NmtCommand(IntEnum):
    """Command specifiers of the NMT node-control frame."""

    START = 0x01
    STOP = 0x02
    ENTER_PRE_OPERATIONAL = 0x80
    RESET_NODE = 0x81
    RESET_COMMUNICATION = 0x82


# The state a node is in right after the command; a reset passes through Initialising.
STATE_AFTER: Mapping[NmtCommand, NmtState] = MappingProxyType(
    {
        NmtCommand.START: NmtState.OPERATIONAL,
        NmtCommand.STOP: NmtState.STOPPED,
        NmtCommand.ENTER_PRE_OPERATIONAL: NmtState.PRE_OPERATIONAL,
        NmtCommand.RESET_NODE: NmtState.INITIALISING,
        NmtCommand.RESET_COMMUNICATION: NmtState.INITIALISING,
    }
)


def make_command(command: NmtCommand, node_id: int = BROADCAST) -> bytes:
    """Data of the NMT frame (COB-ID 000h) sending `command` to `node_id` (0 = all nodes)."""
    if not 0 <= node_id <= 127:
        raise ValueError(f"node id {node_id} is outside 0..127")
    return bytes([command, node_id])


@dataclass(frozen=True, slots=True)
class CommandFrame:
    command: NmtCommand
    node_id: int  # 0 = broadcast

    def addresses(self, node_id: int) -> bool:
        return self.node_id in (BROADCAST, node_id)


def parse_command(data: bytes) -> CommandFrame | None:
    """An NMT frame's command; None for a wrong length or an unknown specifier (CiA 301 defines
    no answer to those, so a node ignores them)."""
    if len(data) != COMMAND_LENGTH:
        return None
    try:
        command = NmtCommand(data[0])
    except ValueError:
        return None
    return CommandFrame(command, data[1])


def make_heartbeat(state: NmtState, *, toggle: bool = False) -> bytes:
    """Data of a heartbeat (toggle False), boot-up (state INITIALISING) or guarding answer."""
    return bytes([state | (GUARD_TOGGLE if toggle else 0)])


def parse_state(byte: int) -> NmtState | None:
    """The state an error-control byte reports (toggle masked off); None for an unknown value."""
    try:
        return NmtState(byte & STATE_MASK)
    except ValueError:
        return None
