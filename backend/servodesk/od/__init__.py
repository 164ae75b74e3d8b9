"""Tolerant EDS / DCF / XDD import with a per-object lint report, value codecs and DCF export.

Every file a vendor ships should load: problems become `LintWarning`s that name the file, line,
section and key, instead of a refusal or a silently dropped value.

`to_canopen` is imported from `servodesk.od.to_canopen`: it brings canopen and python-can (with
asammdf and pandas, a second of start-up), which reading and checking a file never needs.
"""

from __future__ import annotations

from servodesk.od.datatypes import DataType
from servodesk.od.dcf_export import export_dcf
from servodesk.od.lint import Code, LintWarning, Severity, lint_report
from servodesk.od.loader import load_od, load_od_bytes
from servodesk.od.model import (
    DeviceInfo,
    ObjectDictionaryModel,
    OdImportError,
    OdObject,
    OdSub,
)
from servodesk.od.values import format_value, parse_value

__all__ = [
    "Code",
    "DataType",
    "DeviceInfo",
    "LintWarning",
    "ObjectDictionaryModel",
    "OdImportError",
    "OdObject",
    "OdSub",
    "Severity",
    "export_dcf",
    "format_value",
    "lint_report",
    "load_od",
    "load_od_bytes",
    "parse_value",
]
