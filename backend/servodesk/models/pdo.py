"""The PDO, bus-load and live-check shapes of the API (docs/api.md "PDO mapping").

The services build these directly; the pure cores (servodesk.pdo.model, bus_load) mirror them.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, StrictBool

from servodesk.models.base import JsonInt, RequestBody, Value

PdoKindName = Literal["rpdo", "tpdo"]


class PdoMappedObject(BaseModel):
    index: int
    subindex: int
    bits: int
    name: str | None = None  # from the node's dictionary; None when it does not know it


class Pdo(BaseModel):
    """One RPDO/TPDO as the device has it (GET) or as it is to be (PUT)."""

    kind: PdoKindName
    number: int  # 1-based
    cob_id: int  # the CAN identifier, without the valid / RTR bits
    valid: bool  # COB-ID bit 31 clear
    transmission_type: int
    inhibit_time_100us: int
    event_timer_ms: int
    sync_start: int
    mapping: list[PdoMappedObject]
    transmission: str = ""  # read-only: the transmission type in words


class PdoMappedObjectIn(RequestBody):
    index: JsonInt = Field(ge=0, le=0xFFFF)
    subindex: JsonInt = Field(ge=0, le=0xFF)
    bits: JsonInt = Field(ge=1, le=0xFF)
    name: str | None = None  # read-only, ignored (so a GET result can be sent back)


class PdoIn(RequestBody):
    kind: PdoKindName
    number: JsonInt = Field(ge=1, le=512)
    cob_id: JsonInt = Field(ge=0, le=0x7FF)
    valid: StrictBool
    transmission_type: JsonInt = Field(ge=0, le=0xFF)
    inhibit_time_100us: JsonInt = Field(default=0, ge=0, le=0xFFFF)
    event_timer_ms: JsonInt = Field(default=0, ge=0, le=0xFFFF)
    sync_start: JsonInt = Field(default=0, ge=0, le=0xFF)
    mapping: list[PdoMappedObjectIn] = Field(default_factory=list, max_length=64)
    transmission: str | None = None  # read-only, ignored


class PdoWriteRequest(RequestBody):
    pdos: list[PdoIn] = Field(max_length=1024)
    # where SYNC comes from while ServoDesk produces none and none is heard on the bus:
    # "external" = the machine's controller (PLC); it acknowledges the SYNC warnings
    sync_source: Literal["external"] | None = None


class PdoList(BaseModel):
    pdos: list[Pdo]


class PdoProblem(BaseModel):
    kind: PdoKindName
    number: int
    message: str
    # the object it concerns (mapped object, or communication / mapping parameter entry);
    # None when the problem is not about one object
    index: int | None = None
    subindex: int | None = None
    # the message in the page's catalogue (`server.<message_id>` with `params`, docs/api.md
    # "Texts in the user's language"); null: only the English message exists
    message_id: str | None = None
    params: dict[str, str | int] = Field(default_factory=dict)


class PdoRules(BaseModel):
    """How one node takes PDO changes: from its profile, else CiA 301 and its dictionary."""

    byte_granular: bool  # whole bytes only (8, 16, 32 bits)
    fixed_cob_ids: int  # PDOs 1..n whose CAN id is fixed to the pre-defined connection set
    rtr_supported: bool  # TPDO transmission types 252/253
    rpdo_count: int
    tpdo_count: int
    procedure: str  # how the drive takes a new mapping, in words, citing the manual section
    needs_pre_operational: bool  # no PDO changes in Operational


class PdoLoadModel(BaseModel):
    kind: PdoKindName
    number: int
    cob_id: int
    frames_per_s: float | None  # None: a TPDO sent on events without a bound
    bits_per_frame: int
    bits_per_s: float
    # how the rate was estimated ("every SYNC at 1 ms", "event timer 10 ms", "sent by the
    # master every 10 ms (assumed master cycle)")
    basis: str


class NodeLoadModel(BaseModel):
    node: int
    bits_per_s: float
    percent: float
    pdos: list[PdoLoadModel]


class BusLoadResult(BaseModel):
    bitrate: int
    sync_period_us: int | None
    sync_bits_per_s: float
    nodes: list[NodeLoadModel]
    total_bits_per_s: float
    percent: float
    threshold_percent: float
    over_threshold: bool
    master_period_ms: int  # the master cycle assumed for event-driven RPDOs without SYNC
    notes: list[str]  # one line per assumption, naming the PDOs it concerns


class PdoSync(BaseModel):
    """Where SYNC comes from when a mapping is checked."""

    producing: bool  # ServoDesk's own SYNC producer runs
    period_us: int | None = None  # its period
    heard: bool  # another producer's SYNC (080h) was heard on the bus in the last 2 s
    heard_frames: int = 0  # SYNC frames from other producers since ServoDesk started
    heard_period_us: int | None = None  # between the last two heard, while heard
    source: Literal["external"] | None = None  # what the request said


class PdoValidation(BaseModel):
    # an apply of the same body would be accepted: no problems, and the warnings acknowledged
    ok: bool
    problems: list[PdoProblem]  # the mapping is wrong for this node: an apply refuses it
    bus_load: BusLoadResult  # the bus with this node's PDOs replaced by the given ones
    # synchronous PDOs while no SYNC is produced or heard; written once the request says
    # sync_source "external" (or SYNC runs)
    warnings: list[PdoProblem] = Field(default_factory=list)
    sync: PdoSync | None = None


class LiveValue(BaseModel):
    index: int
    subindex: int
    name: str | None = None
    value: Value = None
    raw: str = ""  # the field's bytes in frame order as hex pairs: "50 02"
    unit: str = ""
    # the value in words: 6041h the CiA 402 state and notable bits, 6060h/6061h the mode
    text: str | None = None
    # the value as read, with its unit: bit fields in hex ("0x0250"), a unit with a factor
    # converted ("0.1 %" -> "12.5 %")
    display: str = ""


class LivePdo(BaseModel):
    cob_id: int
    kind: PdoKindName
    number: int
    frames: int  # since the capture started
    # (frames - 1) / (last - first) over the frames of the last ~2 s; None below 2 frames
    rate_hz: float | None = None
    age_ms: int | None = None  # since the last frame; None before the first
    values: list[LiveValue]  # the last frame, decoded


class LiveCheck(BaseModel):
    node: int
    active: bool
    since: float | None = None  # UNIX time the capture started
    pdos: list[LivePdo]
    # what the Drive page does with the node's RPDOs (commands by RPDO or by SDO), in words
    drive_page: str | None = None
