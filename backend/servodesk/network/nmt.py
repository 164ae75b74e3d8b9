"""NMT commands (CiA 301 §7.2.8.3.1) and NMT states: the one place canopen's spellings are
translated to the tool's enums (DESIGN rule 4).

The senders block (python-can's send may wait for the adapter): call them off the event loop.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

import canopen

from servodesk.models import NmtCommandName, NmtStateName

# command specifier byte of the NMT frame (COB-ID 000h: [cs, node id])
COMMAND_SPECIFIER: Mapping[NmtCommandName, int] = MappingProxyType(
    {
        NmtCommandName.START: 0x01,
        NmtCommandName.STOP: 0x02,
        NmtCommandName.PRE_OPERATIONAL: 0x80,
        NmtCommandName.RESET_NODE: 0x81,
        NmtCommandName.RESET_COMMUNICATION: 0x82,
    }
)

# the state a node is in right after the command (a reset ends with a boot-up into Pre-op)
STATE_AFTER: Mapping[NmtCommandName, NmtStateName] = MappingProxyType(
    {
        NmtCommandName.START: NmtStateName.OPERATIONAL,
        NmtCommandName.STOP: NmtStateName.STOPPED,
        NmtCommandName.PRE_OPERATIONAL: NmtStateName.PRE_OPERATIONAL,
        NmtCommandName.RESET_NODE: NmtStateName.INITIALISING,
        NmtCommandName.RESET_COMMUNICATION: NmtStateName.INITIALISING,
    }
)

BOOT_UP = 0x00  # heartbeat state byte of the boot-up frame
# heartbeat / node-guarding state byte (bit 7, the guarding toggle, masked off) -> state
_STATE_BYTES: Mapping[int, NmtStateName] = MappingProxyType(
    {
        0x04: NmtStateName.STOPPED,
        0x05: NmtStateName.OPERATIONAL,
        0x7F: NmtStateName.PRE_OPERATIONAL,
    }
)


def state_from_byte(value: int) -> NmtStateName:
    """The NMT state a heartbeat reports; a boot-up means the node is now Pre-operational."""
    value &= 0x7F
    if value == BOOT_UP:
        return NmtStateName.PRE_OPERATIONAL  # boot-up is sent on entering Pre-operational
    return _STATE_BYTES.get(value, NmtStateName.UNKNOWN)


def send_to_node(remote: canopen.RemoteNode, command: NmtCommandName) -> None:
    """Send `command` to one node through its canopen NmtMaster (blocking)."""
    remote.nmt.send_command(COMMAND_SPECIFIER[command])


def send_broadcast(network: canopen.Network, command: NmtCommandName) -> None:
    """Send `command` to every node (node id 0) through the network's NmtMaster (blocking)."""
    network.nmt.send_command(COMMAND_SPECIFIER[command])
