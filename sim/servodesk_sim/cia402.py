"""CiA 402 drive state machine on controlword 6040h / statusword 6041h, as pure functions.

Commands and transition numbers follow MDi-S1-C manual §3.2.2 (figure 3.2); statusword patterns
follow
MDi-S1-C manual §3.2.3 and CiA 402 (bits 0, 1, 2, 3, 5, 6 encode the state).
"""

from __future__ import annotations

from enum import IntEnum

# Controlword 6040h bits (MDi-S1-C manual §3.2.2)
CW_SWITCH_ON = 0x0001
CW_ENABLE_VOLTAGE = 0x0002
CW_QUICK_STOP = 0x0004  # active low: 0 requests a quick stop
CW_ENABLE_OPERATION = 0x0008
CW_NEW_SETPOINT = 0x0010  # PP new set-point, HM start homing, IP enable (mode specific)
CW_CHANGE_IMMEDIATELY = 0x0020  # PP only
CW_RELATIVE = 0x0040  # PP only
CW_FAULT_RESET = 0x0080  # acts on its 0 -> 1 edge only
CW_HALT = 0x0100

# Statusword 6041h bits (MDi-S1-C manual §3.2.3)
SW_READY_TO_SWITCH_ON = 0x0001
SW_SWITCHED_ON = 0x0002
SW_OPERATION_ENABLED = 0x0004
SW_FAULT = 0x0008
SW_VOLTAGE_ENABLED = 0x0010
SW_QUICK_STOP = 0x0020  # active low: 0 while a quick stop is active
SW_SWITCH_ON_DISABLED = 0x0040
SW_WARNING = 0x0080
SW_REMOTE = 0x0200  # "1 canopen 远程控制模式": the controlword is obeyed
SW_TARGET_REACHED = 0x0400
SW_INTERNAL_LIMIT = 0x0800
SW_MODE_BIT12 = 0x1000
SW_MODE_BIT13 = 0x2000
SW_REFERENCE_FOUND = 0x8000  # Kinco manufacturer bit (Kinco manual §5.4.6)

# Transition numbers of CiA 402 figure 3.1 / MDi-S1-C manual figure 3.2
T_SHUTDOWN_FROM_DISABLED = 2
T_SWITCH_ON = 3
T_ENABLE_OPERATION = 4
T_DISABLE_OPERATION = 5
T_SHUTDOWN_FROM_SWITCHED_ON = 6
T_DISABLE_FROM_READY = 7
T_SHUTDOWN_FROM_ENABLED = 8
T_DISABLE_VOLTAGE_FROM_ENABLED = 9
T_DISABLE_FROM_SWITCHED_ON = 10
T_QUICK_STOP = 11
T_QUICK_STOP_TO_DISABLED = 12
T_FAULT = 13
T_FAULT_REACTION_DONE = 14
T_FAULT_RESET = 15
T_QUICK_STOP_TO_ENABLED = 16


class Cia402State(IntEnum):
    NOT_READY_TO_SWITCH_ON = 0
    SWITCH_ON_DISABLED = 1
    READY_TO_SWITCH_ON = 2
    SWITCHED_ON = 3
    OPERATION_ENABLED = 4
    QUICK_STOP_ACTIVE = 5
    FAULT_REACTION_ACTIVE = 6
    FAULT = 7


class Command(IntEnum):
    """Device control commands of MDi-S1-C manual figure 3.2 (bit 7 handled as an edge
    elsewhere)."""

    SHUTDOWN = 1
    SWITCH_ON = 2  # bit 3 = 0: also "disable operation" in Operation enabled
    SWITCH_ON_ENABLE = 3  # bit 3 = 1: "switch on" (3**) or "enable operation" (4, 16)
    DISABLE_VOLTAGE = 4
    QUICK_STOP = 5


class QuickStopOption(IntEnum):
    """605Ah quick stop option code (CiA 402; MDi accepts 1, 2, 5, 6 — MDi-S1-C manual §5.3)."""

    DISABLE_DRIVE = 0
    SLOW_DOWN_RAMP = 1
    QUICK_STOP_RAMP = 2
    CURRENT_LIMIT = 3
    VOLTAGE_LIMIT = 4
    SLOW_DOWN_RAMP_STAY = 5
    QUICK_STOP_RAMP_STAY = 6
    CURRENT_LIMIT_STAY = 7
    VOLTAGE_LIMIT_STAY = 8


