"""What to delete to keep a kind of kept file (decoded logs, scope captures) within its quota:
the oldest first, never one in use, until the rest fits. A pure core, table-tested."""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass

MB = 1 << 20


@dataclass(frozen=True)
class Kept:
    """One kept item: its id, its bytes on disk and when it was made (epoch s)."""

    id: str
    size: int
    created: float


def over_quota(items: Sequence[Kept], keep_bytes: int, protect: Collection[str] = ()) -> list[str]:
    """Ids to delete, oldest first, so that what remains takes at most `keep_bytes`; items in
    `protect` (running, just made, being read) are never chosen, even when they alone are over."""
    total = sum(item.size for item in items)
    doomed: list[str] = []
    for item in sorted(items, key=lambda i: (i.created, i.id)):
        if total <= keep_bytes:
            break
        if item.id in protect:
            continue
        doomed.append(item.id)
        total -= item.size
    return doomed


def describe_bytes(size: int) -> str:
    """1536 -> '1.5 kB', 3 * MB -> '3.0 MB' (binary multiples, as the quotas are set)."""
    value = float(size)
    for unit in ("B", "kB", "MB", "GB"):
        if value < 1024 or unit == "GB":
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    raise AssertionError("unreachable")
