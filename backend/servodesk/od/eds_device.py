"""[FileInfo], [DeviceInfo], [DummyUsage], [Comments], [DeviceComissioning] -> DeviceInfo."""

from __future__ import annotations

import re

from servodesk.od.ini_reader import IniDocument, IniSection
from servodesk.od.lint import Code, Severity, WarningSink
from servodesk.od.literals import parse_int
from servodesk.od.model import DeviceInfo

BAUD_RATES_KBIT = (10, 20, 50, 125, 250, 500, 800, 1000)  # CiA 306 [DeviceInfo] BaudRate_x keys
_EDS_VERSION = re.compile(r"(4\.\d+|3\.0)")


def read_device_info(doc: IniDocument, sink: WarningSink) -> DeviceInfo:
    reader = _Keys(sink)
    file_info = doc.section("FileInfo")
    info = doc.section("DeviceInfo")
    commissioning = doc.section("DeviceComissioning")
    if info is None:
        sink.add(Code.UNKNOWN_SECTION, "[DeviceInfo] is missing; identity and bit rates unknown")
    empty = IniSection("", 0)
    fi = file_info or empty
    di = info or empty
    dc = commissioning or empty
    if file_info is not None:
        _check_eds_version(file_info, sink)
    baud_rates = frozenset(
        kbit * 1000 for kbit in BAUD_RATES_KBIT if reader.flag(di, f"BaudRate_{kbit}")
    )
    commissioning_kbit = reader.integer(dc, "Baudrate")
    return DeviceInfo(
        vendor_name=di.text("VendorName"),
        vendor_number=reader.integer(di, "VendorNumber", identity=True),
        product_name=di.text("ProductName"),
        product_number=reader.integer(di, "ProductNumber", identity=True),
        revision_number=reader.integer(di, "RevisionNumber", identity=True),
        order_code=di.text("OrderCode"),
        baud_rates=baud_rates,
        granularity=reader.integer(di, "Granularity"),
        nr_rx_pdo=reader.integer(di, "NrOfRXPDO"),
        nr_tx_pdo=reader.integer(di, "NrOfTXPDO"),
        lss_supported=reader.flag(di, "LSS_Supported"),
        simple_boot_up_master=reader.flag(di, "SimpleBootUpMaster"),
        simple_boot_up_slave=reader.flag(di, "SimpleBootUpSlave"),
        dynamic_channels_supported=reader.flag(di, "DynamicChannelsSupported"),
        group_messaging=reader.flag(di, "GroupMessaging"),
        compact_pdo=reader.integer(di, "CompactPDO"),
        dummy_usage=_dummy_usage(doc, reader),
        file_name=fi.text("FileName"),
        file_version=reader.integer(fi, "FileVersion"),
        file_revision=reader.integer(fi, "FileRevision"),
        eds_version=fi.text("EDSVersion"),
        description=fi.text("Description"),
        created_by=fi.text("CreatedBy"),
        modified_by=fi.text("ModifiedBy"),
        comments=_comments(doc),
        node_id=reader.integer(dc, "NodeID"),
        node_name=dc.text("NodeName"),
        baud_rate=None if commissioning_kbit is None else commissioning_kbit * 1000,
        net_number=reader.integer(dc, "NetNumber"),
    )


class _Keys:
    """Typed reads of one key with the warnings a user needs when the text is not usable."""

    def __init__(self, sink: WarningSink) -> None:
        self.sink = sink

    def integer(self, section: IniSection, key: str, *, identity: bool = False) -> int | None:
        entry = section.get(key)
        if entry is None:
            return None
        if not entry.value:
            why = " (python-canopen refuses such a file)" if identity else ""
            self.sink.add(
                Code.EMPTY_VALUE,
                f"{key} is empty{why}; treated as unknown",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="warning" if identity else "info",
            )
            return None
        try:
            value, is_hex = parse_int(entry.value)
        except ValueError:
            self.sink.add(
                Code.BAD_INTEGER,
                f"{key} '{entry.value}' is not a number; treated as unknown",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="warning" if identity else "info",
            )
            return None
        digits = entry.value.lstrip("+-")
        if not is_hex and len(digits) > 1 and digits.startswith("0"):
            self.sink.add(
                Code.LEADING_ZERO,
                f"{key} '{entry.value}' has a leading zero; read as decimal {value}",
                line=entry.line,
                section=section.name,
                key=entry.key,
                severity="info",
            )
        return value

    def flag(self, section: IniSection, key: str) -> bool:
        value = self.integer(section, key)
        return bool(value)


def _check_eds_version(section: IniSection, sink: WarningSink) -> None:
    entry = section.get("EDSVersion")
    if entry is None:
        sink.add(
            Code.EDS_VERSION,
            "EDSVersion is missing; read as a CiA 306 version 4.0 file",
            line=section.line,
            section=section.name,
            severity="info",
        )
        return
    if _EDS_VERSION.fullmatch(entry.value):
        return
    severity: Severity = "warning"
    message = f"EDSVersion '{entry.value}' is not a CiA 306 version (4.0); read as 4.0"
    if entry.value == "4":
        message, severity = "EDSVersion '4' should be written '4.0'; read as 4.0", "info"
    sink.add(
        Code.EDS_VERSION,
        message,
        line=entry.line,
        section=section.name,
        key=entry.key,
        severity=severity,
    )


def _dummy_usage(doc: IniDocument, reader: _Keys) -> frozenset[int]:
    section = doc.section("DummyUsage")
    if section is None:
        return frozenset()
    return frozenset(i for i in range(1, 8) if reader.flag(section, f"Dummy{i:04d}"))


def _comments(doc: IniDocument) -> str:
    section = doc.section("Comments")
    if section is None:
        return ""
    lines = [
        entry.raw
        for key, entry in section.entries.items()
        if key.startswith("line") and key[4:].isdigit()
    ]
    return "\n".join(lines)
