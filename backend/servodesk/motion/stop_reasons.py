"""Why a jog stopped, as message ids with English templates (the page's `server` catalogue,
docs/api.md "Texts in the user's language").

A reason is a `SaidText` (servodesk.said): the English words every caller already formats into
audit entries, timeline events and errors, that also know their message id, so the reason
travels through the jog, the safety layer and the audit log unchanged and `JogInfo` and the
timeline still carry its id for the page. A reason that adds to another ("…; the stop could not
be sent") keeps the first one's id and parameters as `reason_id` and `reason_*`."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from servodesk.said import Params, SaidText, kept, nested, said

__all__ = ["STOP_TEXTS", "Params", "Reason", "nested", "nested_stop", "said", "then"]

STOP_TEXTS: Mapping[str, str] = MappingProxyType(
    {
        "stop.user": "stopped by the user",
        "stop.replaced": "replaced by a new jog",
        "stop.keepalive": "keep-alive missed for {ms} ms",
        "stop.drive_disabled": "drive disabled",
        "stop.shutting_down": "ServoDesk is shutting down",
        "stop.taken_over": "control taken over by {holder}",
        "stop.released": "control released",
        "stop.drive_command": "drive command: {drive_command}",
        "stop.quick_stop": "quick stop",
        "stop.quick_stop_all": "quick stop (all drives)",
        "stop.page_closed": "the page's connection closed",
        "stop.page_hidden": "the page was hidden",
        "stop.emcy": "EMCY {code}h from the drive",
        "stop.bus": "bus {bus_state}",
        "stop.bus_error": "bus {bus_state}: {error}",
        "stop.heartbeat_lost": "heartbeat lost",
        "stop.restarted": "the drive restarted",
        "stop.test_jog_ended": "the commissioning test jog ended",
        "stop.step_ended": "the commissioning step ended",
        # added to a first reason
        "stop.then_replaced": "{reason}; replaced by a new jog",
        "stop.then_not_sent": "{reason}; the stop could not be sent: the drive's heartbeat "
        "consumer is the backstop, check that the axis stands",
        "stop.then_no_slowdown": "{reason}; quick stop sent: it did not slow down on the halt",
        "stop.then_unread": "{reason}; the speed could not be read while stopping ({error})",
        "stop.then_quick_unsent": "{reason}; still {rpm} rpm and the quick stop could not be "
        "sent ({error})",
        "stop.then_still_moving": "{reason}; still {rpm} rpm {seconds} s after a quick stop",
    }
)


class Reason(SaidText):
    """Why a jog stopped, in English, with its message id and parameters."""

    TEXTS = STOP_TEXTS


def nested_stop(text: str | None, message_id: str | None, params: Params) -> Params:
    """A jog's stop reason as it is kept (JogInfo's words, id and parameters) as the `reason`
    parameters of a text that names it."""
    return kept("reason", text, message_id, params)


def then(first: str, message_id: str, **params: str | int) -> Reason:
    """A reason that adds to `first` ("{reason}; …"), with `params` of its own."""
    return Reason(message_id, **nested("reason", first), **params)
