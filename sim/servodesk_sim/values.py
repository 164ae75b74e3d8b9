"""The typed value store that pure cores read their inputs from and publish outputs to.

`ObjectStore` (od_store.py) implements it for a drive; tests use `DictValues`.
"""

from __future__ import annotations

from typing import Protocol


class ValueStore(Protocol):
    def get(self, index: int, subindex: int = 0) -> int:
        """Current integer value of an object (raises KeyError if the drive has no such entry)."""
        ...

    def set(self, index: int, subindex: int, value: int) -> None:
        """Publish a value from inside the drive: no access checks, no write hooks."""
        ...

    @property
    def changes(self) -> int:
        """Grows with every change of any value: equal counts, equal values."""
        ...


class DictValues:
    """A plain dict-backed ValueStore for table tests of the pure cores."""

    def __init__(self, values: dict[tuple[int, int], int] | None = None) -> None:
        self.values: dict[tuple[int, int], int] = dict(values or {})

    def get(self, index: int, subindex: int = 0) -> int:
        return self.values[(index, subindex)]

    def set(self, index: int, subindex: int, value: int) -> None:
        self.values[(index, subindex)] = value

    @property
    def changes(self) -> int:
        # Tests edit `values` directly, which nothing counts: report a change at every look.
        self._looks = getattr(self, "_looks", 0) + 1
        return self._looks
