"""The network management API models: NMT commands, heartbeat producer times and SYNC
(docs/api.md, "Nodes and network")."""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated

from pydantic import Field, StrictBool

from servodesk.models.base import NOT_TEXT, JsonInt, RequestBody


class NmtCommandName(StrEnum):
    START = "start"
    STOP = "stop"
    PRE_OPERATIONAL = "pre-operational"
    RESET_NODE = "reset-node"
    RESET_COMMUNICATION = "reset-communication"


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
