"""The parameter set API models: comparing a node with a DCF file, the identity check, and
loading the file (docs/api.md, "Parameter sets (DCF)")."""

from __future__ import annotations

from pydantic import BaseModel, Field

from servodesk.models.base import Value


class DcfFailure(BaseModel):
    index: int
    subindex: int
    name: str
    abort_code: str | None = None
    message: str


class DcfDifference(BaseModel):
    index: int
    subindex: int
    name: str
    expected: Value
    actual: Value


class DcfLoadResult(BaseModel):
    identity: IdentityCheck | None = None
    written: int
    skipped: int
    failed: list[DcfFailure]
    differences: list[DcfDifference]
    warnings: list[str] = []  # written, but worth knowing (a synchronous PDO without SYNC)


class CompareRow(BaseModel):
    index: int
    subindex: int
    name: str
    unit: str
    device: Value = None
    file: Value = None
    default: Value = None
    device_text: str
    file_text: str
    default_text: str
    differs_from_file: bool
    differs_from_default: bool


class IdentityCheck(BaseModel):
    """Whether a parameter set is for the node's kind of device (vendor, product, type)."""

    matches: bool
    file: str  # "vendor 0x0000026C, product 0x000000C5, device type 0x00020192"
    device: str
    message: str | None = None  # what differs, or why it cannot be told
    # False when no identity value is known on both sides (a file without 1018h/1000h/
    # [DeviceInfo] numbers): a set that cannot be checked is confirmed like a mismatch
    checked: bool = True


class CompareResult(BaseModel):
    # what a parameter set carries: the writable configuration
    rows: list[CompareRow]
    # read-only and status values (6041h …), listed apart and never flagged as differences
    read_only: list[CompareRow] = Field(default_factory=list)
    identity: IdentityCheck | None = None  # when a file was given
    # what loading the file needs the user to confirm first, in words (another or an unknown
    # device, a heartbeat faster than the bus should carry)
    confirm: list[str] = Field(default_factory=list)
