"""The object dictionary as the browser shows it (OdTree) and as `od/check` reports a file."""

from __future__ import annotations

from typing import Literal

from servodesk.models.od import (
    LintWarningModel,
    OdCheckResult,
    OdDeviceSummary,
    OdEntry,
    OdObject,
    OdTree,
)
from servodesk.od import DataType, LintWarning, ObjectDictionaryModel, OdSub
from servodesk.sdo.codec import api_value


def data_type_name(code: int) -> str:
    try:
        return DataType(code).name
    except ValueError:
        return f"0x{code:04X}"


def entry_of(sub: OdSub) -> OdEntry:
    return OdEntry(
        index=sub.index,
        subindex=sub.subindex,
        name=sub.name,
        data_type=sub.data_type,
        data_type_name=data_type_name(sub.data_type),
        access=sub.access,
        pdo_mappable=sub.pdo_mappable,
        default=api_value(sub.default),
        low=sub.low,
        high=sub.high,
        unit=sub.unit,
        description=sub.description,
    )


def warning_of(warning: LintWarning) -> LintWarningModel:
    return LintWarningModel(
        file=warning.file,
        line=warning.line,
        section=warning.section,
        key=warning.key,
        code=warning.code,
        message=warning.message,
        severity=warning.severity,
    )


def od_tree(
    model: ObjectDictionaryModel,
    source: Literal["profile", "upload"],
    *,
    with_objects: bool = True,
) -> OdTree:
    objects = (
        [
            OdObject(
                index=obj.index,
                index_hex=f"{obj.index:04X}",
                name=obj.name,
                object_type=obj.object_type,
                subs=[entry_of(obj.subs[key]) for key in sorted(obj.subs)],
            )
            for obj in sorted(model.objects.values(), key=lambda o: o.index)
        ]
        if with_objects
        else []
    )
    return OdTree(
        source=source,
        filename=model.source,
        warnings=[warning_of(w) for w in model.warnings],
        objects=objects,
    )


def od_check(model: ObjectDictionaryModel, filename: str) -> OdCheckResult:
    device = model.device
    return OdCheckResult(
        filename=filename,
        format=model.format,
        objects=len(model.objects),
        device=OdDeviceSummary(
            vendor_name=device.vendor_name or "",
            vendor_number=device.vendor_number,
            product_name=device.product_name or "",
            product_number=device.product_number,
        ),
        warnings=[warning_of(w) for w in model.warnings],
    )
