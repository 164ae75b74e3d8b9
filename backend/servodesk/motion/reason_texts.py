"""The reasons a CiA 402 transition did not happen, as message ids with English templates: a
reason carries the English `message` (the API's stable text) and `message_id` + `params`, which
the page looks up in its `server` catalogue to show the reason in the user's language
(docs/api.md, "Texts in the user's language"). The page's English catalogue holds these
templates word for word (tests/backend/test_server_texts.py)."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from servodesk.models.motion import EnableReason, EnableReasonCode

RESET_ON_PURPOSE = "nothing resets it by itself: remove its cause, then send Fault reset"

# message id -> English template ({name} placeholders, str.format)
REASON_TEXTS: Mapping[str, str] = MappingProxyType(
    {
        "reason.nmt_stopped": "the node is NMT Stopped: it answers no SDO and takes no PDO — "
        "set it Pre-operational or Operational",
        "reason.nmt_not_operational": "the node is NMT {nmt}, not Operational: it ignores the "
        "control PDOs — start it (NMT start)",
        "reason.held_elsewhere": "{holder} controls this axis now",
        "reason.no_answer": "the drive did not answer (no SDO reply): is it powered and on this "
        "bus?",
        "reason.stayed": "the drive stayed in {state} and its objects show no cause: the "
        "transition took longer than the drive's time allows",
        "reason.fault_unknown": "the drive is in Fault (statusword bit 3); " + RESET_ON_PURPOSE,
        "reason.fault": "fault {fault} is active (statusword bit 3); " + RESET_ON_PURPOSE,
        "reason.fault_check": "fault {fault} is active (statusword bit 3) — check: {check}; "
        + RESET_ON_PURPOSE,
        "reason.fault_reset_high": "controlword bit 7 (fault reset) is 1: the drive takes no "
        "command until it is 0 again (fault reset acts on its 0 → 1 edge)",
        "reason.not_ready": "the drive is still starting (Not ready to switch on)",
        "reason.voltage_disabled": "statusword bit 4 (voltage enabled) is 0: main power to the "
        "power stage is off",
        "reason.quick_stop_active": "quick stop is active (statusword bit 5 = 0 or controlword "
        "bit 2 = 0): leave it with disable voltage, then enable again",
        "reason.mode_not_in_6502": "6060h asks for {mode}, which the drive does not support "
        "(6502h)",
        "reason.mode_display_0": "6060h asks for {mode} but 6061h shows 0: the drive runs no mode "
        "(an unsupported value, MDi-S1-C CANopen manual §3.3)",
        "reason.mode_refused": "mode {key} ({number}) is not supported by this drive: the drive "
        "refused it (SDO abort 06090030h)",
        "reason.mode_not_shown": "mode {key} ({number}) is not supported by this drive: 6061h "
        "shows {shown} after 6060h = {number}",
        "reason.halt_set": "controlword bit 8 (halt) is 1: the axis is held at standstill",
        "reason.not_enabled": "the drive is not in Operation enabled: enable it first",
        "reason.setpoint_not_acknowledged": "the drive did not acknowledge the set-point "
        "(statusword bit 12 stayed 0)",
        "reason.ip_not_started": "interpolation did not start (statusword bit 12)",
        "reason.no_transition": "{command} takes no transition from {state}: it works from "
        "{starts}; nothing was sent",
    }
)


def reason(code: EnableReasonCode, message_id: str, **params: str | int) -> EnableReason:
    """A reason in English, with its message id and parameters for the page's catalogue."""
    return EnableReason(
        code=code,
        message=REASON_TEXTS[message_id].format(**params),
        message_id=message_id,
        params=params,
    )
