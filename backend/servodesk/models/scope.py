"""The scope's API schema: capture requests, captures, the plan shown before starting.

A capture samples signals of one or more drives at the SYNC rate (TPDOs the scope sets up, SDO
polling where an object cannot be mapped), around a trigger, into a rerun recording (.rrd) and
a samples table that the exports (CSV, Parquet, MF4) are made from.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, Field, StrictBool

from servodesk.models.base import NOT_TEXT, JsonInt, RequestBody
from servodesk.models.pdo import BusLoadResult

NodeNumber = Annotated[
    Annotated[int, Field(ge=1, le=127, description="CANopen node id 1–127")], NOT_TEXT
]
Index = Annotated[
    Annotated[int, Field(ge=0, le=0xFFFF, description="object index 0000h–FFFFh")], NOT_TEXT
]
Subindex = Annotated[Annotated[int, Field(ge=0, le=255, description="subindex 0–255")], NOT_TEXT]
Bit = Annotated[Annotated[int, Field(ge=0, le=63)], NOT_TEXT]

TriggerKind = Literal["none", "level", "bit", "emcy", "state"]
Edge = Literal["rising", "falling", "either"]
TriggerMode = Literal["single", "normal"]
# arming: its setup (TPDOs, NMT, SYNC, the trigger's first sample) not done yet: a trigger
# condition met now would be missed; armed: waiting for the trigger; running: recording
CaptureState = Literal["arming", "armed", "running", "done", "failed"]
ACTIVE_STATES: tuple[CaptureState, ...] = ("arming", "armed", "running")
Source = Literal["pdo", "sdo"]
ExportFormat = Literal["csv", "parquet", "mf4", "rrd"]
ExportLayout = Literal["long", "wide"]  # CSV: one row per sample, or per time stamp

MAX_SIGNALS = 32
MAX_DURATION_S = 3600.0
MIN_SYNC_PERIOD_US = 500  # the tool's SYNC producer cannot hold less (network/sync.py)
MAX_SYNC_PERIOD_US = 1_000_000


class ScopeSignalRequest(RequestBody):
    node: NodeNumber
    index: Index
    subindex: Subindex = 0


class TriggerRequest(RequestBody):
    """When the capture starts. `none`: at once (free-running); `level`: the signal at
    (node, index, subindex) crosses `level` (raw value, the object's own units) on `edge`;
    `bit`: bit `bit` of that object (6041h Statusword when no index is given) changes on
    `edge`; `emcy`: an EMCY from `node` (any node when none is given); `state`: the CiA 402
    state of `node` changes (to `state` when given). `pre_s` of the capture lies before the
    trigger. `normal` re-arms after each capture and keeps the last `keep` captures."""

    kind: TriggerKind = "none"
    node: NodeNumber | None = None
    index: Index | None = None
    subindex: Subindex | None = None
    level: float | None = Field(default=None, allow_inf_nan=False)
    edge: Edge = "rising"
    bit: Bit | None = None
    state: Annotated[str, Field(max_length=40)] | None = None
    pre_s: float = Field(default=0.0, ge=0.0, le=MAX_DURATION_S, allow_inf_nan=False)
    mode: TriggerMode = "single"
    keep: JsonInt = Field(default=10, ge=1, le=100)


WordBit = Annotated[Annotated[int, Field(ge=0, le=15)], NOT_TEXT]
DEFAULT_STATUSWORD_BITS = (3, 7, 10, 11, 12, 13)  # fault, warning, target reached, limit, mode
DEFAULT_CONTROLWORD_BITS = (0, 1, 2, 3, 4, 7, 8)  # the command bits, new set-point, reset, halt


def _bit_set(bits: list[int]) -> list[int]:
    return sorted(set(bits))


BitList = Annotated[list[WordBit], Field(max_length=16), AfterValidator(_bit_set)]


class LanesRequest(RequestBody):
    """Lanes drawn under a captured statusword (6041h) or controlword (6040h): its CiA 402
    state (the controlword: its command) and each bit listed as a 0/1 step lane of its own."""

    statusword_bits: BitList = Field(default_factory=lambda: list(DEFAULT_STATUSWORD_BITS))
    controlword_bits: BitList = Field(default_factory=lambda: list(DEFAULT_CONTROLWORD_BITS))


class CaptureRequest(RequestBody):
    signals: Annotated[list[ScopeSignalRequest], Field(min_length=1, max_length=MAX_SIGNALS)]
    sync_period_us: JsonInt = Field(
        default=1000, ge=MIN_SYNC_PERIOD_US, le=MAX_SYNC_PERIOD_US, description="µs"
    )
    duration_s: float = Field(gt=0.0, le=MAX_DURATION_S, allow_inf_nan=False)
    trigger: TriggerRequest = Field(default_factory=TriggerRequest)
    name: Annotated[str, Field(max_length=80)] | None = None
    start_nodes: StrictBool = Field(
        default=True,
        description="put pre-operational nodes into Operational for the capture (TPDOs only "
        "flow there) and back afterwards",
    )
    lanes: LanesRequest = Field(default_factory=LanesRequest)


class CaptureSignal(BaseModel):
    node: int
    index: int
    subindex: int
    name: str
    key: str  # entity-path-safe name: rerun shows it under drives/{node}/{key}
    source: Source
    quantity: str  # position | velocity | torque | following_error | statusword | … | other
    unit: str  # physical unit ("rev", "rpm", "%"); the raw unit when there is no conversion
    raw_unit: str
    scale: float  # value = raw × scale
    bits: int
    tpdo: int | None = None  # the TPDO number carrying it (source pdo)
    cob_id: int | None = None
    rate_hz: float | None = None  # measured sample rate (SDO polling: what the bus achieved)
    samples: int = 0
    last_value: float | None = None  # the latest sample in physical units (armed too)
    note: str | None = None  # why SDO, or what happened to this signal


class Capture(BaseModel):
    id: int
    name: str | None
    state: CaptureState
    created: float  # epoch s
    started: float | None = None  # epoch s: sampling began (armed or running)
    trigger_time: float | None = None  # epoch s of the trigger (free-running: the first sample)
    ended: float | None = None
    signals: list[CaptureSignal]
    nodes: list[int]
    sync_period_us: int
    duration_s: float
    trigger: TriggerRequest
    lanes: LanesRequest = Field(default_factory=LanesRequest)
    samples: int  # all signals together
    lost: int = 0  # frames the pipeline could not keep (0 unless overloaded)
    size_bytes: int = 0  # the .rrd and the samples table on disk
    bus_load_percent: float | None = None
    recording_id: str
    series: int | None = None  # normal mode: the id of the first capture of the series
    error: str | None = None
    notes: list[str] = Field(default_factory=list)


class ScopePlan(BaseModel):
    """What a capture would do, before it starts: each signal's source and the bus load."""

    ok: bool
    signals: list[CaptureSignal]
    bus_load: BusLoadResult
    problems: list[str]
    notes: list[str]


class ScopeViewer(BaseModel):
    """Where the embedded rerun viewer is and what it connects to."""

    url: str  # the viewer page under ServoDesk's origin
    grpc_url: str  # rerun+http://… through ServoDesk
    version: str  # rerun-sdk version (viewer and SDK are the same by construction)
    running: bool


class SignalMeasurement(BaseModel):
    """One signal between the cursors, in physical units (`unit`); None where it has no sample
    (at a cursor: none at or before it; between them: none at all)."""

    node: int
    index: int
    subindex: int
    name: str
    unit: str
    at_a: float | None  # the sample at or before cursor A
    at_b: float | None
    delta: float | None  # at_b − at_a
    min: float | None
    max: float | None
    mean: float | None
    count: int  # samples between the cursors (both ends included)


class Measurement(BaseModel):
    """Two cursors on a finished capture (seconds from its trigger) and what lies between."""

    t0: float  # cursor A
    t1: float  # cursor B
    dt: float  # t1 − t0
    start: float  # the capture's first and last sample time
    end: float
    signals: list[SignalMeasurement]


class Trace(BaseModel):
    """One signal of a finished capture reduced to at most `points` bins for an overview plot:
    per bin its time and the lowest and highest value (a spike between samples stays)."""

    signal: int
    unit: str
    start: float  # the capture's first and last sample time (any signal): where cursors go
    end: float
    times: list[float]
    low: list[float]
    high: list[float]