def decode_command(controlword: int) -> Command | None:
    """The command a controlword carries, or None (bit 7 set, or no pattern of figure 3.2).

    Every row of figure 3.2 other than fault reset needs bit 7 = 0, so a master that leaves
    the fault-reset bit high cannot enable the drive (a real-world trap the tool explains).
    """
    if controlword & CW_FAULT_RESET:
        return None
    if not controlword & CW_ENABLE_VOLTAGE:
        return Command.DISABLE_VOLTAGE  # 0 X X 0 X
    if not controlword & CW_QUICK_STOP:
        return Command.QUICK_STOP  # 0 X 0 1 X
    if not controlword & CW_SWITCH_ON:
        return Command.SHUTDOWN  # 0 X 1 1 0
    if controlword & CW_ENABLE_OPERATION:
        return Command.SWITCH_ON_ENABLE  # 0 1 1 1 1
    return Command.SWITCH_ON  # 0 0 1 1 1


def quick_stop_stays(option: int) -> bool:
    """True if 605Ah keeps the drive in Quick stop active after the stop (options 5–8)."""
    return QuickStopOption.SLOW_DOWN_RAMP_STAY <= option <= QuickStopOption.VOLTAGE_LIMIT_STAY


_S = Cia402State
_C = Command

# (state, command) -> (next state, transition number), MDi-S1-C manual figure 3.2.
_TABLE: dict[tuple[Cia402State, Command], tuple[Cia402State, int]] = {
    (_S.SWITCH_ON_DISABLED, _C.SHUTDOWN): (_S.READY_TO_SWITCH_ON, T_SHUTDOWN_FROM_DISABLED),
    (_S.READY_TO_SWITCH_ON, _C.SWITCH_ON): (_S.SWITCHED_ON, T_SWITCH_ON),
    # 3**: switch on with bit 3 set runs transition 3 and then 4 without another command.
    (_S.READY_TO_SWITCH_ON, _C.SWITCH_ON_ENABLE): (_S.OPERATION_ENABLED, T_SWITCH_ON),
    (_S.READY_TO_SWITCH_ON, _C.DISABLE_VOLTAGE): (_S.SWITCH_ON_DISABLED, T_DISABLE_FROM_READY),
    (_S.READY_TO_SWITCH_ON, _C.QUICK_STOP): (_S.SWITCH_ON_DISABLED, T_DISABLE_FROM_READY),
    (_S.SWITCHED_ON, _C.SWITCH_ON_ENABLE): (_S.OPERATION_ENABLED, T_ENABLE_OPERATION),
    (_S.SWITCHED_ON, _C.SHUTDOWN): (_S.READY_TO_SWITCH_ON, T_SHUTDOWN_FROM_SWITCHED_ON),
    (_S.SWITCHED_ON, _C.DISABLE_VOLTAGE): (_S.SWITCH_ON_DISABLED, T_DISABLE_FROM_SWITCHED_ON),
    (_S.SWITCHED_ON, _C.QUICK_STOP): (_S.SWITCH_ON_DISABLED, T_DISABLE_FROM_SWITCHED_ON),
    (_S.OPERATION_ENABLED, _C.SWITCH_ON): (_S.SWITCHED_ON, T_DISABLE_OPERATION),
    (_S.OPERATION_ENABLED, _C.SHUTDOWN): (_S.READY_TO_SWITCH_ON, T_SHUTDOWN_FROM_ENABLED),
    (_S.OPERATION_ENABLED, _C.DISABLE_VOLTAGE): (
        _S.SWITCH_ON_DISABLED,
        T_DISABLE_VOLTAGE_FROM_ENABLED,
    ),
    (_S.OPERATION_ENABLED, _C.QUICK_STOP): (_S.QUICK_STOP_ACTIVE, T_QUICK_STOP),
    (_S.QUICK_STOP_ACTIVE, _C.DISABLE_VOLTAGE): (_S.SWITCH_ON_DISABLED, T_QUICK_STOP_TO_DISABLED),
}


