"""The nodes' API models: what a scan finds, a node's identity and state, its events, and
changing its node id or bitrate (docs/api.md, "Nodes and network")."""

from __future__ import annotations

from enum import StrEnum
from typing import Literal

from pydantic import BaseModel, Field, StrictBool

from servodesk.models.base import JsonInt, RequestBody


class NmtStateName(StrEnum):
    INITIALISING = "initialising"
    PRE_OPERATIONAL = "pre-operational"
    OPERATIONAL = "operational"
    STOPPED = "stopped"
    UNKNOWN = "unknown"


class NodeInfo(BaseModel):
    node: int
    name: str | None = None
    vendor_id: int | None = None
    product_code: int | None = None
    revision: int | None = None
    serial: int | None = None
    hardware_version: str | None = None  # 1009h, as the device names it
    software_version: str | None = None  # 100Ah: the firmware
    device_type: int | None = None
    profile: str
    profile_label: str
    nmt_state: NmtStateName = NmtStateName.UNKNOWN
    online: bool = False
    heartbeat_age_ms: int | None = None
    last_seen: float | None = None
    od_source: Literal["profile", "upload"] = "profile"
    od_filename: str = ""
    od_warnings: int = 0
    # offline here, while the same device (vendor, product, serial) answers at this id: its
    # node id was changed; this entry can be forgotten
    moved_to: int | None = None


class ScanRequest(RequestBody):
    sdo_sweep: StrictBool = True
    timeout_ms: JsonInt = Field(default=50, ge=5, le=2000)


class ScanResult(BaseModel):
    nodes: list[NodeInfo]
    duration_ms: int


class NodeIdChange(RequestBody):
    new_node: JsonInt = Field(ge=1, le=127)
    confirm: StrictBool = False


class NodeIdChangeResult(BaseModel):
    old_node: int
    new_node: int
    steps: list[str]
    node: NodeInfo


class BitrateChange(RequestBody):
    bitrate: JsonInt
    confirm: StrictBool = False


class NodeIdOptions(BaseModel):
    """Whether a node's id can be changed over CANopen (its profile knows the object)."""

    settable: bool  # false: the drive's id is set with switches or its own tool
    note: str  # one sentence: the object that sets it and its range, or why it cannot


class BitrateOptions(BaseModel):
    """The bitrates a node can be set to over CANopen, from its profile."""

    settable: bool  # false: the drive sets its bitrate with switches or its own tool
    supported: list[int]  # bit/s, fastest first; empty when not settable
    current: int | None = None  # what its bitrate objects select now, when readable
    note: str  # one sentence for the user: what the drive supports, or how it is set


class BitrateChangeResult(BaseModel):
    bitrate: int
    steps: list[str]
    reconnect_required: bool = True


NodeEventKind = Literal["boot-up", "node-lost", "node-back", "nmt", "bus"]


class LiveEvent(BaseModel):
    """The live channel's `event` message: a node or bus event (events.bus.BusEvent, which the
    registry publishes) in its wire form."""

    time: float
    node: int | None = None
    kind: NodeEventKind
    message: str
    # the message in the page's catalogue (`server.<message_id>` with `params`, docs/api.md
    # "Texts in the user's language"); null: only the English message exists
    message_id: str | None = None
    params: dict[str, str | int] = Field(default_factory=dict)
