"""The CAN bus connection's API models: its settings, its state and counters, the
interfaces it can use (docs/api.md, "Health and bus")."""

from __future__ import annotations

from enum import StrEnum
from typing import Any

from pydantic import BaseModel, Field, StrictBool

from servodesk.models.base import JsonInt, RequestBody


class BusState(StrEnum):
    CONNECTED = "connected"
    DISCONNECTED = "disconnected"
    CONNECTING = "connecting"
    ERROR = "error"


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
