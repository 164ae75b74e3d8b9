"""Lanes under a captured statusword (6041h) or controlword (6040h), pure: the CiA 402 state
(the controlword: the command it carries) and chosen bits, each a series of its own that only
changes value, so a word plotted as a number (1591…) reads as what the drive did.

A lane is logged only where its value changes (and once at the start of the window), so lanes
cost next to nothing beside the samples. Each lane keeps its last value across batches.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import numpy.typing as npt

from servodesk.motion.words import STATUSWORD_BIT_NAMES
from servodesk.scope.trigger import NO_STATE, state_words, states_of
from servodesk_protocol.cia402 import CONTROLWORD, STATUSWORD, Command, decode_command

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]

# CiA 402 bit names; 10, 12 and 13 mean what the mode says (both main meanings are given)
STATUSWORD_BITS: Mapping[int, str] = MappingProxyType(
    {
        **STATUSWORD_BIT_NAMES,
        12: "set-point ack or homing attained",
        13: "following error or homing error",
    }
)
CONTROLWORD_BITS: Mapping[int, str] = MappingProxyType(
    {
        0: "switch on",
        1: "enable voltage",
        2: "quick stop (0 = active)",
        3: "enable operation",
        4: "new set-point or start homing",
        5: "change immediately",
        6: "relative",
        7: "fault reset",
        8: "halt",
        9: "operation mode specific",
        10: "reserved",
        11: "manufacturer specific",
        12: "manufacturer specific",
        13: "manufacturer specific",
        14: "manufacturer specific",
        15: "manufacturer specific",
    }
)
FAULT_RESET = -1  # the command lane's value while bit 7 is set (no other command then)
NO_COMMAND = -2


def bit_key(bit: int, names: Mapping[int, str]) -> str:
    """The lane's entity name: "bit_10 target reached" (the viewer shows it as the label)."""
    return f"bit_{bit:02d} {names[bit]}"


def command_words(command: int) -> str:
    if command == FAULT_RESET:
        return "Fault reset"
    if command == NO_COMMAND:
        return "No command"
    return Command(command).name.replace("_", " ").capitalize()


def commands_of(words: Floats) -> Ints:
    """The device control command of each controlword (FAULT_RESET while bit 7 is set)."""
    ints = words.astype(np.int64)
    out = np.full(ints.shape, NO_COMMAND, dtype=np.int64)
    for word in np.unique(ints):  # a handful of distinct words per batch
        command = decode_command(int(word))
        out[ints == word] = FAULT_RESET if command is None else int(command)
    return out


@dataclass(frozen=True, slots=True)
class Lane:
    key: str  # under the word's entity: "state", "command", "bit_10 target reached"
    kind: str  # state | command | bit
    bit: int | None = None


@dataclass(frozen=True, slots=True)
class LaneChanges:
    lane: Lane
    rows: npt.NDArray[np.intp]  # the batch's samples where the lane changes
    values: Ints  # state / command number, or the bit (0/1)
    texts: list[str]  # the value in words ("Operation enabled", "1")


def lanes_for(
    index: int, subindex: int, status_bits: Sequence[int], control_bits: Sequence[int]
) -> list[Lane]:
    """The lanes of a captured object: none unless it is 6041h:00 or 6040h:00."""
    if subindex != 0:
        return []
    if index == STATUSWORD:
        return [Lane("state", "state")] + [
            Lane(bit_key(b, STATUSWORD_BITS), "bit", b) for b in status_bits
        ]
    if index == CONTROLWORD:
        return [Lane("command", "command")] + [
            Lane(bit_key(b, CONTROLWORD_BITS), "bit", b) for b in control_bits
        ]
    return []


def _values(lane: Lane, raw: Floats) -> Ints:
    if lane.kind == "state":
        return states_of(raw)
    if lane.kind == "command":
        return commands_of(raw)
    return (raw.astype(np.int64) >> (lane.bit or 0)) & 1


def _words(lane: Lane, value: int) -> str:
    if lane.kind == "state":
        return state_words(value) if value != NO_STATE else "no CiA 402 state"
    if lane.kind == "command":
        return command_words(value)
    return str(value)


@dataclass
class LaneTracker:
    """The lanes of one captured word; remembers each lane's last value between batches."""

    lanes: list[Lane]
    last: dict[str, int] = field(default_factory=dict)

    def feed(self, raw: Floats) -> list[LaneChanges]:
        """Each lane's changes in this batch of samples (the first sample ever is one)."""
        if raw.size == 0:
            return []
        out: list[LaneChanges] = []
        for lane in self.lanes:
            values = _values(lane, raw)
            before = np.empty_like(values)
            before[1:] = values[:-1]
            before[0] = self.last.get(lane.key, values[0] + 1)  # none yet: a change
            where = np.flatnonzero(before != values)
            self.last[lane.key] = int(values[-1])
            if where.size:
                picked = values[where]
                texts = [_words(lane, int(v)) for v in picked]
                out.append(LaneChanges(lane, where, picked, texts))
        return out
