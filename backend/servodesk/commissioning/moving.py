"""The steps that move the axis (stop_test, test_move, homing): what their run body may hold,
and the dispatch the commissioning service calls. A step that cannot finish (the jog never
settles, a capture fails) is recorded failed with the reason; a refusal before anything moved
(another client holds the drive, the scope is busy) is the request's error."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from servodesk.commissioning import homing_step, stop_test, test_move
from servodesk.commissioning.axis_run import AxisRun, StepError, app_client
from servodesk.commissioning.evidence import Outcome
from servodesk.errors import InvalidValueError
from servodesk.models.commissioning import CommissioningRecord, StepRun

MOVING = frozenset({"stop_test", "test_move", "homing"})
# the run body's fields each step reads; any other field given is refused
TAKES: dict[str, frozenset[str]] = {
    "stop_test": frozenset({"speed_rpm"}),
    "test_move": frozenset({"distance"}),
    "homing": frozenset({"method"}),
    "pdo": frozenset({"apply"}),
}


def check_body(key: str, body: StepRun | None) -> None:
    given = set() if body is None else body.model_dump(exclude_none=True).keys()
    extra = sorted(set(given) - TAKES.get(key, frozenset()))
    if extra:
        takes = ", ".join(sorted(TAKES.get(key, ()))) or "no body"
        raise InvalidValueError(f"step {key} does not take {', '.join(extra)}: it takes {takes}")
    if body is not None and body.distance == 0:
        raise InvalidValueError("distance 0 is no move: give a distance in rev (e.g. 0.5)")


# AxisRun with its services bound (the commissioning service's): takes the node and client
AxisFactory = Callable[..., AxisRun]


async def run(
    new_axis: AxisFactory, key: str, record: CommissioningRecord, body: StepRun | None
) -> tuple[Outcome, dict[str, float]]:
    axis = new_axis(node=record.node, client=app_client(key, record.id))
    body = body or StepRun()
    try:
        if key == "stop_test":
            return await stop_test.run(axis, body.speed_rpm)
        if key == "homing":
            return await homing_step.run(axis, body.method)
        modes = record.identity.supported_modes
        return await test_move.run(axis, record.modes, modes, body.distance)
    except StepError as error:
        evidence: dict[str, Any] = {
            "error": str(error),
            "capture_ids": [],
            "audit_ids": await axis.audit_ids(),
        }
        if axis.notes:
            evidence["notes"] = axis.notes
        return ("failed", evidence, str(error)), {}
