"""The objects motion reads and writes, as blocking steps for a node's worker thread.

Every function here takes the canopen RemoteNode and runs inside `NodeSession.run` (or
`priority`), never on the event loop (DESIGN rule 1). An object the drive does not have reads as
None: one its dictionary (the profile's EDS or the user's import) lacks is not asked for at all
(the drive's abort would show on the timeline as if the drive had a problem); one it has but the
drive refuses answers None by its SDO abort. Only the statusword must answer.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import canopen
from canopen.objectdictionary import ODArray, ODRecord
from canopen.sdo.exceptions import SdoAbortedError

from servodesk_protocol.cia402 import (
    CONTROLWORD,
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    QUICK_STOP_OPTION,
    STATUSWORD,
    SUPPORTED_DRIVE_MODES,
)

ERROR_CODE = 0x603F  # Error code
POSITION_ACTUAL = 0x6064  # Position actual value (user units)
FOLLOWING_WINDOW = 0x6065  # Following error window
POSITION_WINDOW = 0x6067  # Position window
SOFTWARE_POSITION_LIMIT = 0x607D  # Software position limit (:01 min, :02 max, user units)
VELOCITY_ACTUAL = 0x606C  # Velocity actual value
TARGET_TORQUE = 0x6071  # Target torque
MAX_TORQUE = 0x6072  # Max torque
TORQUE_ACTUAL = 0x6077  # Torque actual value
TARGET_POSITION = 0x607A  # Target position
HOME_OFFSET = 0x607C  # Home offset
PROFILE_VELOCITY = 0x6081  # Profile velocity
PROFILE_ACCELERATION = 0x6083  # Profile acceleration
PROFILE_DECELERATION = 0x6084  # Profile deceleration
TORQUE_SLOPE = 0x6087  # Torque slope
ENCODER_RESOLUTION = 0x608F  # Position encoder resolution (:01 increments, :02 motor revs)
GEAR_RATIO = 0x6091  # Gear ratio (:01 motor increments, :02 user units on these drives)
HOMING_METHOD = 0x6098  # Homing method
HOMING_SPEEDS = 0x6099  # Homing speeds (:01 fast, :02 slow)
HOMING_ACCELERATION = 0x609A  # Homing acceleration
IP_DATA = 0x60C1  # Interpolation data record (:01 position set-point)
IP_PERIOD = 0x60C2  # Interpolation time period (:01 value, :02 exponent of 10 s)
FOLLOWING_ERROR = 0x60F4  # Following error actual value
DIGITAL_INPUTS = 0x60FD  # Digital inputs (bit 0 N-OT, 1 P-OT, 2 home switch)
TARGET_VELOCITY = 0x60FF  # Target velocity
SIM_NEGATIVE_SWITCH = 0x5FF1  # SIM negative limit switch position (simulator only, motor inc)
SIM_POSITIVE_SWITCH = 0x5FF2  # SIM positive limit switch position (simulator only, motor inc)

# (size in bytes, signed) of what motion writes; reads take the answer's own length.
I8, U8, I16, U16, I32, U32 = (1, True), (1, False), (2, True), (2, False), (4, True), (4, False)


def has(remote: canopen.RemoteNode, index: int, sub: int = 0) -> bool:
    """Whether the node's dictionary lists the entry; a node without one (empty) may have
    anything, so it is asked."""
    od = remote.object_dictionary
    if not len(od):
        return True
    if index not in od:
        return False
    obj = od[index]
    if isinstance(obj, ODRecord | ODArray):
        return sub in obj.subindices
    return sub == 0


def read(remote: canopen.RemoteNode, index: int, sub: int = 0, *, signed: bool) -> int | None:
    """One entry as an integer, or None when the drive has no such object."""
    if not has(remote, index, sub):
        return None
    try:
        data = bytes(remote.sdo.upload(index, sub))
    except SdoAbortedError:
        return None
    return int.from_bytes(data, "little", signed=signed)


def write(
    remote: canopen.RemoteNode, index: int, sub: int, value: int, kind: tuple[int, bool]
) -> None:
    size, signed = kind
    remote.sdo.download(index, sub, int(value).to_bytes(size, "little", signed=signed))


def write_controlword(remote: canopen.RemoteNode, controlword: int) -> None:
    write(remote, CONTROLWORD, 0, controlword, U16)


def read_statusword(remote: canopen.RemoteNode) -> int:
    """6041h; unlike other objects its absence is an error (the drive is no CiA 402 drive)."""
    return int.from_bytes(bytes(remote.sdo.upload(STATUSWORD, 0))[:2], "little")


@dataclass(frozen=True, slots=True)
class Snapshot:
    """One reading of the drive's live objects (raw drive units)."""

    statusword: int
    controlword: int | None
    mode: int | None  # 6060h
    mode_display: int | None  # 6061h
    position: int | None  # 6064h, user units
    velocity: int | None  # 606Ch
    torque: int | None  # 6077h, 0.1 %
    following_error: int | None  # 60F4h, user units
    inputs: int | None  # 60FDh
    error_code: int | None  # 603Fh
    # where each value came from: "TPDO2", "SDO" (a field left out was not read)
    sources: Mapping[str, str] = field(default_factory=dict)
    # time.monotonic() when the reading began (None: just now); a reading that began before
    # a command may finish after it and show the drive from before it
    taken_at: float | None = None


