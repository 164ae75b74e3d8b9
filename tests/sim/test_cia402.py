"""The CiA 402 state machine against MDi-S1-C manual figure 3.2 and CiA 402 statusword patterns."""

from __future__ import annotations

import pytest
from canopen.profiles.p402 import State402

from servodesk_protocol.cia402 import (
    Cia402State,
    Command,
    decode_command,
    decode_state,
    quick_stop_stays,
)
from servodesk_sim.cia402 import next_state, statusword_bits

S = Cia402State

# Every row of MDi-S1-C manual figure 3.2, in every state it names a transition for.
FIGURE_3_2 = [
    # Shutdown 0 X 1 1 0 -> 2, 6, 8
    ("shutdown", S.SWITCH_ON_DISABLED, 0x06, S.READY_TO_SWITCH_ON, 2),
    ("shutdown, bit 3 set", S.SWITCH_ON_DISABLED, 0x0E, S.READY_TO_SWITCH_ON, 2),
    ("shutdown", S.SWITCHED_ON, 0x06, S.READY_TO_SWITCH_ON, 6),
    ("shutdown", S.OPERATION_ENABLED, 0x06, S.READY_TO_SWITCH_ON, 8),
    # Switch on 0 0 1 1 1 -> 3*
    ("switch on", S.READY_TO_SWITCH_ON, 0x07, S.SWITCHED_ON, 3),
    # Switch on 0 1 1 1 1 -> 3** (3 and then 4 without another command)
    ("switch on + enable", S.READY_TO_SWITCH_ON, 0x0F, S.OPERATION_ENABLED, 3),
    # Disable voltage 0 X X 0 X -> 7, 9, 10, 12
    ("disable voltage", S.READY_TO_SWITCH_ON, 0x00, S.SWITCH_ON_DISABLED, 7),
    ("disable voltage", S.OPERATION_ENABLED, 0x00, S.SWITCH_ON_DISABLED, 9),
    ("disable voltage, others set", S.OPERATION_ENABLED, 0x0D, S.SWITCH_ON_DISABLED, 9),
    ("disable voltage", S.SWITCHED_ON, 0x00, S.SWITCH_ON_DISABLED, 10),
    ("disable voltage", S.QUICK_STOP_ACTIVE, 0x00, S.SWITCH_ON_DISABLED, 12),
    # Quick stop 0 X 0 1 X -> 7, 10, 11
    ("quick stop", S.READY_TO_SWITCH_ON, 0x02, S.SWITCH_ON_DISABLED, 7),
    ("quick stop", S.SWITCHED_ON, 0x03, S.SWITCH_ON_DISABLED, 10),
    ("quick stop", S.OPERATION_ENABLED, 0x02, S.QUICK_STOP_ACTIVE, 11),
    ("quick stop, bits 0 and 3 set", S.OPERATION_ENABLED, 0x0B, S.QUICK_STOP_ACTIVE, 11),
    # Disable operation 0 0 1 1 1 -> 5
    ("disable operation", S.OPERATION_ENABLED, 0x07, S.SWITCHED_ON, 5),
    # Enable operation 0 1 1 1 1 -> 4, 16
    ("enable operation", S.SWITCHED_ON, 0x0F, S.OPERATION_ENABLED, 4),
    ("enable operation, mode bits set", S.SWITCHED_ON, 0x1F, S.OPERATION_ENABLED, 4),
]


@pytest.mark.parametrize(("row", "state", "controlword", "expected", "transition"), FIGURE_3_2)
def test_figure_3_2_rows(
    row: str, state: Cia402State, controlword: int, expected: Cia402State, transition: int
) -> None:
    assert next_state(state, controlword) == (expected, transition), row


NO_TRANSITION = [
    (S.SWITCH_ON_DISABLED, 0x07),  # switch on needs Ready to switch on first
    (S.SWITCH_ON_DISABLED, 0x0F),
    (S.SWITCH_ON_DISABLED, 0x02),
    (S.READY_TO_SWITCH_ON, 0x06),
    (S.SWITCHED_ON, 0x07),
    (S.OPERATION_ENABLED, 0x0F),
    (S.OPERATION_ENABLED, 0x8F),  # bit 7 set: no command but fault reset applies
    (S.SWITCHED_ON, 0x86),
    (S.QUICK_STOP_ACTIVE, 0x06),  # Quick stop active leaves only by 12, 16 (or a fault)
    (S.QUICK_STOP_ACTIVE, 0x07),
    (S.FAULT_REACTION_ACTIVE, 0x00),
    (S.FAULT_REACTION_ACTIVE, 0x80),
    (S.FAULT, 0x06),
    (S.FAULT, 0x0F),
    (S.NOT_READY_TO_SWITCH_ON, 0x06),
]


