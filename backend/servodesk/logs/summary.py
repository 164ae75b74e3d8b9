"""The plain-language summary of a log, built while it is decoded and bounded in size: the first
lines of each kind are kept, later ones only counted ("… and 1,234 more SDO aborts")."""

from __future__ import annotations

from collections.abc import Sequence

MAX_PER_KIND = 25  # lines of one kind before they are only counted
_PLURALS = {
    "boot-up": "boot-ups",
    "nmt": "NMT commands",
    "nmt-state": "NMT state changes",
    "heartbeat-lost": "heartbeat losses",
    "heartbeat-resumed": "heartbeat recoveries",
    "sdo-abort": "SDO aborts",
    "sdo-error": "SDO protocol errors",
    "emcy": "EMCYs",
    "cia402-state": "CiA 402 state changes",
    "identity": "identities",
    "lss": "LSS commands",
}


class SummaryBuilder:
    def __init__(self, max_per_kind: int = MAX_PER_KIND) -> None:
        self._max = max_per_kind
        self._lines: list[str] = []
        self._kept: dict[str, int] = {}
        self._dropped: dict[str, int] = {}

    def add(self, kind: str, line: str) -> None:
        kept = self._kept.get(kind, 0)
        if kept < self._max:
            self._kept[kind] = kept + 1
            self._lines.append(line)
        else:
            self._dropped[kind] = self._dropped.get(kind, 0) + 1

    def count(self, kind: str) -> int:
        return self._kept.get(kind, 0) + self._dropped.get(kind, 0)

    def render(self, header: Sequence[str]) -> list[str]:
        """The header (totals), then what happened in order, then what was left out."""
        tail = [
            f"… and {n:,} more {_PLURALS.get(kind, kind)} (see the events)"
            for kind, n in self._dropped.items()
        ]
        return [*header, *self._lines, *tail]
