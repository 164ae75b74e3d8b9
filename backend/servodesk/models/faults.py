"""API models of the fault routes (docs/api.md, "Faults and events")."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field, StrictBool

from servodesk.models.base import RequestBody


class Fault(BaseModel):
    """One decoded EMCY (servodesk.faults.decode.FaultRecord) and the CiA 402 state around it."""

    time: float
    node: int
    code: int
    code_hex: str
    source: str  # vendor | cia402 | cia301 | unknown
    name_en: str  # the source's words: the manual's English, the CiA table's text
    name_zh: str | None = None
    # where name_zh comes from: "manual" (the drive manual's own Chinese, MDi-S1-C) or
    # "translation" (ServoDesk's translation of an English source: Kinco, CiA 402/301)
    name_zh_source: Literal["manual", "translation"] | None = None
    check: str | None = None
    check_zh: str | None = Field(
        default=None,
        description="the same parts as `check`, in Chinese (labels 原因：, 检查：, CiA 类别：, "
        "CiA 代码 XXXXh：, 错误寄存器 XXh：, 来源：); ServoDesk's translation except MDi-S1-C "
        "causes, which are the manual's own; null when `check` is null or a part has no "
        "Chinese",
    )
    error_register: int | None = None
    manufacturer_hex: str | None = None
    raw_hex: str
    state_before: str | None = None  # the CiA 402 state last seen before the EMCY
    state_after: str | None = None  # 6041h read after the EMCY (best effort)
    bus: str | None = None  # the bus it came from ("socketcan can0"); null: not recorded


class NodeFaults(BaseModel):
    active: Fault | None
    history: list[Fault]
    total: int = Field(description="faults of this node in the history (the list is the newest)")


class ActiveFaults(BaseModel):
    faults: list[Fault]


class FaultResetResult(BaseModel):
    node: int
    ok: bool
    message: str
    # the message in the page's catalogue (`server.<message_id>` with `params`, docs/api.md
    # "Texts in the user's language"); null: only the English message exists
    message_id: str | None = None
    params: dict[str, str | int] = Field(default_factory=dict)
    state_before: str
    state_after: str
    statusword_hex: str
    active: Fault | None


class DeviceHistoryEntry(BaseModel):
    number: int  # 1003h sub-index: 1 = newest
    value_hex: str  # the 32-bit entry: bits 0–15 the error code, 16–31 manufacturer-specific
    fault: Fault


class DeviceHistory(BaseModel):
    node: int
    count: int
    entries: list[DeviceHistoryEntry]
    error_code: Fault | None = Field(description="603Fh, the drive's last error code (0: none)")
    note: str | None = None
    supported: bool = Field(default=True, description="false: the drive has no 1003h at all")


class DeviceHistoryCleared(BaseModel):
    node: int
    message: str
    # the message in the page's catalogue (`server.<message_id>` with `params`, docs/api.md
    # "Texts in the user's language"); null: only the English message exists
    message_id: str | None = None
    params: dict[str, str | int] = Field(default_factory=dict)


class ConfirmBody(RequestBody):
    confirm: StrictBool = False


class TimelineEvent(BaseModel):
    id: int
    time: float
    kind: str
    node: int | None
    message: str
    data: dict[str, Any]
    bus: str | None = None  # the bus it came from ("socketcan can0"); null: not recorded
    # the message in the page's catalogue (`server.<message_id>` with `params`, docs/api.md
    # "Texts in the user's language"); null: only the English message exists
    message_id: str | None = None
    params: dict[str, str | int] = Field(default_factory=dict)


class EventPage(BaseModel):
    events: list[TimelineEvent]
    next: int | None = Field(
        description="cursor for the next page: pass it as `before` (newest-first pages) or as "
        "`since` (since pages); null when there is nothing more yet"
    )
