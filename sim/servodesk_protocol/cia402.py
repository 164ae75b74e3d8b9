"""CiA 402 device control: controlword 6040h commands, statusword 6041h states, modes of
operation 6060h/6061h. Pure builders (`make_*`) and decoders; sending them is the caller's job.

Command patterns and statusword masks follow CiA 402 as the MDi-S1-C CANopen manual §3.2.2
(figure 3.2) and §3.2.3 print them. A controlword travels as 2 bytes little-endian
(`controlword_bytes`), e.g. Kinco servo CANopen manual §5.2 "2B 40 60 00 06 00 00 00".
"""

from __future__ import annotations

from collections.abc import Mapping
from enum import IntEnum
from types import MappingProxyType

CONTROLWORD = 0x6040  # Controlword
STATUSWORD = 0x6041  # Statusword
QUICK_STOP_OPTION = 0x605A  # Quick stop option code
MODES_OF_OPERATION = 0x6060  # Modes of operation
MODES_DISPLAY = 0x6061  # Modes of operation display
SUPPORTED_DRIVE_MODES = 0x6502  # Supported drive modes

# Controlword 6040h bits
CW_SWITCH_ON = 0x0001
CW_ENABLE_VOLTAGE = 0x0002
CW_QUICK_STOP = 0x0004  # active low: 0 requests a quick stop
CW_ENABLE_OPERATION = 0x0008
CW_NEW_SETPOINT = 0x0010  # PP new set-point, HM start homing, IP enable (mode specific)
CW_CHANGE_IMMEDIATELY = 0x0020  # PP only
CW_RELATIVE = 0x0040  # PP only
CW_FAULT_RESET = 0x0080  # acts on its 0 -> 1 edge only
CW_HALT = 0x0100

# Statusword 6041h bits
SW_READY_TO_SWITCH_ON = 0x0001
SW_SWITCHED_ON = 0x0002
SW_OPERATION_ENABLED = 0x0004
SW_FAULT = 0x0008
SW_VOLTAGE_ENABLED = 0x0010
SW_QUICK_STOP = 0x0020  # active low: 0 while a quick stop is active
SW_SWITCH_ON_DISABLED = 0x0040
SW_WARNING = 0x0080
SW_REMOTE = 0x0200  # the drive obeys the controlword ("1 canopen 远程控制模式", MDi §3.2.3)
SW_TARGET_REACHED = 0x0400
SW_INTERNAL_LIMIT = 0x0800
SW_MODE_BIT12 = 0x1000  # PP set-point acknowledge, HM homing attained, IP active
SW_MODE_BIT13 = 0x2000  # PP following error, HM homing error
SW_REFERENCE_FOUND = 0x8000  # Kinco manufacturer bit: homed (Kinco servo CANopen manual §5.4.6)

STATE_MASK = 0x006F  # bits 0–3, 5, 6 encode the state (bit 5 ignored in some states)


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
    """Device control commands a controlword carries (bit 7, fault reset, is an edge apart)."""

    SHUTDOWN = 1
    SWITCH_ON = 2  # bit 3 = 0: also "disable operation" in Operation enabled
    SWITCH_ON_ENABLE = 3  # bit 3 = 1: "switch on" (3**) or "enable operation" (4, 16)
    DISABLE_VOLTAGE = 4
    QUICK_STOP = 5


class QuickStopOption(IntEnum):
    """605Ah quick stop option code (CiA 402; MDi accepts 1, 2, 5, 6 — MDi-S1-C §5.3)."""

    DISABLE_DRIVE = 0
    SLOW_DOWN_RAMP = 1
    QUICK_STOP_RAMP = 2
    CURRENT_LIMIT = 3
    VOLTAGE_LIMIT = 4
    SLOW_DOWN_RAMP_STAY = 5
    QUICK_STOP_RAMP_STAY = 6
    CURRENT_LIMIT_STAY = 7
    VOLTAGE_LIMIT_STAY = 8


class OperationMode(IntEnum):
    """6060h / 6061h values of CiA 402. Negative values are manufacturer-specific."""

    NO_MODE = 0
    PROFILE_POSITION = 1
    VELOCITY = 2
    PROFILE_VELOCITY = 3
    PROFILE_TORQUE = 4
    HOMING = 6
    INTERPOLATED_POSITION = 7
    CYCLIC_SYNC_POSITION = 8
    CYCLIC_SYNC_VELOCITY = 9
    CYCLIC_SYNC_TORQUE = 10


