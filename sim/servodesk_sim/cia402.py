"""CiA 402 drive state machine of a simulated drive on controlword 6040h / statusword 6041h.

The controlword commands, statusword bits and state patterns are servodesk_protocol.cia402;
this module holds what only a drive does: which transition a command takes in which state
(MDi-S1-C CANopen manual §3.2.2, figure 3.2) and the statusword it then shows.
"""

from __future__ import annotations

from servodesk_protocol.cia402 import (
    CW_FAULT_RESET,
    SW_REMOTE,
    Cia402State,
    Command,
    QuickStopOption,
    decode_command,
    quick_stop_stays,
    state_bits,
)

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


def statusword_bits(state: Cia402State) -> int:
    """State bits of 6041h plus bit 9 remote (the simulated drives always obey the CAN master)."""
    remote = 0 if state is Cia402State.NOT_READY_TO_SWITCH_ON else SW_REMOTE
    return state_bits(state) | remote
