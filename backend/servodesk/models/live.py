"""The messages of the live WebSocket `/api/ws`, both ways, as pydantic models: a union
discriminated on `type`. They are added to the OpenAPI schema's components (`ServerMessage`,
`ClientMessage`; see `openapi_components`), so the browser's TypeScript types are generated
with the REST client's (docs/api.md, WebSocket)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, RootModel, TypeAdapter
from pydantic.json_schema import models_json_schema

from servodesk.models.base import NOT_TEXT, JsonInt, RequestBody
from servodesk.models.bus import BusStatus
from servodesk.models.faults import Fault, TimelineEvent
from servodesk.models.motion import DriveState
from servodesk.models.nodes import LiveEvent
from servodesk.models.safety import ControllerHolder, HeartbeatProtection, JogInfo

# ---------------------------------------------------------------------- server -> client


class _Sent(BaseModel):
    # `type` has a default but is always sent: required in the generated TypeScript
    model_config = ConfigDict(json_schema_serialization_defaults_required=True)


class LiveNode(BaseModel):
    node: int
    nmt_state: str
    online: bool
    heartbeat_age_ms: int | None


class BusMessage(_Sent):
    type: Literal["bus"] = "bus"
    bus: BusStatus


class NodesMessage(_Sent):
    type: Literal["nodes"] = "nodes"
    nodes: list[LiveNode]


class EventMessage(_Sent):
    type: Literal["event"] = "event"
    event: LiveEvent


class HistoryMessage(_Sent):
    type: Literal["history"] = "history"
    events: list[LiveEvent]


class TimelineMessage(_Sent):
    """An event of the timeline as it is published (EMCYs, state changes, tool writes …), with
    the id `GET /api/events` shows it under. Ids grow by one: a page that sees a gap missed
    some (a slow page skips the oldest) and fetches them with `GET /api/events?since=`."""

    type: Literal["timeline"] = "timeline"
    event: TimelineEvent


class FaultMessage(_Sent):
    """A node's active fault changed: a new EMCY, an error-reset EMCY or a fault reset (null:
    no active fault). Sent again once the EMCYs behind it are in the node's fault history
    (stored with the state read after them), whether or not one is still active: a page that
    lists the history reads it then. Sent for every node with an active fault when a page
    connects."""

    type: Literal["fault"] = "fault"
    node: int
    fault: Fault | None


class PongMessage(_Sent):
    type: Literal["pong"] = "pong"


class DriveStateMessage(_Sent):
    """~10 Hz for each node the client watches (`watch_drive`)."""

    type: Literal["drive_state"] = "drive_state"
    node: int
    state: DriveState


class ControllerMessage(_Sent):
    """Who controls the node, on every change and when the client starts watching it."""

    type: Literal["controller"] = "controller"
    node: int
    holder: ControllerHolder | None
    you: bool
    protection: HeartbeatProtection


class JogStoppedMessage(_Sent):
    """A jog of this client (or of a watched node) stopped, and why."""

    type: Literal["jog_stopped"] = "jog_stopped"
    jog: JogInfo


class ErrorMessage(_Sent):
    """A client message the server could not act on (unparsable, unknown jog …)."""

    type: Literal["error"] = "error"
    error: str
    message: str


ServerMessageUnion = Annotated[
    BusMessage
    | NodesMessage
    | EventMessage
    | HistoryMessage
    | TimelineMessage
    | FaultMessage
    | PongMessage
    | DriveStateMessage
    | ControllerMessage
    | JogStoppedMessage
    | ErrorMessage,
    Field(discriminator="type"),
]


class ServerMessage(RootModel[ServerMessageUnion]):
    """Any message the server sends on /api/ws."""


# ---------------------------------------------------------------------- client -> server


class HelloMessage(RequestBody):
    """First message of a page: its client id (the one it sends as X-Client-Id) owns the
    socket; jogs it started stop when the socket closes."""

    type: Literal["hello"]
    client_id: str = Field(min_length=1, max_length=64)
    name: str | None = Field(default=None, max_length=64)


class PingMessage(RequestBody):
    type: Literal["ping"]


class JogKeepaliveMessage(RequestBody):
    type: Literal["jog_keepalive"]
    jog_id: str


class _Stop(RequestBody):
    """A stop is never refused for a field it does not know: the field is ignored (REST stops
    do the same, api/audited.py)."""

    model_config = ConfigDict(extra="ignore")


class JogStopMessage(_Stop):
    type: Literal["jog_stop"]
    jog_id: str


class PageHiddenMessage(_Stop):
    """The page went to the background: every jog of this client stops."""

    type: Literal["page_hidden"]


class QuickStopMessage(_Stop):
    """Quick stop one node, or every node when `node` is null; open to every client."""

    type: Literal["quick_stop"]
    node: Annotated[Annotated[int, Field(ge=1, le=127)], NOT_TEXT] | None = None


class WatchDriveMessage(RequestBody):
    type: Literal["watch_drive"]
    node: JsonInt = Field(ge=1, le=127)


class UnwatchDriveMessage(RequestBody):
    type: Literal["unwatch_drive"]
    node: JsonInt = Field(ge=1, le=127)


ClientMessageUnion = Annotated[
    HelloMessage
    | PingMessage
    | JogKeepaliveMessage
    | JogStopMessage
    | PageHiddenMessage
    | QuickStopMessage
    | WatchDriveMessage
    | UnwatchDriveMessage,
    Field(discriminator="type"),
]


class ClientMessage(RootModel[ClientMessageUnion]):
    """Any message a client may send on /api/ws."""


CLIENT_MESSAGE: TypeAdapter[ClientMessageUnion] = TypeAdapter(ClientMessageUnion)


def dump(message: BaseModel) -> dict[str, Any]:
    return message.model_dump(mode="json")


def openapi_components() -> dict[str, Any]:
    """JSON schemas of ServerMessage, ClientMessage and everything they use, with refs into
    `#/components/schemas` (merged there by api/ws.py)."""
    _, top = models_json_schema(
        [(ServerMessage, "serialization"), (ClientMessage, "validation")],
        ref_template="#/components/schemas/{model}",
    )
    defs: dict[str, Any] = top.get("$defs", {})
    return defs