# Short names engineers use, and the 6502h bit announcing the mode (bit 4 is reserved).
MODE_ABBREVIATIONS: Mapping[OperationMode, str] = MappingProxyType(
    {
        OperationMode.NO_MODE: "—",
        OperationMode.PROFILE_POSITION: "PP",
        OperationMode.VELOCITY: "VL",
        OperationMode.PROFILE_VELOCITY: "PV",
        OperationMode.PROFILE_TORQUE: "PT",
        OperationMode.HOMING: "HM",
        OperationMode.INTERPOLATED_POSITION: "IP",
        OperationMode.CYCLIC_SYNC_POSITION: "CSP",
        OperationMode.CYCLIC_SYNC_VELOCITY: "CSV",
        OperationMode.CYCLIC_SYNC_TORQUE: "CST",
    }
)
_SUPPORTED_BIT: Mapping[OperationMode, int] = MappingProxyType(
    {
        OperationMode.PROFILE_POSITION: 0,
        OperationMode.VELOCITY: 1,
        OperationMode.PROFILE_VELOCITY: 2,
        OperationMode.PROFILE_TORQUE: 3,
        OperationMode.HOMING: 5,
        OperationMode.INTERPOLATED_POSITION: 6,
        OperationMode.CYCLIC_SYNC_POSITION: 7,
        OperationMode.CYCLIC_SYNC_VELOCITY: 8,
        OperationMode.CYCLIC_SYNC_TORQUE: 9,
    }
)


def mode_name(value: int) -> str:
    """A 6060h/6061h value in words: "Profile position (PP)", "manufacturer-specific (-3)"."""
    try:
        mode = OperationMode(value)
    except ValueError:
        kind = "manufacturer-specific" if value < 0 else "reserved"
        return f"{kind} ({value})"
    words = mode.name.replace("_", " ").capitalize()
    return words if mode is OperationMode.NO_MODE else f"{words} ({MODE_ABBREVIATIONS[mode]})"


def supported_modes(raw: int) -> frozenset[OperationMode]:
    """The CiA 402 modes a 6502h value announces (manufacturer bits 16–31 are left out)."""
    return frozenset(mode for mode, bit in _SUPPORTED_BIT.items() if raw >> bit & 1)


# ----------------------------------------------------------------------------- controlword


def make_shutdown() -> int:
    """0006h: to Ready to switch on (transitions 2, 6, 8)."""
    return CW_QUICK_STOP | CW_ENABLE_VOLTAGE


def make_switch_on() -> int:
    """0007h: to Switched on (3); in Operation enabled it is "disable operation" (5)."""
    return make_shutdown() | CW_SWITCH_ON


def make_disable_operation() -> int:
    """0007h: Operation enabled -> Switched on (5)."""
    return make_switch_on()


def make_enable_operation(
    *,
    new_setpoint: bool = False,
    change_immediately: bool = False,
    relative: bool = False,
    halt: bool = False,
) -> int:
    """000Fh plus the mode bits: to Operation enabled (4, 16; from Ready to switch on, 3**).

    Bits 4–6 mean what the mode says (PP: new set-point, change immediately, relative; HM: start
    homing; IP: enable interpolation); bit 8 halts the axis in every mode.
    """
    word = make_switch_on() | CW_ENABLE_OPERATION
    word |= CW_NEW_SETPOINT if new_setpoint else 0
    word |= CW_CHANGE_IMMEDIATELY if change_immediately else 0
    word |= CW_RELATIVE if relative else 0
    word |= CW_HALT if halt else 0
    return word


def make_disable_voltage() -> int:
    """0000h: to Switch on disabled (7, 9, 10, 12)."""
    return 0


def make_quick_stop() -> int:
    """0002h: Operation enabled -> Quick stop active (11); elsewhere Switch on disabled."""
    return CW_ENABLE_VOLTAGE


def make_fault_reset() -> int:
    """0080h: Fault -> Switch on disabled (15). The drive acts on the 0 -> 1 edge of bit 7, so
    the previous controlword must have had bit 7 clear (send make_disable_voltage() first)."""
    return CW_FAULT_RESET