# Snapshot field -> (object, signed): what a reading holds, in the order SDO reads them
SNAPSHOT_OBJECTS: Mapping[str, tuple[int, bool]] = {
    "statusword": (STATUSWORD, False),
    "controlword": (CONTROLWORD, False),
    "mode": (MODES_OF_OPERATION, True),
    "mode_display": (MODES_DISPLAY, True),
    "position": (POSITION_ACTUAL, True),
    "velocity": (VELOCITY_ACTUAL, True),
    "torque": (TORQUE_ACTUAL, True),
    "following_error": (FOLLOWING_ERROR, True),
    "inputs": (DIGITAL_INPUTS, False),
    "error_code": (ERROR_CODE, False),
}
SDO = "SDO"


@dataclass(frozen=True, slots=True)
class Travel:
    """Where the axis's travel ends, as the drive's objects say (None: not in its dictionary)."""

    switches: tuple[int | None, int | None] | None  # 5FF1h / 5FF2h, motor increments
    software_limit: tuple[int | None, int | None] | None  # 607Dh:01 / :02, user units


@dataclass(frozen=True, slots=True)
class Limits:
    """The drive's own limits: parameters a user changes (MDi PA-103) while the axis is up,
    so they are read again while the drive state is watched."""

    overspeed_rpm: int | None
    max_torque: int | None
    travel: Travel


@dataclass(frozen=True, slots=True)
class Statics:
    """What changes rarely: read on first contact and again at every enable (the limit objects
    among them also while the drive state is watched, `read_limits`)."""

    supported_raw: int | None  # 6502h
    counts_per_rev: int | None  # 608Fh:01 / :02
    gear: tuple[int, int] | None  # 6091h:01, :02
    quick_stop_option: int | None  # 605Ah
    overspeed_rpm: int | None  # the profile's max speed object
    max_torque: int | None  # 6072h, 0.1 %
    position_window: int | None  # 6067h, user units
    travel: Travel | None = None  # limit switches, 607Dh


def read_snapshot(
    remote: canopen.RemoteNode,
    given: Mapping[str, int | None] | None = None,
    sources: Mapping[str, str] | None = None,
) -> Snapshot:
    """A reading: the `given` values (a TPDO brought them, `sources` says which) and the rest
    by SDO, one upload each."""
    values: dict[str, int | None] = dict(given or {})
    where = dict(sources or {})
    for name, (index, signed) in SNAPSHOT_OBJECTS.items():
        if name in values:
            continue
        if name == "statusword":
            values[name] = read_statusword(remote)
        else:
            values[name] = read(remote, index, signed=signed)
        where[name] = SDO
    return snapshot_of(values, where)


