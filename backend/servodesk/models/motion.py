"""The motion API's bodies (pydantic v2): what the motion service returns and the routes send.

Field names are the public contract the routes and the browser page code against. Units are
spelt in the names: `_inc` encoder increments (motor side), `_rev` revolutions, `_rpm`, `_pct`
of rated torque, `_rpm_s` rpm per second.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, StrictBool, StrictFloat

from servodesk.models.base import JsonInt, RequestBody

DriveStateName = Literal[
    "not_ready_to_switch_on",
    "switch_on_disabled",
    "ready_to_switch_on",
    "switched_on",
    "operation_enabled",
    "quick_stop_active",
    "fault_reaction_active",
    "fault",
]
EnableReasonCode = Literal[
    "nmt_stopped",
    "nmt_not_operational",
    "fault",
    "voltage_disabled",
    "quick_stop_active",
    "mode_unsupported",
    "halt_set",
    "held_by_other",
    "timeout",
    "fault_reset_high",
    "not_ready",
    "not_enabled",
    "no_transition",
]
DriveCommand = Literal[
    "shutdown",
    "switch_on",
    "disable_operation",
    "enable_operation",
    "disable_voltage",
    "quick_stop",
    "fault_reset",
]
JogMode = Literal["pv", "pt"]
IpTrajectory = Literal["point_to_point", "sine"]
# What a request may ask for ramps: beyond these no servo follows, and 6083h/6087h stay in range.
MAX_ACCELERATION_RPM_S = 1_000_000.0  # 6083h/6084h/609Ah
MIN_TORQUE_SLOPE_PCT_S = 100.0  # 6087h counts 0.1 %/ms: one step is 100 %/s
MAX_TORQUE_SLOPE_PCT_S = 100_000.0  # 6087h


class StatusBit(BaseModel):
    bit: int
    name: str
    on: bool


class FaultInfo(BaseModel):
    """The drive's active fault: 603Fh (and the code a profile names it by), decoded."""

    code: int  # 603Fh Error code (MDi: the alarm number)
    code_hex: str
    name: str | None = None  # from the profile's fault table (or the CiA 402 class)
    text: str | None = None  # what to check, where the table says
    source: str | None = None  # e.g. "MDi-S1-C CANopen manual §4.1"
    # the same in Chinese: the MDi-S1-C manual's own name, else ServoDesk's translation (the
    # fault table's name_zh / what_to_check_zh); null where the table has none
    name_zh: str | None = None
    text_zh: str | None = None
    source_zh: str | None = None


class MotionLimits(BaseModel):
    max_velocity_rpm: float = Field(gt=0)
    max_torque_pct: float = Field(gt=0)
    min_position_rev: float | None = None
    max_position_rev: float | None = None


class HomingProgress(BaseModel):
    method: int
    phase: Literal["running", "attained", "error", "interrupted"]
    message: str
    position_inc: int | None


class MoveProgress(BaseModel):
    """The last PP move: moving until the drive reaches its target, or ended without reaching
    it — `error` (statusword bit 13, following error) or `interrupted` (a quick stop, a halt,
    a fault, the drive leaving Operation enabled, another command); `message` says why."""

    target_inc: int
    phase: Literal["moving", "reached", "error", "interrupted"]
    queued: int
    message: str | None = None


class DriveLimits(BaseModel):
    """The drive's own limits as last read (at most a second old while the drive state is
    watched): the limits in force never go above them."""

    max_velocity_rpm: float
    velocity_source: str  # e.g. "2006h:08 PA-103 Maximum speed"
    max_torque_pct: float
    torque_source: str  # e.g. "6072h Max torque"


class TravelEnds(BaseModel):
    """Where something ends the axis's travel, in motor revolutions (None: no end that side)."""

    min_rev: float | None
    max_rev: float | None
    source: str  # the objects, e.g. "5FF1h / 5FF2h SIM limit switch positions"
    simulator: bool = False  # simulator-only objects (5FF0h–5FFFh), never on a real drive
    note: str = ""


class TravelInfo(BaseModel):
    """Where the axis's travel ends: the limit switches (the simulator's 5FF1h/5FF2h), the
    drive's software position limit 607Dh where its dictionary has it. ServoDesk's own travel
    limits are MotionLimits.min_position_rev / max_position_rev."""

    switches: TravelEnds | None
    software_limit: TravelEnds | None  # None: the drive has no 607Dh (or does not answer it)


class SpeedLimit(BaseModel):
    """What caps the speed in profile torque: the drive's max speed object (MDi-S1-C: PA-103
    2006h:08, MDi-S1-C CANopen manual table 2.31; Kinco and CiA 402: 6080h Max motor speed)."""

    rpm: float | None  # as read from the drive (its dictionary's default before first contact)
    source: str  # e.g. "2006h:08 PA-103 Maximum speed"


