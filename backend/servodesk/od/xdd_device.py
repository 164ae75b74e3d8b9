"""CiA 311 XDD identity, bit rates and NMT features -> DeviceInfo."""

from __future__ import annotations

import re

from servodesk.od.lint import Code, WarningSink
from servodesk.od.literals import decimal, parse_int
from servodesk.od.model import DeviceInfo
from servodesk.od.xml_tree import Node, text_child

_BAUD = re.compile(r"\s*(\d+)\s*([kKmM])bps\s*")  # "250 Kbps", "1 Mbps"


def read_xdd_device(root: Node, sink: WarningSink) -> DeviceInfo:
    identity = next(root.iter("DeviceIdentity"), None)
    profile_body = next(root.iter("ProfileBody"), None)
    body = profile_body.attrib if profile_body is not None else {}
    features = next(root.iter("CANopenGeneralFeatures"), None)
    feature = features.attrib if features is not None else {}

    def text(tag: str) -> str:
        node = identity.find(tag) if identity is not None else None
        return node.text.strip() if node is not None else ""

    def number(tag: str) -> int | None:
        value = text(tag)
        if not value:
            if identity is not None and identity.find(tag) is not None:
                sink.add(
                    Code.EMPTY_VALUE,
                    f"{tag} is empty; treated as unknown",
                    line=identity.line,
                    key=tag,
                )
            return None
        try:
            return parse_int(value)[0]
        except ValueError:
            sink.add(
                Code.BAD_INTEGER,
                f"{tag} '{value}' is not a number; treated as unknown",
                line=identity.line if identity else None,
                key=tag,
            )
            return None

    rates = set()
    for rate in root.iter("supportedBaudRate"):
        match = _BAUD.fullmatch(rate.attrib.get("value", ""))
        if match:
            rates.add(int(match.group(1)) * (1000 if match.group(2) in "kK" else 1_000_000))
    dummies = set()
    for dummy in root.iter("dummy"):
        key, _, flag = dummy.attrib.get("entry", "").partition("=")
        slot = decimal(key[5:])
        if key.startswith("Dummy") and slot is not None and flag.strip() == "1":
            dummies.add(slot)
    return DeviceInfo(
        vendor_name=text("vendorName"),
        vendor_number=number("vendorID"),
        product_name=text("productName"),
        product_number=number("productID"),
        baud_rates=frozenset(rates),
        granularity=_int_attr(feature, "granularity"),
        nr_rx_pdo=_int_attr(feature, "nrOfRxPDO"),
        nr_tx_pdo=_int_attr(feature, "nrOfTxPDO"),
        lss_supported=feature.get("layerSettingServiceSlave") == "true",
        group_messaging=feature.get("groupMessaging") == "true",
        dynamic_channels_supported=feature.get("dynamicChannels", "0") not in ("0", "false"),
        dummy_usage=frozenset(dummies),
        file_name=body.get("fileName", ""),
        file_version=_int_attr(body, "fileVersion"),
        created_by=body.get("fileCreator", ""),
        modified_by=body.get("fileModifiedBy", ""),
        description=text_child(identity.find("productText") if identity else None, "description"),
    )


def _int_attr(attrs: dict[str, str], name: str) -> int | None:
    text = attrs.get(name)
    return decimal(text) if text is not None else None
