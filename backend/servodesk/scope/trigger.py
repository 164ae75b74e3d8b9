"""Trigger detection over decoded sample batches (pure): a level crossing, a bit edge, a CiA 402
state change. Each detector remembers the last sample of the previous batch, so a crossing
that falls between two batches is found like any other.

The trigger time is the arrival time of the first sample that meets the condition.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from servodesk_protocol.cia402 import Cia402State, decode_state

Floats = npt.NDArray[np.float64]
NO_STATE = -1  # a statusword that shows no CiA 402 state


@dataclass(frozen=True, slots=True)
class Fired:
    time: float
    sample: int  # position in the batch
    words: str  # what happened, for the timeline ("6064h rose through 5000")


def parse_state(name: str) -> Cia402State:
    """'operation enabled', 'OPERATION_ENABLED' or 'operation-enabled' → the state."""
    key = name.strip().upper().replace(" ", "_").replace("-", "_")
    try:
        return Cia402State[key]
    except KeyError:
        names = ", ".join(s.name.lower().replace("_", " ") for s in Cia402State)
        raise ValueError(f"no CiA 402 state '{name}': one of {names}") from None


Bools = npt.NDArray[np.bool_]


def _edges(prev: Bools, cur: Bools, edge: str) -> Bools:
    if edge == "rising":
        out: Bools = ~prev & cur
    elif edge == "falling":
        out = prev & ~cur
    else:
        out = prev != cur
    return out


class LevelTrigger:
    """`edge` rising: the value goes from below `level` to at or above it; falling: from above
    to at or below; either: both."""

    def __init__(self, level: float, edge: str, label: str) -> None:
        self.level = level
        self.edge = edge
        self.label = label
        self._prev: float | None = None

    def feed(self, times: Floats, raw: Floats) -> Fired | None:
        if raw.size == 0:
            return None
        prev = np.empty_like(raw)
        prev[1:] = raw[:-1]
        prev[0] = raw[0] if self._prev is None else self._prev
        self._prev = float(raw[-1])
        rising = (prev < self.level) & (raw >= self.level)
        falling = (prev > self.level) & (raw <= self.level)
        hit = (
            rising
            if self.edge == "rising"
            else falling
            if self.edge == "falling"
            else rising | falling
        )
        where = np.flatnonzero(hit)
        if where.size == 0:
            return None
        i = int(where[0])
        verb = "rose to" if rising[i] else "fell to"
        return Fired(float(times[i]), i, f"{self.label} {verb} {self.level:g} ({raw[i]:g})")


class BitTrigger:
    def __init__(self, bit: int, edge: str, label: str) -> None:
        self.bit = bit
        self.edge = edge
        self.label = label
        self._prev: bool | None = None

    def feed(self, times: Floats, raw: Floats) -> Fired | None:
        if raw.size == 0:
            return None
        # an UNSIGNED64 at or above 2^63 does not fit int64: take it modulo 2^64 (its bits)
        words = np.where(raw >= 2.0**63, raw - 2.0**64, raw).astype(np.int64)
        bits = ((words >> self.bit) & 1).astype(bool)
        prev = np.empty_like(bits)
        prev[1:] = bits[:-1]
        prev[0] = bits[0] if self._prev is None else self._prev
        self._prev = bool(bits[-1])
        where = np.flatnonzero(_edges(prev, bits, self.edge))
        if where.size == 0:
            return None
        i = int(where[0])
        now = "set" if bits[i] else "cleared"
        return Fired(float(times[i]), i, f"{self.label} bit {self.bit} {now}")


def states_of(statuswords: Floats) -> npt.NDArray[np.int64]:
    """The CiA 402 state of each statusword (NO_STATE where it shows none)."""
    words = statuswords.astype(np.int64)
    out = np.full(words.shape, NO_STATE, dtype=np.int64)
    for word in np.unique(words):  # a handful of distinct words per batch
        with contextlib.suppress(ValueError):  # no state: stays NO_STATE
            out[words == word] = int(decode_state(int(word)))
    return out


class StateTrigger:
    """The CiA 402 state changes (into `target` when given)."""

    def __init__(self, target: Cia402State | None, label: str) -> None:
        self.target = target
        self.label = label
        self._prev: int | None = None

    def feed(self, times: Floats, statuswords: Floats) -> Fired | None:
        if statuswords.size == 0:
            return None
        states = states_of(statuswords)
        prev = np.empty_like(states)
        prev[1:] = states[:-1]
        prev[0] = states[0] if self._prev is None else self._prev
        self._prev = int(states[-1])
        hit = prev != states
        if self.target is not None:
            hit &= states == int(self.target)
        where = np.flatnonzero(hit)
        if where.size == 0:
            return None
        i = int(where[0])
        return Fired(float(times[i]), i, f"{self.label}: {state_words(int(states[i]))}")


def state_words(state: int) -> str:
    if state == NO_STATE:
        return "no CiA 402 state"
    return Cia402State(state).name.replace("_", " ").capitalize()


def state_changes(
    times: Floats, statuswords: Floats, prev: int | None
) -> tuple[list[tuple[float, int]], int | None]:
    """(time, state) at every change, and the last state (for the next batch): the state lane."""
    if statuswords.size == 0:
        return [], prev
    states = states_of(statuswords)
    before = np.empty_like(states)
    before[1:] = states[:-1]
    before[0] = NO_STATE - 1 if prev is None else prev
    where = np.flatnonzero(before != states)
    return [(float(times[i]), int(states[i])) for i in where], int(states[-1])
