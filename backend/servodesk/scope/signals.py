"""What a scope signal is: its name, size, whether a TPDO can carry it, and its physical units.

Pure: the dictionary entry and the drive's units in, a `SignalInfo` out. The units follow the
motion service (motion/units.py): positions in user units shown as motor revolutions, 606Ch in
rpm, torques in 0.1 % of rated torque shown as %.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from servodesk.motion.units import S_PER_MIN, TORQUE_PER_PCT, DriveUnits
from servodesk.od import datatypes as dt
from servodesk.od.model import OdSub
from servodesk.pdo.validate import READABLE

# index -> (quantity, key) for the CiA 402 objects a scope is usually pointed at
_KNOWN: dict[int, tuple[str, str]] = {
    0x6041: ("statusword", "statusword"),
    0x6040: ("controlword", "controlword"),
    0x6061: ("mode", "mode_display"),
    0x603F: ("error_code", "error_code"),
    0x6062: ("position", "position_demand"),
    0x6063: ("position", "position_actual_internal"),
    0x6064: ("position", "position_actual"),
    0x607A: ("position", "target_position"),
    0x60F4: ("following_error", "following_error"),
    0x606B: ("velocity", "velocity_demand"),
    0x606C: ("velocity", "velocity_actual"),
    0x60FF: ("velocity", "target_velocity"),
    0x6071: ("torque", "target_torque"),
    0x6074: ("torque", "torque_demand"),
    0x6077: ("torque", "torque_actual"),
    0x6078: ("current", "current_actual"),
    0x60FD: ("digital_inputs", "digital_inputs"),
}
_USER_POSITIONS = (0x6062, 0x6064, 0x607A, 0x60F4)  # user units (6091h gear)
_USER_VELOCITIES = (0x606B, 0x60FF)  # user units/s
_TENTHS_OF_RATED = (0x6071, 0x6074, 0x6077, 0x6078)  # 0.1 % of rated torque / current


@dataclass(frozen=True, slots=True)
class Scaling:
    quantity: str
    unit: str  # physical
    raw_unit: str
    scale: float  # physical = raw × scale


@dataclass(frozen=True, slots=True)
class SignalInfo:
    node: int
    index: int
    subindex: int
    name: str
    key: str  # unique per node, safe in a rerun entity path
    data_type: int
    bits: int | None  # None: no fixed size (strings, domains): SDO only
    readable: bool
    pdo_mappable: bool
    scaling: Scaling

    @property
    def label(self) -> str:
        return f"{self.index:04X}h:{self.subindex:02X} {self.name}"

    @property
    def mappable_reason(self) -> str | None:
        """Why a TPDO cannot carry it (None when one can)."""
        if self.bits is None:
            return "has no fixed size"
        if not self.pdo_mappable:
            return "is not PDO-mappable in this drive's dictionary"
        return None


def scaling(index: int, subindex: int, od_unit: str, units: DriveUnits) -> Scaling:
    """Physical units for the objects whose units the drives define; raw otherwise."""
    quantity = _KNOWN.get(index, ("other", ""))[0] if subindex == 0 else "other"
    if quantity == "position":
        if index == 0x6063:  # encoder increments
            return Scaling(quantity, "rev", "inc", 1.0 / units.counts_per_rev)
        return Scaling(quantity, "rev", "user units", 1.0 / units.user_per_rev)
    if quantity == "following_error":
        return Scaling(quantity, "rev", "user units", 1.0 / units.user_per_rev)
    if quantity == "velocity":
        if index == 0x606C and units.velocity_actual_rpm:
            return Scaling(quantity, "rpm", "rpm", 1.0)
        return Scaling(quantity, "rpm", "user units/s", S_PER_MIN / units.user_per_rev)
    if index in _TENTHS_OF_RATED and subindex == 0:
        what = "rated current" if quantity == "current" else "rated torque"
        return Scaling(quantity, "%", f"0.1 % {what}", 1.0 / TORQUE_PER_PCT)
    return Scaling(quantity, od_unit, od_unit, 1.0)


def signal_info(node: int, sub: OdSub, units: DriveUnits) -> SignalInfo:
    bits = dt.bit_size(sub.data_type)
    return SignalInfo(
        node=node,
        index=sub.index,
        subindex=sub.subindex,
        name=sub.name,
        key=signal_key(sub.index, sub.subindex, sub.name),
        data_type=sub.data_type,
        bits=bits,
        readable=sub.access in READABLE,
        pdo_mappable=sub.pdo_mappable,
        scaling=scaling(sub.index, sub.subindex, sub.unit, units),
    )


def signal_key(index: int, subindex: int, name: str) -> str:
    """`position_actual` for the well-known objects, else `x2006_08_overspeed` from the name:
    lowercase ASCII words, unique per object because the index leads."""
    known = _KNOWN.get(index)
    if known is not None and subindex == 0:
        return known[1]
    words = re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")[:32].strip("_")
    base = f"x{index:04x}_{subindex:02x}"
    return f"{base}_{words}" if words else base
