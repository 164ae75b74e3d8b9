"""Domain errors. Services raise these; the API maps them to HTTP in one place (api/errors.py)
and the CLI prints them. Every SDO abort keeps its raw code beside the words."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from types import MappingProxyType

from servodesk.pdo_problems import Problem
from servodesk.sdo_aborts import abort_meaning

_WHERE = re.compile(r"[0-9A-F]{4}h:[0-9A-F]{2}h")
# the errors the page shows in the user's language, by id (docs/api.md, "Texts in the user's
# language"); the page's English catalogue holds them word for word
ERROR_TEXTS: Mapping[str, str] = MappingProxyType(
    {
        "error.no_answer_read": "node {node}: no answer to read {where}",
        "error.no_answer_write": "node {node}: no answer to write {where}",
        "error.node_not_found": "node {node} is not known; scan the bus first",
        "error.node_stopped": "node {node} is Stopped: SDO is not available in that state — set "
        "it Pre-operational or Operational",
        "error.bus_not_connected": "the CAN bus is not connected",
        "error.interrupted": "node {node}: the connection to it was renewed (bus reconnected or "
        "node moved) while the request waited; nothing was sent — send the request again",
        "error.interrupted_by_stop": "node {node}: a stop went to the drive during '{what}', "
        "before its first write; nothing was sent — send the request again",
        # motion (servodesk.motion): limits, a busy axis, another client's control, a jog
        "error.speed_above_drive": "node {node}: {rpm} rpm is above the drive's own limit "
        "{limit} rpm; nothing was sent",
        "error.torque_above_drive": "node {node}: {pct} % is above the drive's max torque "
        "{limit} % (6072h); nothing was sent",
        "error.travel_empty": "node {node}: travel limits {low} … {high} rev are empty; nothing "
        "was sent",
        "error.speed_beyond": "node {node}: {rpm} rpm is beyond the speed limit of {limit} rpm; "
        "nothing was sent",
        "error.torque_beyond": "node {node}: {pct} % is beyond the torque limit of {limit} %; "
        "nothing was sent",
        "error.travel_outside": "node {node}: target {target} rev is outside the travel limits "
        "{low} … {high} rev; nothing was sent",
        "error.path_too_fast": "node {node}: the path peaks at {rpm} rpm, beyond {limit} rpm; "
        "nothing was sent",
        "error.setpoint_held": "node {node}: the drive still holds the previous set-point (bit 12)",
        "error.no_jog": "node {node}: no jog is running: start one first",
        "error.controlled_elsewhere": "node {node} is controlled by {holder}: take over control "
        "first (POST /api/nodes/{node}/drive/controller with take_over)",
        "error.jog_stopped": "jog {jog_id} on node {node} was stopped ({reason}); start a new "
        "jog to move again",
    }
)


class ServodeskError(Exception):
    """Base class: a failure a user can understand and act on. An error whose words the page
    can show in the user's language says them by id (`message_id`, `params`: ERROR_TEXTS)."""

    message_id: str | None = None
    params: dict[str, str | int]

    def say(self, message_id: str, **params: str | int) -> str:
        """The English of `message_id` (ERROR_TEXTS), remembered with its id and parameters."""
        self.message_id = message_id
        self.params = params
        return ERROR_TEXTS[message_id].format(**params)

    def said(self) -> tuple[str | None, dict[str, str | int]]:
        return self.message_id, getattr(self, "params", {})


class SdoAbortError(ServodeskError):
    """The drive refused an SDO transfer with an abort code (CiA 301 §7.2.4.3.17)."""

    def __init__(self, code: int, node_id: int, index: int, subindex: int) -> None:
        self.code = code
        self.node_id = node_id
        self.index = index
        self.subindex = subindex
        self.meaning = abort_meaning(code)
        super().__init__(
            f"node {node_id} {index:04X}h:{subindex:02X}h: SDO abort {code:#010x} ({self.meaning})"
        )

    @property
    def code_hex(self) -> str:
        return f"0x{self.code:08X}"


class CommTimeoutError(ServodeskError):
    """No answer from the node in time (it may be off, at another bitrate or another node id)."""

    def __init__(self, node_id: int, what: str) -> None:
        self.node_id = node_id
        verb, _, where = what.partition(" ")
        if verb in ("read", "write") and _WHERE.fullmatch(where):  # a session's own exchange
            super().__init__(self.say(f"error.no_answer_{verb}", node=node_id, where=where))
        else:
            super().__init__(f"node {node_id}: no answer to {what}")


