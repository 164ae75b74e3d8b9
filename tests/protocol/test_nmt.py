"""NMT command frames and the state byte of heartbeat / boot-up / node-guarding frames."""

from __future__ import annotations

import pytest

from servodesk_protocol.nmt import (
    BOOT_UP,
    STATE_AFTER,
    CommandFrame,
    NmtCommand,
    NmtState,
    consumer_entry,
    make_command,
    make_heartbeat,
    parse_command,
    parse_consumer_entry,
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


# 1016h consumer entries: node id in bits 16–23, time in ms in bits 0–15 (CiA 301 §7.5.2.29,
# MDi-S1-C CANopen manual 1016h)
@pytest.mark.parametrize(
    ("node", "ms", "value"),
    [
        (1, 200, 0x000100C8),
        (127, 100, 0x007F0064),
        (126, 65535, 0x007EFFFF),  # the longest time
        (255, 1, 0x00FF0001),  # the whole node field (ids above 127 are not nodes, but fit)
        (5, 0, 0x00050000),  # time 0: entry unused
        (0, 300, 0x0000012C),  # node 0: entry unused
        (0, 0, 0),
    ],
)
def test_consumer_entry_round_trip(node: int, ms: int, value: int) -> None:
    assert consumer_entry(node, ms) == value
    assert parse_consumer_entry(value) == (node, ms)


@pytest.mark.parametrize(
    ("value", "decoded"),
    [
        (0xFF0200FA, (2, 250)),  # reserved bits 24–31 are ignored
        (0x80_7F_0064, (127, 100)),
        (0xFFFFFFFF, (255, 65535)),
    ],
)
def test_parse_consumer_entry_ignores_reserved_bits(value: int, decoded: tuple[int, int]) -> None:
    assert parse_consumer_entry(value) == decoded


@pytest.mark.parametrize(("node", "ms"), [(256, 100), (-1, 100), (1, 65536), (1, -1)])
def test_consumer_entry_refuses_what_does_not_fit(node: int, ms: int) -> None:
    with pytest.raises(ValueError, match="1016h"):
        consumer_entry(node, ms)
