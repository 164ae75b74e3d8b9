"""Profile matching: a node's identity -> the profile the tool uses for it.

1. A shipped drive profile (servodesk_data) when 1018h:01 vendor-ID and 1018h:02 product code
   both match it. Vendor and product identify a device uniquely (CiA 301 §7.5.2.26); the device
   type is not compared because the drives do not agree on it (MDi reports 1000h = 0).
2. Otherwise "generic-cia402" when 1000h bits 0–15 name device profile 402: the cia402 profile's
   EDS as the dictionary, but no parameter catalogue or fault table.
3. Otherwise "generic-cia301": the cia402 EDS restricted to the communication area 1000h–1FFFh,
   which every CiA 301 device shares in layout (the rest of that EDS would be a guess).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import servodesk_data
from servodesk_data import DriveData

GENERIC_CIA402 = "generic-cia402"
GENERIC_CIA301 = "generic-cia301"
CIA402_DEVICE_PROFILE = 0x0192  # 1000h Device type, bits 0–15: profile number 402
DEVICE_PROFILE_MASK = 0xFFFF
GENERIC_EDS_PROFILE = "cia402"  # whose EDS the generic profiles borrow
COMMUNICATION_AREA = (0x1000, 0x1FFF)  # CiA 301 communication profile area

# the labels by profile name (the page has them in its `format.profile` catalogue too)
LABELS = {
    "mdi-s1c": "MDi-S1-C CAN servo",
    "kinco": "Kinco servo",
    "cia402": "CiA 402 controller (Nanotec style)",
    GENERIC_CIA402: "Generic CiA 402 drive",
    GENERIC_CIA301: "Generic CiA 301 device",
}


@dataclass(frozen=True)
class ProfileMatch:
    name: str
    label: str
    data: DriveData | None  # parameter catalogue, quirks, faults; None for generic profiles
    eds_path: Path | None
    # Only these indices of the EDS apply (generic CiA 301); None = the whole file.
    index_range: tuple[int, int] | None = None


def load_known() -> tuple[DriveData, ...]:
    """The shipped drive profiles, parsed (each call reads the TOML files again)."""
    return tuple(servodesk_data.load(name) for name in servodesk_data.PROFILE_NAMES)


def match(
    device_type: int | None,
    vendor_id: int | None,
    product_code: int | None,
    *,
    known: Sequence[DriveData] | None = None,
) -> ProfileMatch:
    """The profile for a node with this identity (None = the node did not say)."""
    profiles = load_known() if known is None else known
    if vendor_id is not None and product_code is not None:
        for data in profiles:
            identity = data.identity
            if identity.vendor_id == vendor_id and identity.product_code == product_code:
                return ProfileMatch(
                    name=data.profile,
                    label=LABELS.get(data.profile, identity.description),
                    data=data,
                    eds_path=data.eds,
                )
    generic_eds = servodesk_data.eds_path(GENERIC_EDS_PROFILE)
    if device_type is not None and device_type & DEVICE_PROFILE_MASK == CIA402_DEVICE_PROFILE:
        return ProfileMatch(
            name=GENERIC_CIA402, label=LABELS[GENERIC_CIA402], data=None, eds_path=generic_eds
        )
    return ProfileMatch(
        name=GENERIC_CIA301,
        label=LABELS[GENERIC_CIA301],
        data=None,
        eds_path=generic_eds,
        index_range=COMMUNICATION_AREA,
    )
