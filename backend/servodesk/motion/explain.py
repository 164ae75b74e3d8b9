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
        reasons.append(
            _r(
                "nmt_stopped",
                "the node is NMT Stopped: it answers no SDO and takes no PDO — "
                "set it Pre-operational or Operational",
            )
        )
    elif seen.needs_pdos and seen.nmt_state != "operational":
        reasons.append(
            _r(
                "nmt_not_operational",
                f"the node is NMT {seen.nmt_state or 'unknown'}, "
                "not Operational: it ignores the control PDOs — start it (NMT start)",
            )
        )
    if seen.held_by:
        reasons.append(_r("held_by_other", f"{seen.held_by} controls this axis now"))
    if seen.statusword is not None:
        reasons += _from_words(seen, seen.statusword)
    if not reasons:
        if seen.statusword is None:
            message = "the drive did not answer (no SDO reply): is it powered and on this bus?"
        else:
            message = (
                f"the drive stayed in {_state_text(seen.statusword)} and its objects show no "
                "cause: the transition took longer than the drive's time allows"
            )
        reasons.append(_r("timeout", message))
    return reasons


def _from_words(seen: Observed, status: int) -> list[EnableReason]:
    control = seen.controlword
    reasons: list[EnableReason] = []
    try:
        state: Cia402State | None = decode_state(status)
    except ValueError:
        state = None
    if status & SW_FAULT or state in (Cia402State.FAULT, Cia402State.FAULT_REACTION_ACTIVE):
        reasons.append(_r("fault", _fault_text(seen.fault)))
    if control is not None and control & CW_FAULT_RESET:
        reasons.append(
            _r(
                "fault_reset_high",
                "controlword bit 7 (fault reset) is 1: the drive takes no "
                "command until it is 0 again (fault reset acts on its 0 → 1 edge)",
            )
        )
    if state is Cia402State.NOT_READY_TO_SWITCH_ON:
        reasons.append(_r("not_ready", "the drive is still starting (Not ready to switch on)"))
    elif not status & SW_VOLTAGE_ENABLED:
        reasons.append(
            _r(
                "voltage_disabled",
                "statusword bit 4 (voltage enabled) is 0: main power to the power stage is off",
            )
        )
    if state is Cia402State.QUICK_STOP_ACTIVE or (
        control is not None and not control & CW_QUICK_STOP and control & 0x0002
    ):
        reasons.append(
            _r(
                "quick_stop_active",
                "quick stop is active (statusword bit 5 = 0 or controlword "
                "bit 2 = 0): leave it with disable voltage, then enable again",
            )
        )
    reasons += _mode_reasons(seen)
    if control is not None and control & CW_HALT:
        reasons.append(
            _r("halt_set", "controlword bit 8 (halt) is 1: the axis is held at standstill")
        )
    return reasons


def _mode_reasons(seen: Observed) -> list[EnableReason]:
    asked = seen.mode
    if not asked:
        return []
    if seen.supported is not None and asked not in seen.supported:
        return [
            _r(
                "mode_unsupported",
                f"6060h asks for {mode_name(asked)}, which the drive does not support (6502h)",
            )
        ]
    if seen.mode_display == 0 and asked != OperationMode.NO_MODE:
        return [
            _r(
                "mode_unsupported",
                f"6060h asks for {mode_name(asked)} but 6061h shows 0: the "
                "drive runs no mode (an unsupported value, MDi-S1-C CANopen manual §3.3)",
            )
        ]
    return []


RESET_ON_PURPOSE = "nothing resets it by itself: remove its cause, then send Fault reset"


def _fault_text(fault: FaultInfo | None) -> str:
    if fault is None:
        return f"the drive is in Fault (statusword bit 3); {RESET_ON_PURPOSE}"
    name = f" {fault.name}" if fault.name else ""
    source = f" ({fault.source})" if fault.source else ""
    check = f" — check: {fault.text.rstrip('. ')}" if fault.text else ""
    return (
        f"fault {fault.code_hex}{name}{source} is active (statusword bit 3){check}; "
        f"{RESET_ON_PURPOSE}"
    )


def _state_text(statusword: int) -> str:
    try:
        return state_label(decode_state(statusword))
    except ValueError:
        return f"statusword {statusword:#06x}"


def _r(code: str, message: str) -> EnableReason:
    return EnableReason.model_validate({"code": code, "message": message})
