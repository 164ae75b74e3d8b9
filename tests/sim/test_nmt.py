"""NmtSlave: boot-up, NMT commands by node and broadcast, and what it ignores."""

from __future__ import annotations

import pytest

from servodesk_protocol.nmt import NmtCommand, NmtState
from servodesk_sim.frames import frame
from servodesk_sim.nmt import NmtSlave

NODE = 4


def booted() -> NmtSlave:
    slave = NmtSlave()
    slave.boot(NODE)
    return slave


def test_starts_initialising_and_boots_into_pre_operational() -> None:
    slave = NmtSlave()
    before = slave.state
    assert slave.boot(NODE) == frame(0x704, "00")  # Nanotec article boot-up: 700h+id, one byte 00
    assert (before, slave.state) == (NmtState.INITIALISING, NmtState.PRE_OPERATIONAL)


@pytest.mark.parametrize(
    ("data", "command", "state"),
    [
        # MDi-S1-C manual table 2.7: 01 start, 02 stop, 80 pre-operational, 81/82 resets
        ("01 04", NmtCommand.START, NmtState.OPERATIONAL),
        ("02 04", NmtCommand.STOP, NmtState.STOPPED),
        ("80 04", NmtCommand.ENTER_PRE_OPERATIONAL, NmtState.PRE_OPERATIONAL),
        ("81 04", NmtCommand.RESET_NODE, NmtState.INITIALISING),
        ("82 04", NmtCommand.RESET_COMMUNICATION, NmtState.INITIALISING),
        ("01 00", NmtCommand.START, NmtState.OPERATIONAL),  # node 0: broadcast
        ("02 00", NmtCommand.STOP, NmtState.STOPPED),
        ("81 00", NmtCommand.RESET_NODE, NmtState.INITIALISING),
        # not for this node, wrong length or unknown command: ignored
        ("01 05", None, NmtState.PRE_OPERATIONAL),
        ("02 7F", None, NmtState.PRE_OPERATIONAL),
        ("01", None, NmtState.PRE_OPERATIONAL),
        ("01 04 00", None, NmtState.PRE_OPERATIONAL),
        ("", None, NmtState.PRE_OPERATIONAL),
        ("03 04", None, NmtState.PRE_OPERATIONAL),
        ("83 00", None, NmtState.PRE_OPERATIONAL),
    ],
)
def test_command(data: str, command: NmtCommand | None, state: NmtState) -> None:
    slave = booted()
    assert slave.on_command(bytes.fromhex(data), NODE) is command
    assert slave.state is state


@pytest.mark.parametrize(
    ("commands", "state"),
    [
        (["01 04", "02 04"], NmtState.STOPPED),
        (["02 04", "01 04"], NmtState.OPERATIONAL),  # Stopped -> Operational directly
        (["02 00", "80 00"], NmtState.PRE_OPERATIONAL),
        (["01 04", "01 04"], NmtState.OPERATIONAL),
        (["01 04", "80 04"], NmtState.PRE_OPERATIONAL),
    ],
)
def test_transitions(commands: list[str], state: NmtState) -> None:
    slave = booted()
    for data in commands:
        slave.on_command(bytes.fromhex(data), NODE)
    assert slave.state is state


def test_commands_before_boot_up_are_ignored() -> None:
    slave = NmtSlave()
    assert slave.on_command(bytes.fromhex("01 00"), NODE) is None
    assert slave.state is NmtState.INITIALISING


def test_reset_then_boot_again() -> None:
    slave = booted()
    slave.on_command(bytes.fromhex("01 04"), NODE)
    assert slave.on_command(bytes.fromhex("82 04"), NODE) is NmtCommand.RESET_COMMUNICATION
    assert slave.boot(9) == frame(0x709, "00")  # the drive may come back with a new id
    assert slave.state is NmtState.PRE_OPERATIONAL
