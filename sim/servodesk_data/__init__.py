"""The drive data that the simulator (`servodesk_sim`) and the tool (`servodesk`) both read.

One folder per drive profile holds its object dictionary (`drive.eds`, CiA 306) and its
`profile.toml` (identity, quirks, parameter catalogue, fault table), so a simulated drive never
drifts from what the tool believes about it.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import resources
from pathlib import Path

from servodesk_data.loader import format_object_ref, load_path, parse_object_ref
from servodesk_data.model import (
    BitrateCode,
    DriveData,
    EmcyFormat,
    FaultEntry,
    Identity,
    LimitSwitchReaction,
    NodeIdSource,
    ObjectRef,
    Parameter,
    PdoRemapRule,
    Quirks,
    SdoLengthCheck,
    TakesEffect,
)

PROFILE_NAMES: tuple[str, ...] = ("mdi-s1c", "kinco", "cia402")

# MDi-S1-C manual §2.2: the MDi drive parameters PA-n are reached over CANopen in the manufacturer
# area, 16 per index starting at 2000h; sub 0 holds the highest sub-index.
MDI_PA_BASE = 0x2000
MDI_PA_PER_INDEX = 16


def data_dir(profile: str) -> Path:
    """The folder holding `profile`'s drive.eds and profile.toml."""
    if profile not in PROFILE_NAMES:
        raise ValueError(f"unknown drive profile {profile!r}; known: {', '.join(PROFILE_NAMES)}")
    folder = resources.files(__name__).joinpath(profile)
    # setuptools installs package data as plain files, so the resource is a real path
    if not isinstance(folder, Path):
        raise RuntimeError(f"servodesk_data is not installed as files on disk ({folder!r})")
    return folder


def eds_path(profile: str) -> Path:
    """The CiA 306 EDS of `profile`, loadable with `canopen.import_od(path, node_id)`."""
    return data_dir(profile) / "drive.eds"


def load(profile: str) -> DriveData:
    """Parse and validate `profile`'s profile.toml (ValueError naming file and key if bad)."""
    return load_path(data_dir(profile) / "profile.toml")


def mdi_pa_object(number: int) -> ObjectRef:
    """MDi parameter PA-`number` -> (index, sub-index): PA-103 -> (0x2006, 0x08)."""
    if not 0 <= number < MDI_PA_PER_INDEX * 0x100:
        raise ValueError(f"PA-{number} is outside the PA parameter range")
    index, rest = divmod(number, MDI_PA_PER_INDEX)
    return MDI_PA_BASE + index, rest + 1


def bitrate_of(data: DriveData, values: Mapping[ObjectRef, int]) -> int | None:
    """The bitrate (bit/s) the drive's bitrate objects select; None if absent or unknown.

    MDi: PA-106 code 0–6 (MDi-S1-C manual §2.2); Kinco: the 2F81h/2F82h pair (Kinco manual §4).
    """
    objects = data.quirks.bitrate_objects
    if not objects or any(ref not in values for ref in objects):
        return None
    current = tuple(values[ref] for ref in objects)
    for code in data.quirks.bitrate_codes:
        if code.values == current:
            return code.bitrate
    return None


def bitrate_objects(data: DriveData, bitrate: int) -> dict[ObjectRef, int]:
    """The values to write to the drive's bitrate objects for `bitrate` bit/s.

    Empty for a drive whose bitrate is not set over CANopen; ValueError for a bitrate the drive
    cannot run at.
    """
    objects = data.quirks.bitrate_objects
    if not objects:
        return {}
    for code in data.quirks.bitrate_codes:
        if code.bitrate == bitrate:
            return dict(zip(objects, code.values, strict=True))
    supported = ", ".join(str(code.bitrate) for code in data.quirks.bitrate_codes)
    raise ValueError(f"{data.profile} cannot run at {bitrate} bit/s (supported: {supported})")


__all__ = [
    "MDI_PA_BASE",
    "MDI_PA_PER_INDEX",
    "PROFILE_NAMES",
    "BitrateCode",
    "DriveData",
    "EmcyFormat",
    "FaultEntry",
    "Identity",
    "LimitSwitchReaction",
    "NodeIdSource",
    "ObjectRef",
    "Parameter",
    "PdoRemapRule",
    "Quirks",
    "SdoLengthCheck",
    "TakesEffect",
    "bitrate_objects",
    "bitrate_of",
    "data_dir",
    "eds_path",
    "format_object_ref",
    "load",
    "load_path",
    "mdi_pa_object",
    "parse_object_ref",
]
