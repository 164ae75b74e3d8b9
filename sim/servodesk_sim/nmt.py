"""NMT slave state machine of a simulated drive (CiA 301 §7.2.8.3; MDi-S1-C CANopen manual §2.3.1,
Nanotec CANopen article NMT).

Pure: it decodes NMT commands and keeps the state. Resets are handed back to the drive, which
reloads its object dictionary and then calls `boot` again.
"""

from __future__ import annotations

from servodesk_protocol import cob_id
from servodesk_protocol.nmt import (
    BOOT_UP,
    STATE_AFTER,
    NmtCommand,
    NmtState,
    make_heartbeat,
    parse_command,
)
from servodesk_sim.frames import Frame


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
        return Frame(cob_id.HEARTBEAT + node_id, make_heartbeat(BOOT_UP))

    def on_command(self, data: bytes, node_id: int) -> NmtCommand | None:
        """Apply an NMT frame (COB-ID 0); returns the command if it was for this node.

        START / STOP / ENTER_PRE_OPERATIONAL change the state here; RESET_NODE and
        RESET_COMMUNICATION put the node back to Initialising and are for the drive to carry out.
        """
        if self._state is NmtState.INITIALISING:
            return None  # still initialising: the node listens to nobody until boot-up
        command = parse_command(data)
        if command is None or not command.addresses(node_id):
            return None
        self._state = STATE_AFTER[command.command]
        return command.command
