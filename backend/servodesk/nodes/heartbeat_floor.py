"""The one rule for a node's heartbeat time (1017h): below HEARTBEAT_FLOOR_MS a single node puts
100+ frames/s on the bus, so such a time is written only with confirmation — through the
heartbeat route and through a raw SDO write of 1017h alike (docs/security.md)."""

from __future__ import annotations

from servodesk.errors import ConfirmationRequiredError

HEARTBEAT_FLOOR_MS = 10


def check_heartbeat_time(node: int, ms: int, *, confirm: bool) -> None:
    """ConfirmationRequiredError (API 428) for 0 < ms < the floor without `confirm`."""
    if 0 < ms < HEARTBEAT_FLOOR_MS and not confirm:
        raise ConfirmationRequiredError(
            f"a heartbeat every {ms} ms puts {1000 // ms} frames/s on the bus from node "
            f"{node} alone; below {HEARTBEAT_FLOOR_MS} ms needs confirm"
        )