def next_state(
    state: Cia402State,
    controlword: int,
    *,
    previous_controlword: int = 0,
    quick_stop_option: int = QuickStopOption.QUICK_STOP_RAMP,
) -> tuple[Cia402State, int | None]:
    """The state after writing `controlword` in `state`, and the transition taken (None: stay).

    Fault reset (15) needs a 0 -> 1 edge of bit 7 against `previous_controlword`; the caller
    still decides whether the faults are gone. Enable operation leaves Quick stop active (16)
    only when 605Ah is 5–8 (CiA 402). Automatic transitions (1, 12 after the ramp, 13, 14) are
    not controlword commands and are the caller's job.
    """
    if state is Cia402State.FAULT:
        edge = controlword & CW_FAULT_RESET and not previous_controlword & CW_FAULT_RESET
        return (Cia402State.SWITCH_ON_DISABLED, T_FAULT_RESET) if edge else (state, None)
    command = decode_command(controlword)
    if command is None:
        return state, None
    if (
        state is Cia402State.QUICK_STOP_ACTIVE
        and command is Command.SWITCH_ON_ENABLE
        and quick_stop_stays(quick_stop_option)
    ):
        return Cia402State.OPERATION_ENABLED, T_QUICK_STOP_TO_ENABLED
    return _TABLE.get((state, command), (state, None))


# Bits 0,1,2,3,5,6 per CiA 402; bit 4 = main circuit charged (every state but "not ready").
_STATUS: dict[Cia402State, int] = {
    Cia402State.NOT_READY_TO_SWITCH_ON: 0x0000,
    Cia402State.SWITCH_ON_DISABLED: SW_SWITCH_ON_DISABLED | SW_VOLTAGE_ENABLED,
    Cia402State.READY_TO_SWITCH_ON: SW_QUICK_STOP | SW_VOLTAGE_ENABLED | SW_READY_TO_SWITCH_ON,
    Cia402State.SWITCHED_ON: (
        SW_QUICK_STOP | SW_VOLTAGE_ENABLED | SW_READY_TO_SWITCH_ON | SW_SWITCHED_ON
    ),
    Cia402State.OPERATION_ENABLED: (
        SW_QUICK_STOP
        | SW_VOLTAGE_ENABLED
        | SW_READY_TO_SWITCH_ON
        | SW_SWITCHED_ON
        | SW_OPERATION_ENABLED
    ),
    Cia402State.QUICK_STOP_ACTIVE: (
        SW_VOLTAGE_ENABLED | SW_READY_TO_SWITCH_ON | SW_SWITCHED_ON | SW_OPERATION_ENABLED
    ),
    Cia402State.FAULT_REACTION_ACTIVE: (
        SW_VOLTAGE_ENABLED
        | SW_READY_TO_SWITCH_ON
        | SW_SWITCHED_ON
        | SW_OPERATION_ENABLED
        | SW_FAULT
    ),
    Cia402State.FAULT: SW_VOLTAGE_ENABLED | SW_FAULT,
}


def statusword_bits(state: Cia402State) -> int:
    """State bits of 6041h plus bit 9 remote (the simulated drives always obey the CAN master)."""
    remote = 0 if state is Cia402State.NOT_READY_TO_SWITCH_ON else SW_REMOTE
    return _STATUS[state] | remote


def decode_state(statusword: int) -> Cia402State:
    """The state a statusword shows (CiA 402 masks 0x4F / 0x6F); inverse of statusword_bits."""
    low = statusword & 0x4F
    if low == 0x00:
        return Cia402State.NOT_READY_TO_SWITCH_ON
    if low == 0x40:
        return Cia402State.SWITCH_ON_DISABLED
    if low == 0x0F:
        return Cia402State.FAULT_REACTION_ACTIVE
    if low == 0x08:
        return Cia402State.FAULT
    by_six = {
        0x21: Cia402State.READY_TO_SWITCH_ON,
        0x23: Cia402State.SWITCHED_ON,
        0x27: Cia402State.OPERATION_ENABLED,
        0x07: Cia402State.QUICK_STOP_ACTIVE,
    }
    state = by_six.get(statusword & 0x6F)
    if state is None:
        raise ValueError(f"statusword {statusword:#06x} shows no CiA 402 state")
    return state