class DriveState(BaseModel):
    node: int
    state: DriveStateName
    state_label: str
    statusword: int
    status_bits: list[StatusBit]
    controlword: int
    last_transition: str | None  # e.g. "enable operation (4)": the transition just taken
    # the same words by id for the page's catalogue (docs/api.md "Texts in the user's language")
    last_transition_id: str | None = None
    last_transition_params: dict[str, str | int] = Field(default_factory=dict)
    mode: str | None  # 6060h as a short name ("pp", "pv", …)
    mode_display: str | None  # 6061h as a short name
    supported_modes: list[str]  # from 6502h
    position_inc: int
    position_rev: float
    velocity_rpm: float
    torque_pct: float | None
    following_error_inc: int | None
    digital_inputs: int | None
    inputs: dict[str, bool]  # "negative_limit", "positive_limit", "home_switch" from 60FDh
    homed: bool | None
    homing: HomingProgress | None
    move: MoveProgress | None
    target_reached: bool
    fault: FaultInfo | None
    nmt_state: str
    counts_per_rev: int
    gear_ratio: tuple[int, int] | None  # 6091h:01 motor revolutions : 6091h:02 shaft
    limits: MotionLimits
    pt_speed_limit: SpeedLimit | None = None  # PT: the drive's own speed cap (pt supported)
    drive_limits: DriveLimits | None = None  # the drive's own, which `limits` stay under
    travel: TravelInfo | None = None  # where the travel ends (None before first contact)
    # where each live value came from: "TPDO1" (the drive's own frames) or "SDO" (read), by
    # object: statusword, controlword, mode, mode_display, position, velocity, torque,
    # following_error, digital_inputs, error_code
    sources: dict[str, str] = Field(default_factory=dict)


class EnableReason(BaseModel):
    code: EnableReasonCode
    message: str  # English, stable
    # the message in the page's catalogue (`server.<message_id>` with `params`); null: only
    # the English message exists
    message_id: str | None = None
    params: dict[str, str | int] = Field(default_factory=dict)


class MoveRequest(RequestBody):
    """Numbers are JSON numbers only ("12" and true are refused, not read as 12 and 1)."""

    mode: Literal["pp"] = "pp"
    position_rev: StrictFloat
    relative: StrictBool = False
    velocity_rpm: StrictFloat = Field(gt=0)
    acceleration_rpm_s: StrictFloat | None = Field(default=None, gt=0, le=MAX_ACCELERATION_RPM_S)
    immediately: StrictBool = False


class MoveQueueRequest(RequestBody):
    moves: list[MoveRequest] = Field(min_length=1, max_length=64)


class HomeRequest(RequestBody):
    method: JsonInt
    fast_rpm: StrictFloat | None = Field(default=None, gt=0)
    slow_rpm: StrictFloat | None = Field(default=None, gt=0)
    acceleration_rpm_s: StrictFloat | None = Field(default=None, gt=0, le=MAX_ACCELERATION_RPM_S)
    offset_inc: JsonInt | None = None


class DriveCommandRequest(RequestBody):
    """One CiA 402 controlword command (MDi-S1-C CANopen manual §3.2.2, figure 3.2)."""

    command: DriveCommand


class IpStreamRequest(RequestBody):
    trajectory: IpTrajectory
    period_ms: JsonInt = Field(ge=1, le=20)
    distance_rev: StrictFloat
    duration_s: StrictFloat = Field(gt=0, le=30)


class PathStep(BaseModel):
    direction: Literal["negative", "positive"]
    speed: Literal["fast", "slow"]
    until: str  # e.g. "negative limit switch rises"


class HomingMethodInfo(BaseModel):
    method: int
    name: str
    description: str
    path: list[PathStep]


class IpStreamResult(BaseModel):
    """What an interpolated-position stream did: how closely the axis followed the plan and how
    regular the tool's SYNC was."""

    node: int
    trajectory: IpTrajectory
    period_ms: int
    points: int  # set-points sent
    syncs: int  # SYNC frames the tool sent during the stream
    duration_s: float
    max_lag_inc: int  # worst |planned − actual| sampled during the stream
    max_lag_rev: float
    final_error_inc: int  # |planned end − actual| after the settle
    sync_jitter_ms: float  # worst deviation of a SYNC interval from the period
    sync_interval_max_ms: float
    stalled: bool  # the stream stopped before its end
    fault: FaultInfo | None  # e.g. MDi alarm 62 (SYNC lost) when the stream stalled
    message: str
    state: DriveState