@pytest.mark.parametrize(("state", "controlword"), NO_TRANSITION)
def test_commands_without_a_transition_keep_the_state(state: Cia402State, controlword: int) -> None:
    assert next_state(state, controlword) == (state, None)


@pytest.mark.parametrize(
    ("option", "expected"),
    [
        (1, (S.QUICK_STOP_ACTIVE, None)),
        (2, (S.QUICK_STOP_ACTIVE, None)),
        (5, (S.OPERATION_ENABLED, 16)),
        (6, (S.OPERATION_ENABLED, 16)),
    ],
)
def test_enable_operation_leaves_quick_stop_only_for_options_5_to_8(
    option: int, expected: tuple[Cia402State, int | None]
) -> None:
    assert next_state(S.QUICK_STOP_ACTIVE, 0x0F, quick_stop_option=option) == expected


@pytest.mark.parametrize(
    ("previous", "controlword", "expected"),
    [
        (0x00, 0x80, (S.SWITCH_ON_DISABLED, 15)),  # 0 -> 1 edge: fault reset
        (0x0F, 0x8F, (S.SWITCH_ON_DISABLED, 15)),  # the other bits are "X"
        (0x80, 0x80, (S.FAULT, None)),  # bit 7 held high: no edge
        (0x80, 0x00, (S.FAULT, None)),  # falling edge
        (0x00, 0x06, (S.FAULT, None)),
    ],
)
def test_fault_reset_needs_a_rising_edge_of_bit_7(
    previous: int, controlword: int, expected: tuple[Cia402State, int | None]
) -> None:
    assert next_state(S.FAULT, controlword, previous_controlword=previous) == expected


@pytest.mark.parametrize(
    ("controlword", "command"),
    [
        (0x06, Command.SHUTDOWN),
        (0x07, Command.SWITCH_ON),
        (0x0F, Command.SWITCH_ON_ENABLE),
        (0x00, Command.DISABLE_VOLTAGE),
        (0x05, Command.DISABLE_VOLTAGE),
        (0x02, Command.QUICK_STOP),
        (0x86, None),
        (0x8F, None),
    ],
)
def test_decode_command(controlword: int, command: Command | None) -> None:
    assert decode_command(controlword) is command


STATUSWORDS = [
    (S.NOT_READY_TO_SWITCH_ON, 0x0000),
    (S.SWITCH_ON_DISABLED, 0x0250),
    (S.READY_TO_SWITCH_ON, 0x0231),
    (S.SWITCHED_ON, 0x0233),
    (S.OPERATION_ENABLED, 0x0237),
    (S.QUICK_STOP_ACTIVE, 0x0217),
    (S.FAULT_REACTION_ACTIVE, 0x021F),
    (S.FAULT, 0x0218),
]


@pytest.mark.parametrize(("state", "statusword"), STATUSWORDS)
def test_statusword_patterns(state: Cia402State, statusword: int) -> None:
    assert statusword_bits(state) == statusword
    assert decode_state(statusword) is state


@pytest.mark.parametrize(("state", "statusword"), STATUSWORDS)
def test_python_canopen_reads_the_same_state(state: Cia402State, statusword: int) -> None:
    # An independent master's masks (python-canopen BaseNode402) must agree with ours.
    name = state.name.replace("_", " ")
    matches = [key for key, (mask, value) in State402.SW_MASK.items() if statusword & mask == value]
    assert name in matches


def test_undecodable_statusword_is_rejected() -> None:
    with pytest.raises(ValueError, match="no CiA 402 state"):
        decode_state(0x0001)


@pytest.mark.parametrize(
    ("option", "stays"), [(0, False), (1, False), (2, False), (5, True), (6, True), (8, True)]
)
def test_quick_stop_option_decides_where_it_ends(option: int, stays: bool) -> None:
    assert quick_stop_stays(option) is stays
