"""The SDO API models: one value read or written, and the upload-all job (docs/api.md,
"Object dictionary and SDO")."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, StrictBool

from servodesk.models.base import NOT_BOOL, JsonInt, RequestBody, Value


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
