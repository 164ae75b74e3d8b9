"""The object dictionary's API models: a node's dictionary as a tree, and the check of an
EDS/DCF file with its warnings (docs/api.md, "Object dictionary and SDO")."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel

from servodesk.models.base import Value


class LintWarningModel(BaseModel):
    file: str
    line: int | None
    section: str | None
    key: str | None
    code: str
    message: str
    severity: Literal["info", "warning", "error"]


class OdEntry(BaseModel):
    index: int
    subindex: int
    name: str
    data_type: int
    data_type_name: str
    access: str
    pdo_mappable: bool
    default: Value = None
    low: int | float | None = None
    high: int | float | None = None
    unit: str = ""
    description: str = ""


class OdObject(BaseModel):
    index: int
    index_hex: str
    name: str
    object_type: str
    subs: list[OdEntry]


class OdTree(BaseModel):
    source: Literal["profile", "upload"]
    filename: str
    warnings: list[LintWarningModel]
    objects: list[OdObject]


class OdDeviceSummary(BaseModel):
    vendor_name: str = ""
    vendor_number: int | None = None
    product_name: str = ""
    product_number: int | None = None


class OdCheckResult(BaseModel):
    filename: str
    format: str
    objects: int
    device: OdDeviceSummary
    warnings: list[LintWarningModel]
