"""Bodies of the safety layer's routes and messages: who controls a drive, whether the drive
stops by itself if the tool dies, and hold-to-run jogs."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, StrictBool, StrictFloat

from servodesk.models.base import JsonInt, RequestBody
from servodesk.models.motion import (
    MAX_ACCELERATION_RPM_S,
    MAX_TORQUE_SLOPE_PCT_S,
    MIN_TORQUE_SLOPE_PCT_S,
)


class ControllerHolder(BaseModel):
    client_id: str
    name: str | None = None  # what the client called itself (hello), for "held by …"
    since: float  # wall-clock time it took control


class HeartbeatProtection(BaseModel):
    """Whether the drive watches the tool's heartbeat (1016h) and stops if it goes silent."""

    active: bool
    tool_node_id: int
    consumer_ms: int
    message: str


class ControllerInfo(BaseModel):
    node: int
    holder: ControllerHolder | None
    you: bool  # the asking client holds it
    protection: HeartbeatProtection


class TakeControlRequest(RequestBody):
    take_over: StrictBool = False  # take it even though another client holds it
    name: str | None = Field(default=None, max_length=64)


class JogRequest(RequestBody):
    mode: Literal["pv", "pt"]
    velocity_rpm: StrictFloat | None = None  # pv (true/false is not a speed)
    torque_pct: StrictFloat | None = None  # pt
    # pv: 6083h/6084h, up to speed and back down (default: the settings' acceleration)
    acceleration_rpm_s: StrictFloat | None = Field(default=None, gt=0, le=MAX_ACCELERATION_RPM_S)
    # pt: 6087h torque slope (default 100 %/s, the drive's finest step)
    torque_slope_pct_s: StrictFloat | None = Field(
        default=None, ge=MIN_TORQUE_SLOPE_PCT_S, le=MAX_TORQUE_SLOPE_PCT_S
    )
    keepalive_ms: JsonInt = Field(default=250, ge=20, le=500)
    # pt: ServoDesk's own speed cap (rpm): the jog is stopped when the axis passes it
    # (default: the settings' jog_pt_speed_cap_rpm, never above the speed limit in force)
    speed_cap_rpm: StrictFloat | None = Field(default=None, gt=0)


# running: keep-alives hold it; stopping: the stop was sent and the axis is still decelerating;
# stopped: the axis is at rest (or could not be watched to rest: stop_reason says so)
JogStateName = Literal["running", "stopping", "stopped"]


class JogInfo(BaseModel):
    jog_id: str
    node: int
    mode: Literal["pv", "pt"]
    value: float  # rpm (pv) or % rated torque (pt)
    acceleration_rpm_s: float | None = None  # pv: the ramp written to 6083h/6084h
    torque_slope_pct_s: float | None = None  # pt: the slope written to 6087h
    # pt: the speed the drive will not exceed, and the object that sets it
    velocity_limit_rpm: float | None = None
    velocity_limit_source: str | None = None
    # pt: ServoDesk's own cap; passing it stops the jog
    speed_cap_rpm: float | None = None
    keepalive_ms: int
    state: JogStateName
    stop_reason: str | None = None  # why it stopped: keep-alive missed, socket closed, EMCY …
    # the same words by id for the page's catalogue (docs/api.md "Texts in the user's language")
    stop_reason_id: str | None = None
    stop_reason_params: dict[str, str | int] = Field(default_factory=dict)
    # the deceleration the stop uses (rpm/s): never below ServoDesk's floor, whatever the ramp
    stop_deceleration_rpm_s: float | None = None
    velocity_rpm: float | None = None  # the last speed read while it ran or stopped
    owner: str | None = None  # the client id that started it (scripts get one of their own)


class LimitsRequest(RequestBody):
    """PUT …/drive/limits: MotionLimits, strict (true/false is not a number)."""

    max_velocity_rpm: StrictFloat = Field(gt=0)
    max_torque_pct: StrictFloat = Field(gt=0)
    min_position_rev: StrictFloat | None = None
    max_position_rev: StrictFloat | None = None


class QuickStopResult(BaseModel):
    """`POST /api/quick-stop`: which drives were told to stop, and which could not be."""

    stopped: list[int]
    failed: dict[str, str]  # node (as text: JSON keys) -> why
