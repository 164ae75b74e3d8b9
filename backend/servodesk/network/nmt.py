"""NMT commands (CiA 301 §7.2.8.3.1) and NMT states: the one place canopen's spellings are
translated to the tool's enums (DESIGN rule 4).

The senders block (python-can's send may wait for the adapter): call them off the event loop.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

import canopen

from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NmtStateName
from servodesk_protocol import nmt
from servodesk_protocol.nmt import NmtCommand, NmtState

# command specifier byte of the NMT frame (COB-ID 000h: [cs, node id])
COMMAND_SPECIFIER: Mapping[NmtCommandName, int] = MappingProxyType(
    {
        NmtCommandName.START: NmtCommand.START,
        NmtCommandName.STOP: NmtCommand.STOP,
        NmtCommandName.PRE_OPERATIONAL: NmtCommand.ENTER_PRE_OPERATIONAL,
        NmtCommandName.RESET_NODE: NmtCommand.RESET_NODE,
        NmtCommandName.RESET_COMMUNICATION: NmtCommand.RESET_COMMUNICATION,
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

BOOT_UP = int(nmt.BOOT_UP)  # heartbeat state byte of the boot-up frame
# heartbeat / node-guarding state (the guarding toggle masked off) -> the tool's state name;
# a boot-up is sent on entering Pre-operational, so it means the node is now Pre-operational
_STATE_NAMES: Mapping[NmtState, NmtStateName] = MappingProxyType(
    {
        NmtState.INITIALISING: NmtStateName.PRE_OPERATIONAL,
        NmtState.STOPPED: NmtStateName.STOPPED,
        NmtState.OPERATIONAL: NmtStateName.OPERATIONAL,
        NmtState.PRE_OPERATIONAL: NmtStateName.PRE_OPERATIONAL,
    }
)


def state_from_byte(value: int) -> NmtStateName:
    """The NMT state a heartbeat reports; a boot-up means the node is now Pre-operational."""
    state = nmt.parse_state(value)
    return NmtStateName.UNKNOWN if state is None else _STATE_NAMES[state]


def send_to_node(remote: canopen.RemoteNode, command: NmtCommandName) -> None:
    """Send `command` to one node through its canopen NmtMaster (blocking)."""
    remote.nmt.send_command(COMMAND_SPECIFIER[command])


def send_broadcast(network: canopen.Network, command: NmtCommandName) -> None:
    """Send `command` to every node (node id 0) through the network's NmtMaster (blocking)."""
    network.nmt.send_command(COMMAND_SPECIFIER[command])