def controlword_bytes(controlword: int) -> bytes:
    """The 2 data bytes of 6040h (SDO download data or an RPDO field)."""
    return (controlword & 0xFFFF).to_bytes(2, "little")


def decode_command(controlword: int) -> Command | None:
    """The command a controlword carries, or None (bit 7 set, or no pattern of figure 3.2).

    Every command other than fault reset needs bit 7 = 0, so a master that leaves the
    fault-reset bit high cannot enable the drive (a real-world trap the tool explains).
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


_ENABLE = (make_shutdown(), make_switch_on(), make_enable_operation())
# Controlwords that bring a drive from each state to Operation enabled, one transition each.
_TO_ENABLED: Mapping[Cia402State, tuple[int, ...]] = MappingProxyType(
    {
        Cia402State.NOT_READY_TO_SWITCH_ON: (),  # the drive leaves it by itself (transition 1)
        Cia402State.SWITCH_ON_DISABLED: _ENABLE,
        Cia402State.READY_TO_SWITCH_ON: _ENABLE[1:],
        Cia402State.SWITCHED_ON: _ENABLE[2:],
        Cia402State.OPERATION_ENABLED: (),
        # 12 first: transition 16 back to enabled exists only for 605Ah options 5–8
        Cia402State.QUICK_STOP_ACTIVE: (make_disable_voltage(), *_ENABLE),
        Cia402State.FAULT_REACTION_ACTIVE: (),  # the drive ends it by itself (14)
        Cia402State.FAULT: (make_disable_voltage(), make_fault_reset(), *_ENABLE),
    }
)


def enable_sequence(state: Cia402State) -> tuple[int, ...]:
    """Controlwords, in order, from `state` to Operation enabled; () where the master must wait
    (the drive leaves Not ready / Fault reaction active on its own) or nothing is needed."""
    return _TO_ENABLED[state]


# ----------------------------------------------------------------------------- statusword

# The state bits of each state (bit 4 = voltage enabled, set in every state but "not ready").
_STATUS: Mapping[Cia402State, int] = MappingProxyType(
    {
        Cia402State.NOT_READY_TO_SWITCH_ON: 0x0000,
        Cia402State.SWITCH_ON_DISABLED: SW_SWITCH_ON_DISABLED | SW_VOLTAGE_ENABLED,
        Cia402State.READY_TO_SWITCH_ON: (
            SW_QUICK_STOP | SW_VOLTAGE_ENABLED | SW_READY_TO_SWITCH_ON
        ),
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
)

# CiA 402 masks: 4Fh where bit 5 does not matter, 6Fh where it tells states apart.
_BY_4F: Mapping[int, Cia402State] = MappingProxyType(
    {
        0x00: Cia402State.NOT_READY_TO_SWITCH_ON,
        0x40: Cia402State.SWITCH_ON_DISABLED,
        0x0F: Cia402State.FAULT_REACTION_ACTIVE,
        0x08: Cia402State.FAULT,
    }
)
_BY_6F: Mapping[int, Cia402State] = MappingProxyType(
    {
        0x21: Cia402State.READY_TO_SWITCH_ON,
        0x23: Cia402State.SWITCHED_ON,
        0x27: Cia402State.OPERATION_ENABLED,
        0x07: Cia402State.QUICK_STOP_ACTIVE,
    }
)


def state_bits(state: Cia402State) -> int:
    """The statusword bits 0–6 a drive shows in `state`."""
    return _STATUS[state]


def decode_state(statusword: int) -> Cia402State:
    """The state a statusword shows; ValueError for a pattern that is no CiA 402 state."""
    state = _BY_4F.get(statusword & 0x4F)
    if state is None:
        state = _BY_6F.get(statusword & STATE_MASK)
    if state is None:
        raise ValueError(f"statusword {statusword:#06x} shows no CiA 402 state")
    return state


def statusword_from_bytes(data: bytes) -> int:
    """6041h from its 2 data bytes (SDO upload data or a TPDO field)."""
    if len(data) < 2:
        raise ValueError(f"{len(data)} bytes: a statusword has 2")
    return int.from_bytes(data[:2], "little")
