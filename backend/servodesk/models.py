"""The data the services return and the API sends, as pydantic models (docs/api.md); the PDO,
bus-load and live-check shapes are in servodesk.pdo_models.

Services build these directly so the HTTP layer stays a thin mapping with no second copy of
every shape; the TypeScript client is generated from the OpenAPI schema they produce.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Any, Literal

from pydantic import BaseModel, Field, StrictBool

from servodesk.model_base import NOT_BOOL, NOT_TEXT
from servodesk.model_base import JsonInt as JsonInt
from servodesk.model_base import RequestBody as RequestBody
from servodesk.model_base import Value as Value
from servodesk.pdo_models import PdoProblem


class BusState(StrEnum):
    CONNECTED = "connected"
    DISCONNECTED = "disconnected"
    CONNECTING = "connecting"
    ERROR = "error"


class NmtStateName(StrEnum):
    INITIALISING = "initialising"
    PRE_OPERATIONAL = "pre-operational"
    OPERATIONAL = "operational"
    STOPPED = "stopped"
    UNKNOWN = "unknown"


class NmtCommandName(StrEnum):
    START = "start"
    STOP = "stop"
    PRE_OPERATIONAL = "pre-operational"
    RESET_NODE = "reset-node"
    RESET_COMMUNICATION = "reset-communication"


class BusConfig(RequestBody):
    interface: str | None = None
    channel: str | None = None
    bitrate: JsonInt | None = None
    options: dict[str, Any] = Field(default_factory=dict)
    simulated: StrictBool = False


class BusStatus(BaseModel):
    state: BusState
    interface: str | None = None
    channel: str | None = None
    bitrate: int | None = None
    simulated: bool = False
    error: str | None = None
    rx_frames: int = 0
    tx_frames: int = 0
    error_frames: int = 0
    bus_errors: int = 0
    reconnects: int = 0
    since: float | None = None


class InterfaceInfo(BaseModel):
    name: str
    label: str
    needs_channel: bool
    example_channel: str


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


class NmtRequest(RequestBody):
    command: NmtCommandName


class HeartbeatConfig(RequestBody):
    producer_ms: JsonInt = Field(ge=0, le=65535)


class HeartbeatWrite(HeartbeatConfig):
    # below 10 ms the node floods the bus: only on purpose
    confirm: StrictBool = False


class SyncConfig(RequestBody):
    producing: StrictBool = False
    period_us: Annotated[Annotated[int, Field(ge=0)], NOT_TEXT] | None = None


class LintWarningModel(BaseModel):
    file: str
    line: int | None
    section: str | None
    key: str | None
    code: str
    message: str
    severity: Literal["info", "warning", "error"]


class OdEntry(BaseModel):
    index: int
    subindex: int
    name: str
    data_type: int
    data_type_name: str
    access: str
    pdo_mappable: bool
    default: Value = None
    low: int | float | None = None
    high: int | float | None = None
    unit: str = ""
    description: str = ""


class OdObject(BaseModel):
    index: int
    index_hex: str
    name: str
    object_type: str
    subs: list[OdEntry]


class OdTree(BaseModel):
    source: Literal["profile", "upload"]
    filename: str
    warnings: list[LintWarningModel]
    objects: list[OdObject]


class OdDeviceSummary(BaseModel):
    vendor_name: str = ""
    vendor_number: int | None = None
    product_name: str = ""
    product_number: int | None = None


class OdCheckResult(BaseModel):
    filename: str
    format: str
    objects: int
    device: OdDeviceSummary
    warnings: list[LintWarningModel]


class SdoValue(BaseModel):
    node: int
    index: int
    subindex: int
    name: str | None = None
    data_type_name: str | None = None
    value: Value
    raw_hex: str
    text: str


class SdoWrite(RequestBody):
    value: Annotated[JsonInt | float | str, NOT_BOOL]
    size: Literal[1, 2, 4] | None = None
    # a heartbeat time (1017h) below 10 ms floods the bus: only on purpose
    confirm: StrictBool = False


class JobResult(BaseModel):
    index: int
    subindex: int
    name: str
    value: Value = None
    text: str | None = None
    abort_code: str | None = None
    message: str | None = None


class Job(BaseModel):
    id: str
    kind: Literal["upload-all"]
    node: int
    state: Literal["running", "done", "cancelled", "failed"]
    done: int
    total: int
    error: str | None = None
    elapsed_s: float = 0.0  # from start to now, or to the end once finished
    results_from: int = 0  # position of results[0] among all results (GET ?since=N)
    results: list[JobResult]


class Param(BaseModel):
    name: str
    label: str
    description: str
    object: str
    index: int
    subindex: int
    value: int | None = None
    unit: str
    min: int
    max: int
    default: int
    takes_effect: Literal["immediately", "after_reset", "after_store_and_reset"]
    choices: dict[str, str]
    error: str | None = None
    # written since the node's last boot-up, in effect only after a reset (the drive reads
    # back the new value but still works with the old one)
    pending: bool = False


class ParamWriteRequest(RequestBody):
    value: JsonInt | str


class ParamWriteResult(BaseModel):
    param: Param
    message: str
    requires_reset: bool
    requires_store: bool


class Confirm(RequestBody):
    confirm: StrictBool = False


class MessageResult(BaseModel):
    message: str


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


class DcfFailure(BaseModel):
    index: int
    subindex: int
    name: str
    abort_code: str | None = None
    message: str


class DcfDifference(BaseModel):
    index: int
    subindex: int
    name: str
    expected: Value
    actual: Value


class DcfLoadResult(BaseModel):
    identity: IdentityCheck | None = None
    written: int
    skipped: int
    failed: list[DcfFailure]
    differences: list[DcfDifference]
    warnings: list[str] = []  # written, but worth knowing (a synchronous PDO without SYNC)


class CompareRow(BaseModel):
    index: int
    subindex: int
    name: str
    unit: str
    device: Value = None
    file: Value = None
    default: Value = None
    device_text: str
    file_text: str
    default_text: str
    differs_from_file: bool
    differs_from_default: bool


class IdentityCheck(BaseModel):
    """Whether a parameter set is for the node's kind of device (vendor, product, type)."""

    matches: bool
    file: str  # "vendor 0x0000026C, product 0x000000C5, device type 0x00020192"
    device: str
    message: str | None = None  # what differs, or why it cannot be told
    # False when no identity value is known on both sides (a file without 1018h/1000h/
    # [DeviceInfo] numbers): a set that cannot be checked is confirmed like a mismatch
    checked: bool = True


