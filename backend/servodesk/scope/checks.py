"""What a capture request must satisfy beyond its schema, and the refusals in words."""

from __future__ import annotations

from collections.abc import Sequence

from servodesk.errors import InvalidValueError, ServodeskError
from servodesk.models.scope import CaptureRequest
from servodesk.scope.run import SILENT_S
from servodesk.scope.trigger import parse_state


class SilentSignalsError(ServodeskError):
    """Signals that never sent a sample: the capture cannot go on (or ever trigger)."""

    def __init__(self, labels: Sequence[str], states: dict[int, str]) -> None:
        nmt = ", ".join(f"node {node} {state}" for node, state in sorted(states.items()))
        super().__init__(
            f"no samples from {', '.join(labels)} in {SILENT_S:g} s (NMT: {nmt}): check that"
            " the node is Operational, receives SYNC and keeps the scope's TPDOs"
        )


def check_request(request: CaptureRequest) -> None:
    """What the schema cannot say: the fields each trigger needs, pre-trigger inside the
    capture (InvalidValueError in words)."""
    trigger = request.trigger
    missing = {
        "level": trigger.node is None or trigger.index is None or trigger.level is None,
        "bit": trigger.node is None or trigger.bit is None,
        "state": trigger.node is None,
    }
    needs = {
        "level": "node, index and level",
        "bit": "node and bit (index defaults to 6041h)",
        "state": "node",
    }
    if missing.get(trigger.kind):
        raise InvalidValueError(f"a {trigger.kind} trigger needs {needs[trigger.kind]}")
    if trigger.kind == "none" and trigger.pre_s > 0:
        raise InvalidValueError("pre_s needs a trigger: a free-running capture starts at once")
    if trigger.pre_s >= request.duration_s:
        raise InvalidValueError(
            f"pre_s ({trigger.pre_s:g} s) must be shorter than duration_s"
            f" ({request.duration_s:g} s)"
        )
    if trigger.kind == "state" and trigger.state:
        try:
            parse_state(trigger.state)
        except ValueError as error:
            raise InvalidValueError(str(error)) from error


def trigger_nodes(request: CaptureRequest) -> set[int]:
    node = request.trigger.node
    return (
        {node} if node is not None and request.trigger.kind in ("level", "bit", "state") else set()
    )


def overload(percent: float, period_us: int) -> str:
    return (
        f"the capture would load the bus to {percent:.0f} % at a {period_us} µs SYNC period:"
        " choose a longer SYNC period or fewer signals"
    )
