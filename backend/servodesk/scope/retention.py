"""Captures kept within their quota (settings `captures_keep_mb`): the oldest finished ones go
when a capture ends and at start-up, and a capture ends itself before it fills the disk (an hour
at 1 kHz is about 1.4 GB). Blocking functions: call them off the loop."""

from __future__ import annotations

import logging
from collections.abc import Collection

from servodesk.models.scope import ACTIVE_STATES
from servodesk.scope.store import CaptureStore
from servodesk.storage.quota import Kept, describe_bytes, over_quota
from servodesk.storage.usage import free_bytes

log = logging.getLogger(__name__)

ACTIVE = ACTIVE_STATES


def prune(store: CaptureStore, keep_bytes: int, protect: Collection[int] = ()) -> list[Kept]:
    """Delete the oldest finished captures until all of them take at most `keep_bytes`;
    returns what was deleted. An armed or running capture and those in `protect` stay."""
    captures = store.list()
    # ids zero-padded: captures made in the same second go in the order they were made
    kept = [Kept(f"{c.id:012d}", store.size_bytes(c.id), c.created) for c in captures]
    sizes = {k.id: k for k in kept}
    guarded = {f"{i:012d}" for i in protect} | {
        f"{c.id:012d}" for c in captures if c.state in ACTIVE
    }
    removed: list[Kept] = []
    for key in over_quota(kept, keep_bytes, guarded):
        try:
            store.delete(int(key))
        except Exception:  # one that cannot go must not keep the rest
            log.warning("scope: could not delete capture %d", int(key), exc_info=True)
            continue
        removed.append(sizes[key])
    if removed:
        log.info("scope: %s", pruned_note(removed, keep_bytes))
    return removed


def pruned_note(removed: list[Kept], keep_bytes: int) -> str:
    """'removed capture 3 (1.2 GB) and 4 (80.0 MB) to keep captures within 8.0 GB'."""
    parts = [f"{int(k.id)} ({describe_bytes(k.size)})" for k in removed]
    listed = parts[0] if len(parts) == 1 else f"{', '.join(parts[:-1])} and {parts[-1]}"
    noun = "capture" if len(parts) == 1 else "captures"
    return f"removed {noun} {listed} to keep captures within {describe_bytes(keep_bytes)}"


def room_left(store: CaptureStore, capture_id: int, keep_bytes: int, min_free: int) -> str | None:
    """Why the recording capture must end now (its own size at the quota, or the disk nearly
    full), in words for its notes; None while there is room."""
    if store.size_bytes(capture_id) >= keep_bytes:
        return f"ended at {describe_bytes(keep_bytes)}, the size kept for captures"
    free = free_bytes(store.root)
    if free < min_free:
        return (
            f"ended early: the disk has {describe_bytes(free)} free, less than the "
            f"{describe_bytes(min_free)} kept for the audit log and the timeline"
        )
    return None
