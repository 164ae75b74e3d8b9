"""The timeline's words as message ids with English templates: an event carries the English
`message` (stored, and the API's stable text) and `message_id` + `params`, which the page looks
up in its `server` catalogue to show the event in the user's language (docs/api.md, "Texts in
the user's language"). The page's English catalogue holds these templates word for word
(tests/backend/test_server_texts.py).

Parameters named `nmt_command`, `nmt_state` and `state` (a CiA 402 state as servodesk names
it) are words the page translates itself; every other parameter is shown as sent (numbers,
object addresses, file names, a bus's own error text).

Imports nothing: `servodesk.events` is a bottom layer."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

EVENT_TEXTS: Mapping[str, str] = MappingProxyType(
    {
        # the bus and the nodes (nodes/registry.py, network/monitor.py)
        "event.bus_connected": "bus connected ({where})",
        "event.bus_error": "bus error: {error}",
        "event.bus_disconnected": "bus disconnected",
        "event.booted": "node {node} booted",
        "event.booted_unscanned": "node {node} booted (not scanned yet)",
        "event.answers_again": "node {node} answers again",
        "event.back": "node {node} is back",
        "event.lost_heartbeat": "node {node} lost: no heartbeat for {limit_ms} ms",
        "event.lost_sdo": "node {node} lost: it stopped answering SDO",
        "event.forgotten": "node {node} forgotten",
        "event.forgotten_moved": "node {node} forgotten (it answers as node {moved_to} now)",
        "event.nmt_sent": "NMT {nmt_command} sent to node {node}",
        "event.nmt_sent_all": "NMT {nmt_command} sent to all nodes",
        # faults and states (faults/service.py, faults/collector.py)
        "event.emcy": "node {node}: {fault}",
        "event.error_reset": "node {node}: error reset (EMCY 0000h)",
        "event.state": "node {node}: {state}",
        "event.state_was": "node {node}: {state} (was {was})",
        "event.fault_reset_ok": "fault reset: node {node} went from Fault to {state}",
        "event.fault_reset_failed": "fault reset sent, but node {node} is still in Fault "
        "(statusword {statusword}): the cause is still present — check the active fault",
        "event.not_in_fault": "node {node} is not in Fault ({state}): nothing to reset",
        "event.not_in_fault_cleared": "node {node} is not in Fault ({state}): nothing to reset; "
        "its last EMCY is no longer active",
        "event.history_cleared": "node {node}: error history 1003h cleared",
        "event.sdo_abort": "node {node} aborted SDO {where}: {abort_code} {meaning}",
        # what the tool wrote (sdo/publish.py, params/, motion/publish.py)
        "event.wrote": "wrote {where} = {value}",
        "event.write_failed": "write {where} = {value} failed: {error}",
        "event.param_set": "set {name} ({where}) of node {node}: {value}",
        "event.param_set_was": "set {name} ({where}) of node {node}: {old} → {value}",
        "event.stored": "node {node}: parameters stored (1010h:01h)",
        "event.defaults_restored": "node {node}: default parameters restored (1011h:01h)",
        "event.dcf_entry": "{file}: wrote {where} {name} = {value}",
        "event.dcf_entry_unnamed": "{file}: wrote {where} = {value}",
        "event.dcf_loaded": "parameter set {file} loaded into node {node}: {written} entries "
        "written",
        "event.dcf_loaded_failed": "parameter set {file} loaded into node {node}: {written} "
        "entries written, {failed} failed",
        "event.pdos_applied": "applied the PDOs of node {node}",
        "event.pdos_changed": "applied PDOs of node {node}: {pdos} changed",
        "event.pdos_unchanged": "applied PDOs of node {node}: nothing changed",
        "event.jog_stopping": "node {node}: {mode} jog stopping ({reason})",
        "event.jog_at_rest": "node {node}: {mode} jog at rest ({reason})",
        # recordings (api/recording.py)
        "event.recording_started": "recording started ({file})",
        "event.recording_stopped": "recording stopped: {frames} frames in {file}",
    }
)

Params = Mapping[str, str | int]


@dataclass(frozen=True, slots=True)
class Said:
    """An event's words: a message id and its parameters; `message` is the English."""

    message_id: str
    params: Params = field(default_factory=dict)

    @property
    def message(self) -> str:
        return EVENT_TEXTS[self.message_id].format(**self.params)


def say(message_id: str, **params: str | int) -> Said:
    """Words for an event; a KeyError here is an id missing from EVENT_TEXTS (a test finds it)."""
    EVENT_TEXTS[message_id].format(**params)  # a missing parameter fails where it is said
    return Said(message_id, params)
