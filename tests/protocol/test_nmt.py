"""NMT command frames and the state byte of heartbeat / boot-up / node-guarding frames."""

from __future__ import annotations

import pytest

from servodesk_protocol.nmt import (
    BOOT_UP,
    STATE_AFTER,
    CommandFrame,
    NmtCommand,
    NmtState,
    make_command,
    make_heartbeat,
    parse_command,
    parse_state,
)


@pytest.mark.parametrize(
    ("command", "node", "data"),
    [
        # Kinco servo CANopen manual §5.5: 01 start, 02 stop, 80 pre-operational
        (NmtCommand.START, 1, "01 01"),
        (NmtCommand.STOP, 1, "02 01"),
        (NmtCommand.ENTER_PRE_OPERATIONAL, 0, "80 00"),  # node 0: every node
        (NmtCommand.RESET_NODE, 4, "81 04"),
        (NmtCommand.RESET_COMMUNICATION, 127, "82 7F"),
    ],
)
def test_command_frames(command: NmtCommand, node: int, data: str) -> None:
    assert make_command(command, node) == bytes.fromhex(data)
    assert parse_command(bytes.fromhex(data)) == CommandFrame(command, node)


@pytest.mark.parametrize("data", ["01", "01 01 00", "03 01", "00 00"])
def test_parse_command_ignores_malformed_frames(data: str) -> None:
    assert parse_command(bytes.fromhex(data)) is None


def test_broadcast_addresses_every_node() -> None:
    assert CommandFrame(NmtCommand.START, 0).addresses(5)
    assert CommandFrame(NmtCommand.START, 5).addresses(5)
    assert not CommandFrame(NmtCommand.START, 4).addresses(5)


def test_make_command_refuses_a_node_id_above_127() -> None:
    with pytest.raises(ValueError, match=r"outside 0\.\.127"):
        make_command(NmtCommand.START, 128)


@pytest.mark.parametrize(
    ("state", "toggle", "data"),
    [
        (BOOT_UP, False, "00"),
        (NmtState.STOPPED, False, "04"),
        (NmtState.OPERATIONAL, False, "05"),
        (NmtState.PRE_OPERATIONAL, False, "7F"),
        (NmtState.PRE_OPERATIONAL, True, "FF"),  # node guarding: toggle bit 7
        (NmtState.OPERATIONAL, True, "85"),
    ],
)
def test_error_control_bytes(state: NmtState, toggle: bool, data: str) -> None:
    assert make_heartbeat(state, toggle=toggle) == bytes.fromhex(data)
    assert parse_state(bytes.fromhex(data)[0]) is state


def test_parse_state_of_an_unknown_byte() -> None:
    assert parse_state(0x06) is None


@pytest.mark.parametrize(
    ("command", "state"),
    [
        (NmtCommand.START, NmtState.OPERATIONAL),
        (NmtCommand.STOP, NmtState.STOPPED),
        (NmtCommand.ENTER_PRE_OPERATIONAL, NmtState.PRE_OPERATIONAL),
        (NmtCommand.RESET_NODE, NmtState.INITIALISING),
        (NmtCommand.RESET_COMMUNICATION, NmtState.INITIALISING),
    ],
)
def test_state_after(command: NmtCommand, state: NmtState) -> None:
    assert STATE_AFTER[command] is state


@pytest.mark.parametrize(
    ("state", "sdo", "pdo"),
    [
        (NmtState.PRE_OPERATIONAL, True, False),
        (NmtState.OPERATIONAL, True, True),
        (NmtState.STOPPED, False, False),  # MDi-S1-C CANopen manual table 2.8
    ],
)
def test_services_per_state(state: NmtState, sdo: bool, pdo: bool) -> None:
    assert (state.allows_sdo, state.allows_pdo) == (sdo, pdo)
