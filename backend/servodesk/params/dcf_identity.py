"""Whose parameter set is this? A DCF written onto another kind of device sets objects that
mean something else there (a vendor's 2000h area, another drive's PDO layout), so the file's
identity is compared with the node's before anything is written."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from servodesk.models.nodes import NodeInfo
from servodesk.models.paramsets import IdentityCheck
from servodesk.nodes.registry import HEARTBEAT_FLOOR_MS
from servodesk.od import ObjectDictionaryModel

DEVICE_TYPE = (0x1000, 0)  # Device type
VENDOR_ID = (0x1018, 1)  # Identity object: vendor-ID
PRODUCT_CODE = (0x1018, 2)  # Identity object: product code
PRODUCER_HEARTBEAT_KEY = (0x1017, 0)


@dataclass(frozen=True)
class DeviceIds:
    vendor: int | None
    product: int | None
    device_type: int | None

    def describe(self) -> str:
        parts = [
            f"{label} 0x{value:08X}"
            for label, value in (
                ("vendor", self.vendor),
                ("product", self.product),
                ("device type", self.device_type),
            )
            if value is not None
        ]
        return ", ".join(parts) or "no identity"


def _int_value(model: ObjectDictionaryModel, key: tuple[int, int]) -> int | None:
    sub = model.get(*key)
    if sub is None:
        return None
    value = sub.value if sub.value is not None else sub.default
    return value if isinstance(value, int) else None


def file_ids(model: ObjectDictionaryModel) -> DeviceIds:
    """The identity a DCF/EDS states: its 1018h/1000h values, else its [DeviceInfo]."""
    vendor = _int_value(model, VENDOR_ID)
    product = _int_value(model, PRODUCT_CODE)
    return DeviceIds(
        vendor=vendor if vendor is not None else model.device.vendor_number,
        product=product if product is not None else model.device.product_number,
        device_type=_int_value(model, DEVICE_TYPE),
    )


def node_ids(info: NodeInfo) -> DeviceIds:
    return DeviceIds(info.vendor_id, info.product_code, info.device_type)


def check_identity(model: ObjectDictionaryModel, filename: str, info: NodeInfo) -> IdentityCheck:
    """Whether the file is for this kind of device: every identity value both sides know must
    agree (revision and serial may differ: a set moves between drives of one type)."""
    ours, theirs = file_ids(model), node_ids(info)
    differs = [
        label
        for label, mine, other in (
            ("vendor", ours.vendor, theirs.vendor),
            ("product", ours.product, theirs.product),
            ("device type", ours.device_type, theirs.device_type),
        )
        if mine is not None and other is not None and mine != other
    ]
    compared = [
        (mine, other)
        for mine, other in (
            (ours.vendor, theirs.vendor),
            (ours.product, theirs.product),
            (ours.device_type, theirs.device_type),
        )
        if mine is not None and other is not None
    ]
    message = None
    if differs:
        message = (
            f"{filename} is for {ours.describe()}; node {info.node} is {theirs.describe()} "
            f"({', '.join(differs)} differ)"
        )
    elif not compared:
        # Stripping a file's identity must not get it past the check: unknown is not "same".
        message = (
            f"{filename} names no device (no vendor, product or device type in 1018h, 1000h "
            f"or [DeviceInfo]): it cannot be checked against node {info.node} "
            f"({theirs.describe()})"
            if ours.describe() == "no identity"
            else f"node {info.node}'s identity is unknown: {filename} ({ours.describe()}) "
            "cannot be checked against it"
        )
    return IdentityCheck(
        matches=not differs and bool(compared),
        file=ours.describe(),
        device=theirs.describe(),
        message=message,
        checked=bool(compared),
    )


def heartbeat_question(filename: str, values: Mapping[tuple[int, int], object]) -> str | None:
    """Why a set's producer heartbeat time (1017h) needs confirming, as the heartbeat editor
    asks: below the floor one node alone puts 100+ frames/s on the bus."""
    ms = values.get(PRODUCER_HEARTBEAT_KEY)
    if not isinstance(ms, int) or isinstance(ms, bool) or not 0 < ms < HEARTBEAT_FLOOR_MS:
        return None
    return (
        f"{filename} sets a heartbeat every {ms} ms (1017h): {1000 // ms} frames/s from "
        f"one node; below {HEARTBEAT_FLOOR_MS} ms needs confirm"
    )


def load_questions(
    identity: IdentityCheck, filename: str, values: Mapping[tuple[int, int], object]
) -> list[str]:
    """What a load of the file needs confirmed, in words (empty: nothing)."""
    questions = [] if identity.matches or identity.message is None else [identity.message]
    heartbeat = heartbeat_question(filename, values)
    return questions if heartbeat is None else [*questions, heartbeat]