def snapshot_of(values: Mapping[str, int | None], sources: Mapping[str, str]) -> Snapshot:
    """A Snapshot from a complete set of values (every SNAPSHOT_OBJECTS field)."""
    statusword = values["statusword"]
    if statusword is None:
        raise ValueError("a reading without the statusword")
    return Snapshot(
        statusword=statusword,
        controlword=values["controlword"],
        mode=values["mode"],
        mode_display=values["mode_display"],
        position=values["position"],
        velocity=values["velocity"],
        torque=values["torque"],
        following_error=values["following_error"],
        inputs=values["inputs"],
        error_code=values["error_code"],
        sources=dict(sources),
    )


def read_statics(
    remote: canopen.RemoteNode, max_speed: tuple[int, int] | None, *, switches: bool = False
) -> Statics:
    counts = read(remote, ENCODER_RESOLUTION, 1, signed=False)
    revs = read(remote, ENCODER_RESOLUTION, 2, signed=False) if counts else None
    motor = read(remote, GEAR_RATIO, 1, signed=False)
    user = read(remote, GEAR_RATIO, 2, signed=False)
    limits = read_limits(remote, max_speed, switches=switches)
    return Statics(
        supported_raw=read(remote, SUPPORTED_DRIVE_MODES, signed=False),
        counts_per_rev=counts // revs if counts and revs else counts,
        gear=(motor, user) if motor and user else None,
        quick_stop_option=read(remote, QUICK_STOP_OPTION, signed=True),
        overspeed_rpm=limits.overspeed_rpm,
        max_torque=limits.max_torque,
        position_window=read(remote, POSITION_WINDOW, signed=False),
        travel=limits.travel,
    )


Objects = Mapping[str, tuple[int, int, bool]]  # name -> (index, sub-index, signed)


def limit_objects(max_speed: tuple[int, int] | None, *, switches: bool) -> Objects:
    """The drive's own limits, object by object (`switches`: also the simulator's limit
    switch objects, only asked of the simulator)."""
    out: dict[str, tuple[int, int, bool]] = {}
    if switches:
        out["negative_switch"] = (SIM_NEGATIVE_SWITCH, 0, True)
        out["positive_switch"] = (SIM_POSITIVE_SWITCH, 0, True)
    out["software_min"] = (SOFTWARE_POSITION_LIMIT, 1, True)
    out["software_max"] = (SOFTWARE_POSITION_LIMIT, 2, True)
    if max_speed:
        out["overspeed"] = (*max_speed, False)
    out["max_torque"] = (MAX_TORQUE, 0, False)
    return out


def read_objects(remote: canopen.RemoteNode, objects: Objects) -> dict[str, int | None]:
    return {
        name: read(remote, index, sub, signed=signed)
        for name, (index, sub, signed) in objects.items()
    }


def limits_of(values: Mapping[str, int | None]) -> Limits:
    ends = (values.get("negative_switch"), values.get("positive_switch"))
    software = (values.get("software_min"), values.get("software_max"))
    return Limits(
        overspeed_rpm=values.get("overspeed"),
        max_torque=values.get("max_torque"),
        travel=Travel(
            switches=ends if ends != (None, None) else None,
            software_limit=software if software != (None, None) else None,
        ),
    )


def limit_values(limits: Limits | Statics) -> dict[str, int | None]:
    """The objects behind `limits` (what a later one-object-at-a-time refresh updates)."""
    travel = limits.travel
    switches = travel.switches if travel and travel.switches else (None, None)
    software = travel.software_limit if travel and travel.software_limit else (None, None)
    return {
        "negative_switch": switches[0],
        "positive_switch": switches[1],
        "software_min": software[0],
        "software_max": software[1],
        "overspeed": limits.overspeed_rpm,
        "max_torque": limits.max_torque,
    }


def read_limits(
    remote: canopen.RemoteNode, max_speed: tuple[int, int] | None, *, switches: bool = False
) -> Limits:
    return limits_of(read_objects(remote, limit_objects(max_speed, switches=switches)))
