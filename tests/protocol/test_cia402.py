"""CiA 402 controlword builders (exact bytes), statusword decoding and modes of operation."""

from __future__ import annotations

import pytest

from servodesk_protocol.cia402 import (
    Cia402State,
    Command,
    OperationMode,
    controlword_bytes,
    decode_command,
    decode_state,
    enable_sequence,
    make_disable_operation,
    make_disable_voltage,
    make_enable_operation,
    make_fault_reset,
    make_quick_stop,
    make_shutdown,
    make_switch_on,
    mode_name,
    state_bits,
    statusword_from_bytes,
    supported_modes,
)

S = Cia402State


@pytest.mark.parametrize(
    ("controlword", "data", "command"),
    [
        # MDi-S1-C CANopen manual figure 3.2 rows; Kinco servo CANopen manual §5.2 "06 00"
        (make_shutdown(), "06 00", Command.SHUTDOWN),
        (make_switch_on(), "07 00", Command.SWITCH_ON),
        (make_disable_operation(), "07 00", Command.SWITCH_ON),
        (make_enable_operation(), "0F 00", Command.SWITCH_ON_ENABLE),  # Kinco §5.4.5 "0xf"
        (make_disable_voltage(), "00 00", Command.DISABLE_VOLTAGE),
        (make_quick_stop(), "02 00", Command.QUICK_STOP),
        (make_fault_reset(), "80 00", None),  # an edge, not a state command
        # Kinco §5.4.5 / §5.4.6: 1Fh enables interpolation or starts homing
        (make_enable_operation(new_setpoint=True), "1F 00", Command.SWITCH_ON_ENABLE),
        # MDi-S1-C CANopen manual ch. 6 step 13: "95" = 5Fh, a relative move
        (make_enable_operation(new_setpoint=True, relative=True), "5F 00",
         Command.SWITCH_ON_ENABLE),
        (make_enable_operation(new_setpoint=True, change_immediately=True), "3F 00",
         Command.SWITCH_ON_ENABLE),
        (make_enable_operation(halt=True), "0F 01", Command.SWITCH_ON_ENABLE),
    ],
)  # fmt: skip
def test_builders(controlword: int, data: str, command: Command | None) -> None:
    assert controlword_bytes(controlword) == bytes.fromhex(data)
    assert decode_command(controlword) is command


@pytest.mark.parametrize(
    ("controlword", "command"),
    [
        (0x000E, Command.SHUTDOWN),  # bit 3 does not matter for shutdown
        (0x0004, Command.DISABLE_VOLTAGE),  # 0 X X 0 X
        (0x000B, Command.QUICK_STOP),  # 0 X 0 1 X
        (0x0086, None),  # bit 7 high: no command at all
        (0x008F, None),
    ],
)
def test_decode_command(controlword: int, command: Command | None) -> None:
    assert decode_command(controlword) is command


@pytest.mark.parametrize(
    ("statusword", "state"),
    [
        (0x0000, S.NOT_READY_TO_SWITCH_ON),
        (0x0250, S.SWITCH_ON_DISABLED),
        (0x0270, S.SWITCH_ON_DISABLED),  # bit 5 ignored
        (0x0231, S.READY_TO_SWITCH_ON),
        (0x0233, S.SWITCHED_ON),
        (0x0237, S.OPERATION_ENABLED),  # remote bit 9 set, as the simulated drives show it
        (0x4037, S.OPERATION_ENABLED),  # Kinco servo CANopen manual §5.2 read example
        (0x0617, S.QUICK_STOP_ACTIVE),
        (0x001F, S.FAULT_REACTION_ACTIVE),
        (0x0218, S.FAULT),
        (0x0238, S.FAULT),  # bit 5 ignored
    ],
)
def test_decode_state(statusword: int, state: Cia402State) -> None:
    assert decode_state(statusword) is state


@pytest.mark.parametrize("statusword", [0x0001, 0x0003, 0x0021 | 0x0040, 0x0025])
def test_decode_state_refuses_patterns_of_no_state(statusword: int) -> None:
    with pytest.raises(ValueError, match="no CiA 402 state"):
        decode_state(statusword)


@pytest.mark.parametrize("state", list(Cia402State))
def test_state_bits_decode_to_their_state(state: Cia402State) -> None:
    assert decode_state(state_bits(state)) is state


def test_statusword_from_bytes() -> None:
    assert statusword_from_bytes(bytes.fromhex("37 40")) == 0x4037
    with pytest.raises(ValueError, match="a statusword has 2"):
        statusword_from_bytes(b"\x37")


@pytest.mark.parametrize(
    ("state", "controlwords"),
    [
        (S.SWITCH_ON_DISABLED, [0x06, 0x07, 0x0F]),
        (S.READY_TO_SWITCH_ON, [0x07, 0x0F]),
        (S.SWITCHED_ON, [0x0F]),
        (S.OPERATION_ENABLED, []),
        (S.QUICK_STOP_ACTIVE, [0x00, 0x06, 0x07, 0x0F]),
        (S.FAULT, [0x00, 0x80, 0x06, 0x07, 0x0F]),  # bit 7 low first: reset needs an edge
        (S.NOT_READY_TO_SWITCH_ON, []),  # the drive leaves these by itself
        (S.FAULT_REACTION_ACTIVE, []),
    ],
)
def test_enable_sequence(state: Cia402State, controlwords: list[int]) -> None:
    assert list(enable_sequence(state)) == controlwords


@pytest.mark.parametrize(
    ("value", "name"),
    [
        (0, "No mode"),
        (1, "Profile position (PP)"),
        (3, "Profile velocity (PV)"),
        (4, "Profile torque (PT)"),
        (6, "Homing (HM)"),
        (7, "Interpolated position (IP)"),
        (8, "Cyclic sync position (CSP)"),
        (-3, "manufacturer-specific (-3)"),  # Kinco servo CANopen manual §6: modes -3, -4
        (5, "reserved (5)"),
        (11, "reserved (11)"),
    ],
)
def test_mode_name(value: int, name: str) -> None:
    assert mode_name(value) == name


@pytest.mark.parametrize(
    ("raw", "modes"),
    [
        (0x0000006D, {1, 3, 4, 6, 7}),  # the MDi and Kinco sets: PP, PV, PT, HM, IP
        (0x000003FF, {1, 2, 3, 4, 6, 7, 8, 9, 10}),  # bit 4 reserved
        (0x00030001, {1}),  # manufacturer bits left out
    ],
)
def test_supported_modes(raw: int, modes: set[int]) -> None:
    assert supported_modes(raw) == {OperationMode(mode) for mode in modes}