class CompareResult(BaseModel):
    # what a parameter set carries: the writable configuration
    rows: list[CompareRow]
    # read-only and status values (6041h …), listed apart and never flagged as differences
    read_only: list[CompareRow] = Field(default_factory=list)
    identity: IdentityCheck | None = None  # when a file was given
    # what loading the file needs the user to confirm first, in words (another or an unknown
    # device, a heartbeat faster than the bus should carry)
    confirm: list[str] = Field(default_factory=list)


NodeEventKind = Literal["boot-up", "node-lost", "node-back", "nmt", "bus"]


class LiveEvent(BaseModel):
    """The live channel's `event` message: a node or bus event (events.bus.BusEvent, which the
    registry publishes) in its wire form."""

    time: float
    node: int | None = None
    kind: NodeEventKind
    message: str


class ErrorBody(BaseModel):
    error: str
    message: str
    abort_code: str | None = None
    node: int | None = None
    index: int | None = None
    subindex: int | None = None
    step: str | None = None  # pdo_apply_failed: the write or read that failed
    restored: bool | None = None  # pdo_apply_failed: whether the previous PDOs are back
    problems: list[PdoProblem] | None = None  # invalid PDO configuration: every reason
    role: str | None = None  # forbidden: the caller's role
    required: str | None = None  # forbidden: the least role that may
    retry_after_s: int | None = None  # rate_limited: when to try again
