""" "Why won't it enable?" — what blocks a CiA 402 transition, from the drive's own objects
(pure; DESIGN "Motion safety": name the statusword bit or precondition, not just "timeout").

Causes, in the order a user has to clear them:
- NMT: Stopped answers no SDO at all (MDi-S1-C CANopen manual table 2.8); PDO control needs
  Operational;
- another controller holds the axis (the controller lease);
- a fault (statusword bit 3), named from 603Fh and the profile's fault table (an enable never
  resets it: that is the user's own act, Fault reset);
- controlword bit 7 left high: every command needs it 0, so a master that holds fault reset
  cannot enable;
- voltage not enabled (bit 4): main power is off or the drive is still starting;
- quick stop active (bit 5 = 0 in Operation enabled, or controlword bit 2 = 0);
- an unsupported mode: 6061h shows 0 after 6060h asked for a mode (MDi), or 6060h outside 6502h;
- halt (controlword bit 8): the drive enables but will not move.
"""

from __future__ import annotations

from dataclasses import dataclass

from servodesk.models.motion import EnableReason, FaultInfo
from servodesk.motion.reason_texts import reason
from servodesk.motion.words import state_label
from servodesk_protocol.cia402 import (
    CW_FAULT_RESET,
    CW_HALT,
    CW_QUICK_STOP,
    SW_FAULT,
    SW_VOLTAGE_ENABLED,
    Cia402State,
    OperationMode,
    decode_state,
    mode_name,
)


@dataclass(frozen=True, slots=True)
class Observed:
    """What the drive showed when the transition did not happen."""

    statusword: int | None  # None: unreadable (no SDO answer)
    controlword: int | None
    nmt_state: str  # servodesk.models.nodes.NmtStateName values
    mode: int | None = None  # 6060h
    mode_display: int | None = None  # 6061h
    supported: frozenset[int] | None = None  # 6502h / the profile's modes; None = unknown
    fault: FaultInfo | None = None
    needs_pdos: bool = False  # the axis is commanded through PDOs
    held_by: str | None = None  # another controller's name
    target: Cia402State = Cia402State.OPERATION_ENABLED


def explain(seen: Observed) -> list[EnableReason]:
    """The reasons, most fundamental first; [timeout] when the drive's objects show none."""
    reasons: list[EnableReason] = []
    if seen.nmt_state == "stopped":
        reasons.append(reason("nmt_stopped", "reason.nmt_stopped"))
    elif seen.needs_pdos and seen.nmt_state != "operational":
        nmt = seen.nmt_state or "unknown"
        reasons.append(reason("nmt_not_operational", "reason.nmt_not_operational", nmt=nmt))
    if seen.held_by:
        reasons.append(reason("held_by_other", "reason.held_elsewhere", holder=seen.held_by))
    if seen.statusword is not None:
        reasons += _from_words(seen, seen.statusword)
    if not reasons:
        if seen.statusword is None:
            reasons.append(reason("timeout", "reason.no_answer"))
        else:
            state = _state_text(seen.statusword)
            reasons.append(reason("timeout", "reason.stayed", state=state))
    return reasons


def _from_words(seen: Observed, status: int) -> list[EnableReason]:
    control = seen.controlword
    reasons: list[EnableReason] = []
    try:
        state: Cia402State | None = decode_state(status)
    except ValueError:
        state = None
    if status & SW_FAULT or state in (Cia402State.FAULT, Cia402State.FAULT_REACTION_ACTIVE):
        reasons.append(_fault_reason(seen.fault))
    if control is not None and control & CW_FAULT_RESET:
        reasons.append(reason("fault_reset_high", "reason.fault_reset_high"))
    if state is Cia402State.NOT_READY_TO_SWITCH_ON:
        reasons.append(reason("not_ready", "reason.not_ready"))
    elif not status & SW_VOLTAGE_ENABLED:
        reasons.append(reason("voltage_disabled", "reason.voltage_disabled"))
    if state is Cia402State.QUICK_STOP_ACTIVE or (
        control is not None and not control & CW_QUICK_STOP and control & 0x0002
    ):
        reasons.append(reason("quick_stop_active", "reason.quick_stop_active"))
    reasons += _mode_reasons(seen)
    if control is not None and control & CW_HALT:
        reasons.append(reason("halt_set", "reason.halt_set"))
    return reasons


def _mode_reasons(seen: Observed) -> list[EnableReason]:
    asked = seen.mode
    if not asked:
        return []
    if seen.supported is not None and asked not in seen.supported:
        return [reason("mode_unsupported", "reason.mode_not_in_6502", mode=mode_name(asked))]
    if seen.mode_display == 0 and asked != OperationMode.NO_MODE:
        return [reason("mode_unsupported", "reason.mode_display_0", mode=mode_name(asked))]
    return []


def _fault_reason(fault: FaultInfo | None) -> EnableReason:
    if fault is None:
        return reason("fault", "reason.fault_unknown")
    name = f" {fault.name}" if fault.name else ""
    source = f" ({fault.source})" if fault.source else ""
    named = f"{fault.code_hex}{name}{source}"
    if fault.text:
        return reason("fault", "reason.fault_check", fault=named, check=fault.text.rstrip(". "))
    return reason("fault", "reason.fault", fault=named)


def _state_text(statusword: int) -> str:
    try:
        return state_label(decode_state(statusword))
    except ValueError:
        return f"statusword {statusword:#06x}"
