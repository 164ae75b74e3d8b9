"""The imported object dictionary: frozen, format-neutral (EDS, DCF and XDD load into the same)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from servodesk.od.lint import LintWarning

Access = Literal["ro", "wo", "rw", "rwr", "rww", "const"]
ObjectKind = Literal["var", "array", "record", "domain"]
FileFormat = Literal["eds", "dcf", "xdd"]
Value = int | float | str | bytes


class OdImportError(Exception):
    """Nothing usable could be read: not an INI or XML file, or no object at all."""


# slots: a large vendor dictionary holds tens of thousands of entries; without a __dict__ each
@dataclass(frozen=True, slots=True)
class OdSub:
    """One entry (index, sub-index). A VAR object has exactly one, at sub-index 0."""

    index: int
    subindex: int
    name: str
    data_type: int  # CiA 301 code (0x0007 UNSIGNED32 ...)
    access: Access
    pdo_mappable: bool
    # Parsed DefaultValue. For `relative` entries it already includes the node id the model was
    # loaded with (`ObjectDictionaryModel.node_id`, 0 when none was given).
    default: Value | None = None
    default_raw: str | None = None  # the text in the file, e.g. "$NODEID+0x180"
    relative: bool = False  # default uses $NODEID
    low: int | float | None = None
    high: int | float | None = None
    unit: str = ""
    value: Value | None = None  # DCF ParameterValue (same node-id rule as `default`)
    description: str = ""
    value_raw: str | None = None
    value_relative: bool = False
    factor: float = 1.0  # python-canopen's non-standard `Factor` key
    obj_flags: int = 0  # CiA 306 ObjFlags: tool hints (refuse write on download / read on scan)
    line: int | None = None  # where the entry is defined, for messages


@dataclass(frozen=True, slots=True)
class OdObject:
    index: int
    name: str
    object_type: ObjectKind
    subs: dict[int, OdSub]
    line: int | None = None

    def sub(self, subindex: int = 0) -> OdSub:
        return self.subs[subindex]


@dataclass(frozen=True)
class DeviceInfo:
    vendor_name: str = ""
    vendor_number: int | None = None
    product_name: str = ""
    product_number: int | None = None
    revision_number: int | None = None
    order_code: str = ""
    baud_rates: frozenset[int] = frozenset()  # bit/s, e.g. 500_000
    granularity: int | None = None
    nr_rx_pdo: int | None = None
    nr_tx_pdo: int | None = None
    lss_supported: bool = False
    simple_boot_up_master: bool = False
    simple_boot_up_slave: bool = False
    dynamic_channels_supported: bool = False
    group_messaging: bool = False
    compact_pdo: int | None = None
    dummy_usage: frozenset[int] = frozenset()  # dummy data types (0x0002..0x0007) usable in PDOs
    # [FileInfo]
    file_name: str = ""
    file_version: int | None = None
    file_revision: int | None = None
    eds_version: str = ""
    description: str = ""
    created_by: str = ""
    modified_by: str = ""
    comments: str = ""
    # [DeviceComissioning] of a DCF (CiA 306 spells it with one "m")
    node_id: int | None = None
    node_name: str = ""
    baud_rate: int | None = None  # bit/s
    net_number: int | None = None


@dataclass(frozen=True)
class ObjectDictionaryModel:
    device: DeviceInfo
    objects: dict[int, OdObject]
    warnings: tuple[LintWarning, ...]
    source: str
    format: FileFormat
    node_id: int | None = None  # the node id `relative` defaults and values were resolved with
    encoding: str = "utf-8"

    def get(self, index: int, subindex: int = 0) -> OdSub | None:
        obj = self.objects.get(index)
        if obj is None:
            return None
        return obj.subs.get(subindex)
