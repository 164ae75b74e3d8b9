"""The statusword bit by bit, the CiA 402 state in words, the transition just taken and the
short mode names (pure; on top of servodesk_protocol.cia402).

Bit names follow CiA 402 as MDi-S1-C CANopen manual §3.2.3 prints them; bits 10, 12 and 13 mean
what the mode displayed in 6061h says (§3.4 PP, §3.5 PV, §3.6 PT, §3.7 HM, §3.8 IP).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from servodesk.models.motion import DriveStateName, StatusBit
from servodesk_protocol.cia402 import Cia402State, OperationMode

S = Cia402State

STATE_NAMES: Mapping[Cia402State, DriveStateName] = MappingProxyType(
    {
        S.NOT_READY_TO_SWITCH_ON: "not_ready_to_switch_on",
        S.SWITCH_ON_DISABLED: "switch_on_disabled",
        S.READY_TO_SWITCH_ON: "ready_to_switch_on",
        S.SWITCHED_ON: "switched_on",
        S.OPERATION_ENABLED: "operation_enabled",
        S.QUICK_STOP_ACTIVE: "quick_stop_active",
        S.FAULT_REACTION_ACTIVE: "fault_reaction_active",
        S.FAULT: "fault",
    }
)


def state_label(state: Cia402State) -> str:
    """ "Operation enabled", "Switch on disabled", …"""
    return state.name.replace("_", " ").capitalize()


# Short mode names the API uses; 6060h/6061h values without one are shown as their number.
MODE_KEYS: Mapping[int, str] = MappingProxyType(
    {
        OperationMode.PROFILE_POSITION: "pp",
        OperationMode.VELOCITY: "vl",
        OperationMode.PROFILE_VELOCITY: "pv",
        OperationMode.PROFILE_TORQUE: "pt",
        OperationMode.HOMING: "hm",
        OperationMode.INTERPOLATED_POSITION: "ip",
        OperationMode.CYCLIC_SYNC_POSITION: "csp",
        OperationMode.CYCLIC_SYNC_VELOCITY: "csv",
        OperationMode.CYCLIC_SYNC_TORQUE: "cst",
    }
)
MODE_VALUES: Mapping[str, int] = MappingProxyType({key: value for value, key in MODE_KEYS.items()})


def mode_key(value: int | None) -> str | None:
    """6060h/6061h as a short name: 1 → "pp", 0 → None (no mode), -3 → "-3"."""
    if value is None or value == 0:
        return None
    return MODE_KEYS.get(value, str(value))


# the statusword's bits with the names they have in every mode (10, 12, 13 also by mode below)
STATUSWORD_BIT_NAMES: Mapping[int, str] = MappingProxyType(
    {
        0: "ready to switch on",
        1: "switched on",
        2: "operation enabled",
        3: "fault",
        4: "voltage enabled",
        5: "quick stop (0 = active)",
        6: "switch on disabled",
        7: "warning",
        8: "manufacturer specific",
        9: "remote",
        10: "target reached",
        11: "internal limit active",
        12: "operation mode specific",
        13: "operation mode specific",
        14: "manufacturer specific",
        15: "manufacturer specific",
    }
)
# What bits 10, 12, 13 mean in each mode (CiA 402 §10, MDi-S1-C manual §3.4–§3.8).
_MODE_BITS: Mapping[int, Mapping[int, str]] = MappingProxyType(
    {
        OperationMode.PROFILE_POSITION: {12: "set-point acknowledge", 13: "following error"},
        OperationMode.PROFILE_VELOCITY: {12: "speed (0 = standstill)", 13: "max slippage error"},
        OperationMode.PROFILE_TORQUE: {},
        OperationMode.HOMING: {12: "homing attained", 13: "homing error"},
        OperationMode.INTERPOLATED_POSITION: {12: "interpolation active"},
        OperationMode.CYCLIC_SYNC_POSITION: {12: "target position ignored", 13: "following error"},
    }
)


def status_bits(
    statusword: int, mode_display: int | None, *, reference_found_bit15: bool = False
) -> list[StatusBit]:
    """Every statusword bit with its name in the mode displayed (Kinco bit 15: "reference
    found", Kinco servo CANopen manual §5.4.6)."""
    names = dict(STATUSWORD_BIT_NAMES)
    names.update(_MODE_BITS.get(mode_display or 0, {}))
    if reference_found_bit15:
        names[15] = "reference found"
    return [
        StatusBit(bit=bit, name=names[bit], on=bool(statusword >> bit & 1)) for bit in range(16)
    ]


# A transition's words by id (the page's `server` catalogue, docs/api.md "Texts in the user's
# language"); the English as the API's `last_transition` has always said it.
TRANSITION_TEXTS: Mapping[str, str] = MappingProxyType(
    {
        "transition.drive_ready": "drive ready ({number})",
        "transition.shutdown": "shutdown ({number})",
        "transition.switch_on": "switch on ({number})",
        "transition.switch_on_and_enable": "switch on and enable operation (3, 4)",
        "transition.enable_operation": "enable operation ({number})",
        "transition.disable_operation": "disable operation ({number})",
        "transition.disable_voltage_or_quick_stop": "disable voltage or quick stop ({number})",
        "transition.disable_voltage": "disable voltage ({number})",
        "transition.quick_stop": "quick stop ({number})",
        "transition.quick_stop_ended": "quick stop ended or disable voltage ({number})",
        "transition.fault": "fault ({number})",
        "transition.fault_reaction_completed": "fault reaction completed ({number})",
        "transition.fault_reset": "fault reset ({number})",
        # two readings apart: several steps between them (the states are words the page has)
        "transition.between": "{was} → {state}",
    }
)


@dataclass(frozen=True, slots=True)
class Transition:
    message_id: str
    params: Mapping[str, str | int]

    @property
    def message(self) -> str:
        return TRANSITION_TEXTS[self.message_id].format(**self.params)


def _t(key: str, number: int | None = None) -> Transition:
    return Transition(f"transition.{key}", {} if number is None else {"number": number})


# (from, to) → the CiA 402 transition (MDi-S1-C manual figure 3.2). 3** is switch on with bit 3
# already set: Ready to switch on straight to Operation enabled.
_TRANSITIONS: Mapping[tuple[Cia402State, Cia402State], Transition] = MappingProxyType(
    {
        (S.NOT_READY_TO_SWITCH_ON, S.SWITCH_ON_DISABLED): _t("drive_ready", 1),
        (S.SWITCH_ON_DISABLED, S.READY_TO_SWITCH_ON): _t("shutdown", 2),
        (S.READY_TO_SWITCH_ON, S.SWITCHED_ON): _t("switch_on", 3),
        (S.READY_TO_SWITCH_ON, S.OPERATION_ENABLED): _t("switch_on_and_enable"),
        (S.SWITCHED_ON, S.OPERATION_ENABLED): _t("enable_operation", 4),
        (S.OPERATION_ENABLED, S.SWITCHED_ON): _t("disable_operation", 5),
        (S.SWITCHED_ON, S.READY_TO_SWITCH_ON): _t("shutdown", 6),
        (S.READY_TO_SWITCH_ON, S.SWITCH_ON_DISABLED): _t("disable_voltage_or_quick_stop", 7),
        (S.OPERATION_ENABLED, S.READY_TO_SWITCH_ON): _t("shutdown", 8),
        (S.OPERATION_ENABLED, S.SWITCH_ON_DISABLED): _t("disable_voltage", 9),
        (S.SWITCHED_ON, S.SWITCH_ON_DISABLED): _t("disable_voltage_or_quick_stop", 10),
        (S.OPERATION_ENABLED, S.QUICK_STOP_ACTIVE): _t("quick_stop", 11),
        (S.QUICK_STOP_ACTIVE, S.SWITCH_ON_DISABLED): _t("quick_stop_ended", 12),
        (S.FAULT_REACTION_ACTIVE, S.FAULT): _t("fault_reaction_completed", 14),
        (S.FAULT, S.SWITCH_ON_DISABLED): _t("fault_reset", 15),
        (S.QUICK_STOP_ACTIVE, S.OPERATION_ENABLED): _t("enable_operation", 16),
    }
)


def taken(command: str, number: int) -> Transition:
    """The transition a state machine command took: `command` is its key ("enable_operation")."""
    return _t(command, number)


def transition(before: Cia402State, after: Cia402State) -> Transition | None:
    """The transition from `before` to `after` with its number; None when the state did not
    change; "fault (13)" into Fault reaction active or Fault from anywhere; "… → …" when the
    two states are not neighbours (several steps between two readings)."""
    if before is after:
        return None
    if after in (S.FAULT_REACTION_ACTIVE, S.FAULT) and before not in (
        S.FAULT_REACTION_ACTIVE,
        S.FAULT,
    ):
        return _t("fault", 13)
    named = _TRANSITIONS.get((before, after))
    return named or Transition(
        "transition.between", {"was": state_label(before), "state": state_label(after)}
    )
