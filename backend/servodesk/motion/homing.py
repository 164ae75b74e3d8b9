"""Homing methods (6098h) with a small path for the wizard's diagram, and the homing progress
statusword bits 10/12/13 in words (pure).

Paths follow CiA 402 as MDi-S1-C CANopen manual §3.7.3 describes its five methods ("只有 5
种": 17, 18, 23, 27, 35); Kinco servo CANopen manual §5.4.6 starts homing the same way
(controlword 1Fh after Fh) and the Nanotec-style controller lists the same methods.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Literal

from servodesk.models.motion import HomingMethodInfo, PathStep
from servodesk_protocol.cia402 import SW_MODE_BIT12, SW_MODE_BIT13, SW_TARGET_REACHED

HomingPhase = Literal["running", "attained", "error", "interrupted"]


def _step(direction: str, speed: str, until: str) -> PathStep:
    return PathStep.model_validate({"direction": direction, "speed": speed, "until": until})


def _limit_method(method: int, side: str, switch: str) -> HomingMethodInfo:
    """17 / 18: home where the limit switch on `side` releases."""
    back = "positive" if side == "negative" else "negative"
    return HomingMethodInfo(
        method=method,
        name=f"{side.capitalize()} limit switch",
        description=(
            f"Searches the {side} limit switch ({switch}) at the fast speed, reverses at its "
            "rising edge and creeps back at the slow speed; home is where the switch "
            "releases. Started on the switch, only the slow creep runs."
        ),
        path=[
            _step(side, "fast", f"{side} limit switch rises"),
            _step(back, "slow", f"{side} limit switch falls (home)"),
        ],
    )


def _switch_method(method: int, start: str, edge: str) -> HomingMethodInfo:
    """23 / 27: home at one edge of the home switch, reversing at the limit switch."""
    back = "positive" if start == "negative" else "negative"
    return HomingMethodInfo(
        method=method,
        name=f"Home switch, {start} start, {edge} edge",
        description=(
            f"Moves {start} at the fast speed to the home switch, then back at the slow speed "
            f"to the switch's {edge} edge (home). Meeting the {start} limit switch first, it "
            f"reverses, runs {back} to the switch and creeps through it to the same edge. "
            "Started on the switch, only the slow creep runs."
        ),
        path=[
            _step(start, "fast", "home switch rises"),
            _step(back, "slow", f"home switch falls at its {edge} edge (home)"),
        ],
    )


METHODS: Mapping[int, HomingMethodInfo] = MappingProxyType(
    {
        17: _limit_method(17, "negative", "N-OT"),
        18: _limit_method(18, "positive", "P-OT"),
        23: _switch_method(23, "positive", "lower"),
        27: _switch_method(27, "negative", "upper"),
        35: HomingMethodInfo(
            method=35,
            name="Current position",
            description="The axis does not move: its current position becomes home (607Ch).",
            path=[],
        ),
    }
)
DEFAULT_METHODS = (17, 18, 23, 27, 35)  # what the wizard offers a drive without a profile


def methods_for(listed: frozenset[int] | None) -> list[HomingMethodInfo]:
    """The methods a drive supports that the wizard can draw, in number order."""
    wanted = sorted(listed) if listed is not None else list(DEFAULT_METHODS)
    return [METHODS[method] for method in wanted if method in METHODS]


def homing_phase(statusword: int) -> tuple[HomingPhase, str]:
    """Statusword bits 13/12/10 in homing mode (CiA 402; MDi-S1-C manual §3.2.3, §3.7.1):
    0/0/0 in progress, 0/0/1 interrupted or not started, 0/1/0 attained but still moving,
    0/1/1 attained, 1/x/x error."""
    error = bool(statusword & SW_MODE_BIT13)
    attained = bool(statusword & SW_MODE_BIT12)
    reached = bool(statusword & SW_TARGET_REACHED)
    if error:
        still = "" if reached else " (still stopping)"
        return "error", f"homing error (statusword bit 13){still}: switch or method wrong?"
    if attained:
        if reached:
            return "attained", "homing attained (bits 12 and 10)"
        return "running", "home found, the axis is stopping"
    if reached:
        return "interrupted", "homing not started or interrupted (bit 10 without bit 12)"
    return "running", "homing in progress"
