"""Publishers that feed the event bus from what already exists:

- `registry_events`: the registry's LiveEvents (boot-up, node lost/back, NMT, bus), as they are;
  an NMT command the tool sent carries `data.command` and `data.tool` (events/tool_writes.py).
- EMCYs and SDO aborts seen on the bus: `servodesk.faults.collector.FrameTap`.
- `PublishingSdoService`: SdoService whose writes publish "tool-write" events (node, object,
  value read back, or the failure).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from servodesk.bounded import TEXT_LIMIT, shorten
from servodesk.events.bus import BusEvent, EventBus, EventKind, event
from servodesk.models import LiveEvent, SdoValue
from servodesk.nodes.access import NodeAccess
from servodesk.sdo.service import SdoService, WriteListener, where


def registry_events(bus: EventBus) -> Callable[[LiveEvent], None]:
    """A registry event listener (`registry.add_event_listener`) that republishes on the bus."""

    def listener(live: LiveEvent) -> None:
        data: dict[str, Any] = {}
        if live.kind == "nmt":  # "NMT reset-node sent to node 3" / "… sent to all nodes"
            words = live.message.split()
            command = words[1] if len(words) > 1 and words[0] == "NMT" else None
            data = {"tool": True, "command": command, "broadcast": live.node is None}
        bus.publish(BusEvent(live.time, EventKind(live.kind), live.node, live.message, data))

    return listener


class PublishingSdoService(SdoService):
    """Every write through the SDO routes becomes a "tool-write" event (an audit trail for the
    timeline; the append-only audit log of the Trust issue will add who)."""

    def __init__(
        self, access: NodeAccess, *, bus: EventBus, on_write: WriteListener | None = None
    ) -> None:
        super().__init__(access, on_write=on_write)
        self._events = bus

    async def write(
        self,
        node: int,
        index: int,
        subindex: int,
        value: int | float | str,
        size: int | None = None,
        *,
        confirm: bool = False,
    ) -> SdoValue:
        place = where(index, subindex)
        # what a client sent, bounded: the timeline and the live channel carry no 100 MB text
        shown = shorten(value) if isinstance(value, str) else value
        data: dict[str, object] = {
            "action": "sdo",
            "index": index,
            "subindex": subindex,
            "value": shown,
        }
        try:
            result = await super().write(node, index, subindex, value, size, confirm=confirm)
        except Exception as error:
            data["error"] = shorten(str(error), TEXT_LIMIT)
            message = f"write {place} = {shown} failed: {data['error']}"
            self._events.publish(event(EventKind.TOOL_WRITE, node, message, data))
            raise
        data["value"] = result.value
        self._events.publish(
            event(EventKind.TOOL_WRITE, node, f"wrote {place} = {result.text}", data)
        )
        return result
