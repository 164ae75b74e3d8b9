"""The parameter API models: a drive's named parameters and writing them (docs/api.md,
"Parameters")."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel

from servodesk.models.base import JsonInt, RequestBody


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
