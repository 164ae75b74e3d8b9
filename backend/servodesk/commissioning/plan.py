"""Which steps a drive can do, decided when the record is made (pure: table-tested).

A step the drive cannot do is skipped with the reason, so the record says why it is not
there instead of leaving it "to do" for ever."""

from __future__ import annotations

from collections.abc import Iterable

from servodesk.errors import InvalidValueError
from servodesk.models.commissioning import STEP_KEYS, STEP_TITLES, CommissioningStep, RecordStatus
from servodesk.motion.words import MODE_VALUES

# Steps whose automated part exists; the others are done on their page and signed off.
AUTOMATED = frozenset(STEP_KEYS)
# Where the user does a step by hand when the server has no part to run it with (a moving step
# without the motion safety layer, the pdo step without the PDO service): the 409 says so.
DONE_ON_PAGE = {"pdo": "PDOs", "homing": "Drive", "stop_test": "Drive", "test_move": "Drive"}


def check_modes(modes: Iterable[str]) -> list[str]:
    """The picked modes, each once, in the order given; an unknown name is refused."""
    picked = list(dict.fromkeys(modes))
    unknown = [m for m in picked if m not in MODE_VALUES]
    if unknown:
        raise InvalidValueError(
            f"unknown mode(s) {', '.join(unknown)}: pick from {', '.join(MODE_VALUES)}"
        )
    return picked


def _listed(modes: Iterable[str]) -> str:
    return ", ".join(modes) or "none"


def plan_steps(supported: frozenset[str] | None, picked: list[str]) -> list[CommissioningStep]:
    """The record's steps: all "to do", except what the drive cannot do (skipped, reason).
    `supported` None: the drive's modes are unknown, so nothing is skipped for them."""
    skips: dict[str, str] = {}
    if supported is not None:
        if "hm" not in supported:
            skips["homing"] = (
                "the drive announces no homing mode (6) in 6502h: nothing to home; "
                f"its modes: {_listed(sorted(supported))}"
            )
        usable = [m for m in picked if m in supported]
        if picked and not usable:
            skips["test_move"] = (
                f"none of the chosen modes ({_listed(picked)}) is supported by the drive "
                f"(6502h: {_listed(sorted(supported))})"
            )
        if not {"pp", "pv"} & supported:
            skips["stop_test"] = (
                "the drive has neither profile position nor profile velocity (6502h): "
                "no speed to stop from"
            )
    steps: list[CommissioningStep] = []
    for key in STEP_KEYS:
        step = CommissioningStep.model_validate({"key": key, "title": STEP_TITLES[key]})
        if key in skips:
            step.status, step.reason, step.by = "skipped", skips[key], "servodesk"
        if key == "test_move" and supported is not None:
            missing = [m for m in picked if m not in supported]
            if missing and key not in skips:
                step.evidence["not_supported"] = {
                    m: f"not among the drive's modes (6502h: {_listed(sorted(supported))})"
                    for m in missing
                }
        steps.append(step)
    return steps


def record_status(steps: Iterable[CommissioningStep]) -> RecordStatus:
    """failed if any step failed; done once every step is done or skipped."""
    states = [step.status for step in steps]
    if "failed" in states:
        return "failed"
    return "done" if all(s in ("done", "skipped") for s in states) else "in_progress"
