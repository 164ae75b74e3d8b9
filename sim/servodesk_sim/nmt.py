"""NMT slave state machine of a simulated drive (CiA 301 §7.2.8.3; MDi-S1-C manual §2.3.1, Nanotec
article NMT).

Pure: it decodes NMT commands and keeps the state. Resets are handed back to the drive, which
reloads its object dictionary and then calls `boot` again.
"""

from __future__ import annotations

from servodesk_sim.frames import Frame
from servodesk_sim.nmt_state import NmtCommand, NmtState

NMT_FRAME_LENGTH = 2  # [command specifier, node id] (MDi-S1-C manual table 2.6)
BROADCAST = 0  # node id 0 addresses every node (MDi-S1-C manual §2.3.1)
BOOTUP_BASE = 0x700  # boot-up shares the error-control COB-ID 700h+id

_TARGET_STATE = {
    NmtCommand.START: NmtState.OPERATIONAL,
    NmtCommand.STOP: NmtState.STOPPED,
    NmtCommand.ENTER_PRE_OPERATIONAL: NmtState.PRE_OPERATIONAL,
}


class NmtSlave:
    """NMT state of one node: Initialising until boot(), then driven by NMT commands."""

    def __init__(self) -> None:
        self._state = NmtState.INITIALISING

    @property
    def state(self) -> NmtState:
        return self._state

    def boot(self, node_id: int) -> Frame:
        """End of initialisation: the boot-up frame (700h+id, one byte 00), then Pre-operational."""
        self._state = NmtState.PRE_OPERATIONAL
        return Frame(BOOTUP_BASE + node_id, bytes([NmtState.INITIALISING]))

    def on_command(self, data: bytes, node_id: int) -> NmtCommand | None:
        """Apply an NMT frame (COB-ID 0); returns the command if it was for this node.

        START / STOP / ENTER_PRE_OPERATIONAL change the state here; RESET_NODE and
        RESET_COMMUNICATION put the node back to Initialising and are for the drive to carry out.
        """
        if self._state is NmtState.INITIALISING:
            return None  # still initialising: the node listens to nobody until boot-up
        if len(data) != NMT_FRAME_LENGTH or data[1] not in (BROADCAST, node_id):
            return None
        try:
            command = NmtCommand(data[0])
        except ValueError:
            return None  # unknown command specifier: CiA 301 defines no answer, so ignore it
        target = _TARGET_STATE.get(command)
        self._state = NmtState.INITIALISING if target is None else target
        return command
