"""Motion's domain errors. The routes map them in api/errors.py: EnableBlockedError to 409
{"error": "enable_blocked", "reasons": […], "state": …}, LimitError to 422."""

from __future__ import annotations

from collections.abc import Sequence

from servodesk.errors import InvalidValueError, ServodeskError
from servodesk.models.motion import DriveState, EnableReason


class EnableBlockedError(ServodeskError):
    """A requested state transition did not happen; `reasons` say what on the drive blocks it."""

    def __init__(
        self,
        node: int,
        reasons: Sequence[EnableReason],
        state: DriveState,
        *,
        goal: str = "enable",
    ) -> None:
        self.node = node
        self.reasons = list(reasons)
        self.state = state
        words = "; ".join(reason.message for reason in self.reasons) or "no reason found"
        super().__init__(f"node {node} does not {goal}: {words}")


class LimitError(InvalidValueError):
    """A command outside the node's motion limits; nothing was sent. Its words by id
    (servodesk.errors.ERROR_TEXTS, `error.*`), the numbers formatted as the message shows them."""

    def __init__(self, node: int, message_id: str, **params: str | int) -> None:
        self.node = node
        super().__init__(self.say(message_id, node=node, **params))


class MotionBusyError(ServodeskError):
    """The axis is busy with something that a new command would conflict with."""

    def __init__(self, node: int, message_id: str) -> None:
        self.node = node
        super().__init__(self.say(message_id, node=node))
