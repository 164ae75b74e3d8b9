"""The timeline: every event the services published, stored (docs/api.md, "Events")."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.events.bus import EventKind
from servodesk.models.faults import EventPage, TimelineEvent

router = APIRouter(tags=["events"], route_class=AuditedRoute)


@router.get("/events")
async def events(
    services: ServicesDep,
    node: Annotated[int | None, Query(ge=1, le=127)] = None,
    kind: EventKind | None = None,
    since: Annotated[
        int | None, Query(ge=0, description="events after this id, oldest first (polling)")
    ] = None,
    before: Annotated[
        int | None, Query(ge=1, description="older events than this id, newest first")
    ] = None,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
    all_buses: Annotated[
        bool,
        Query(
            description="also the events of other buses (another server sharing this data "
            "directory, a bus connected before); default: the connected bus's only"
        ),
    ] = False,
) -> EventPage:
    storage = services.storage
    await storage.flush()  # everything published before the request is in the answer
    rows = await storage.events(
        node=node,
        kind=kind.value if kind is not None else None,
        since=since,
        before=None if since is not None else before,
        limit=limit,
        bus=None if all_buses else services.bus.label(),
    )
    page = [TimelineEvent(**vars(row)) for row in rows]
    if since is not None:
        following: int | None = page[-1].id if page else since  # poll again from here
    else:
        following = page[-1].id if len(page) == limit else None
    return EventPage(events=page, next=following)
