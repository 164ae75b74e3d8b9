"""`PublishingSdoService`: the SdoService whose writes publish "tool-write" events (node, object,
value read back, or the failure) on the event bus (events/tool_writes.py lists every kind)."""

from __future__ import annotations

from servodesk.bounded import TEXT_LIMIT, shorten
from servodesk.events.bus import EventBus, EventKind, event
from servodesk.events.texts import say
from servodesk.models.sdo import SdoValue
from servodesk.nodes.access import NodeAccess
from servodesk.sdo.service import SdoService, WriteListener, where


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
            failure = shorten(str(error), TEXT_LIMIT)
            data["error"] = failure
            said = say("event.write_failed", where=place, value=str(shown), error=failure)
            self._events.publish(event(EventKind.TOOL_WRITE, node, said, data))
            raise
        data["value"] = result.value
        said = say("event.wrote", where=place, value=result.text)
        self._events.publish(event(EventKind.TOOL_WRITE, node, said, data))
        return result
