"""The commissioning record as the API sends it and the store keeps it (one JSON per record).
Field names are a contract (outside scripts read them): do not rename."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, Field, StrictBool, StrictFloat, StrictStr

from servodesk.models.base import NOT_TEXT, RequestBody

StepKey = Literal[
    "identity",
    "communication",
    "parameters",
    "pdo",
    "limits",
    "stop_test",
    "test_move",
    "homing",
    "store_verify",
]
StepStatus = Literal["to_do", "done", "failed", "skipped"]
RecordStatus = Literal["in_progress", "done", "failed"]

# The flow's steps in the order the user walks them, with the title the record shows.
STEP_TITLES: dict[str, str] = {
    "identity": "Identity",
    "communication": "Communication",
    "parameters": "Parameters",
    "pdo": "PDO mapping",
    "limits": "Limits",
    "stop_test": "Stop test",
    "test_move": "Test move",
    "homing": "Homing",
    "store_verify": "Store and verify",
}
STEP_KEYS: tuple[str, ...] = tuple(STEP_TITLES)


class CommissioningStep(BaseModel):
    key: StepKey
    title: str
    status: StepStatus = "to_do"
    # what decided the status: values read back, audit entry ids, what differed
    evidence: dict[str, Any] = Field(default_factory=dict)
    figures: dict[str, float] = Field(default_factory=dict)  # measured numbers (stop time …)
    by: str | None = None  # who ran or signed it (the acting user's name)
    at: float | None = None  # unix s
    reason: str | None = None  # why skipped (or why it failed, in one line)


class CommissioningIdentity(BaseModel):
    """The drive as the tool knew it when the record was made (1008h–100Ah, 1018h, profile)."""

    name: str | None = None
    vendor_id: int | None = None
    product_code: int | None = None
    revision: int | None = None
    serial: int | None = None
    hardware_version: str | None = None
    software_version: str | None = None
    device_type: int | None = None
    profile: str
    profile_label: str
    od_source: str
    od_filename: str
    supported_modes: list[str] | None = None  # from 6502h (or the profile); None: unknown


class CommissioningRecord(BaseModel):
    id: int
    node: int
    title: str
    created: float  # unix s
    identity: CommissioningIdentity
    modes: list[str]  # the modes the user picked ("pp", "pv", …)
    steps: list[CommissioningStep]
    status: RecordStatus


class CommissioningCreate(RequestBody):
    modes: list[StrictStr] = Field(max_length=16)
    title: StrictStr | None = Field(default=None, max_length=200)


class StepSignOff(RequestBody):
    status: Literal["done", "skipped"]
    reason: StrictStr | None = Field(default=None, max_length=500)


class StepRun(RequestBody):
    """The optional body of `POST …/steps/{key}/run`: each step reads what it takes (stop_test:
    speed_rpm; test_move: distance; homing: method; pdo: apply); a field the step does not take
    is refused."""

    speed_rpm: StrictFloat | None = Field(default=None, gt=0, le=10_000)
    distance: StrictFloat | None = Field(default=None, ge=-100, le=100)  # rev, relative
    # homing: the method to run (6098h); default: the one the drive is set to
    method: Annotated[Annotated[int, Field(ge=-128, le=127)], NOT_TEXT] | None = None
    # pdo: apply the manuals' recommended mapping for the record's modes first (engineer)
    apply: StrictBool | None = None


class CheckRequest(RequestBody):
    """`POST /api/commissioning/check` as JSON: a record of this server, and the node to check
    (default: the record's)."""

    # JSON Schema's integers (12 and 12.0), never "12" (models/base.py)
    record_id: Annotated[Annotated[int, Field(ge=1, le=2**53)], NOT_TEXT]
    node: Annotated[Annotated[int, Field(ge=1, le=127)], NOT_TEXT] | None = None