class SdoProtocolError(CommTimeoutError):
    """The node answered, but not as the transfer expects (a segment with the wrong toggle bit,
    another command, another object's answer): the transfer was aborted. A subclass of
    CommTimeoutError so every caller handles it like a failed exchange; its message names the
    cause instead of claiming that nothing came back."""

    def __init__(self, node_id: int, what: str, detail: str) -> None:
        super().__init__(node_id, what)
        self.message_id = None  # its words are the cause's, in English only
        self.detail = detail
        self.args = (f"node {node_id}: {what} failed: {detail}; the transfer was aborted",)


class NodeNotFoundError(ServodeskError):
    def __init__(self, node_id: int) -> None:
        self.node_id = node_id
        super().__init__(self.say("error.node_not_found", node=node_id))


class NodeStoppedError(ServodeskError):
    """The node is in NMT Stopped, where SDO is not available (MDi-S1-C manual table 2.8)."""

    def __init__(self, node_id: int) -> None:
        self.node_id = node_id
        super().__init__(self.say("error.node_stopped", node=node_id))


class RequestInterruptedError(ServodeskError):
    """A request waited for a node whose connection was renewed (bus reconnect, node moved),
    or a stop cut in before its first write (`stopped_during`: what the request was)."""

    def __init__(self, node_id: int, *, stopped_during: str | None = None) -> None:
        self.node_id = node_id
        if stopped_during is None:
            super().__init__(self.say("error.interrupted", node=node_id))
        else:
            said = self.say("error.interrupted_by_stop", node=node_id, what=stopped_during)
            super().__init__(said)


class BusNotConnectedError(ServodeskError):
    def __init__(self, detail: str | None = None) -> None:
        super().__init__(detail or self.say("error.bus_not_connected"))


class BusOpenError(ServodeskError):
    """The bus asked for could not be opened; the bus that was connected stays connected."""


class InvalidValueError(ServodeskError):
    """User input that cannot be written (wrong type, out of range, unknown parameter)."""


class ConfirmationRequiredError(ServodeskError):
    """An action that changes stored drive data needs an explicit confirmation."""


class IdentityMismatchError(ConfirmationRequiredError):
    """A file made for another device (vendor, product or device type differ) needs confirm."""


class PdoInvalidError(InvalidValueError):
    """A PDO configuration that validation refused; nothing was written."""

    def __init__(self, node_id: int, problems: Sequence[Problem]) -> None:
        self.node_id = node_id
        self.problems = tuple(problems)
        first = self.problems[0].message if self.problems else "invalid configuration"
        more = f" (and {len(self.problems) - 1} more)" if len(self.problems) > 1 else ""
        super().__init__(f"node {node_id}: {first}{more}; nothing was written")


class PdoApplyError(ServodeskError):
    """A PDO change the device refused part-way (or read back differently). `step` names the
    write or read that failed; `restored` says whether the previous configuration is back."""

    def __init__(
        self,
        node_id: int,
        step: str,
        *,
        abort_code: int | None,
        detail: str,
        restored: bool,
    ) -> None:
        self.node_id = node_id
        self.step = step
        self.abort_code = abort_code
        self.restored = restored
        outcome = (
            "the previous PDO configuration was restored"
            if restored
            else "restoring the previous PDO configuration failed too: read the PDOs again"
        )
        super().__init__(f"node {node_id}: {step} failed: {detail}; {outcome}")

    @property
    def code_hex(self) -> str | None:
        return None if self.abort_code is None else f"0x{self.abort_code:08X}"


class ForbiddenError(ServodeskError):
    """What the acting user's role may not do, where the route alone cannot tell (403
    forbidden, as the access guard answers): the message names the role it needs."""

    def __init__(self, message: str, *, role: str, required: str) -> None:
        super().__init__(message)
        self.role = role
        self.required = required


class NotFoundError(ServodeskError):
    """Something the URL names does not exist (a decoded log); `kind` is the API's error kind."""

    def __init__(self, kind: str, message: str) -> None:
        self.kind = kind
        super().__init__(message)


class StateConflictError(ServodeskError):
    """The request does not fit the current state (stopping a recording when none runs)."""

    def __init__(self, kind: str, message: str) -> None:
        self.kind = kind
        super().__init__(message)


class CaptureNotFoundError(NotFoundError):
    """No scope capture with this id (deleted, or never made); the API answers 404."""

    def __init__(self, capture_id: int) -> None:
        self.capture_id = capture_id
        super().__init__("capture_not_found", f"no scope capture {capture_id}")


class ScopeViewerError(ServodeskError):
    """The embedded rerun viewer (its web and gRPC server) could not be started or reached."""
