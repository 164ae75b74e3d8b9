"""What the drive itself allows, from its objects as read and its dictionary: the max speed
object (MDi PA-103 2006h:08, else 6080h), 6072h Max torque and 6071h's range, capped by
ServoDesk's settings. A new axis starts with these (core.py); the user's choice is held under
them (drive_limits.py)."""

from __future__ import annotations

from servodesk.models.motion import MotionLimits
from servodesk.motion import drive_io as io
from servodesk.motion.drive_io import Statics
from servodesk.nodes.access import NodeAccess
from servodesk.settings import Settings

DEFAULT_MAX_RPM = 3000.0  # a drive with no overspeed object nor default
DEFAULT_MAX_TORQUE_PCT = 300.0  # 6072h's usual default (3000 = 300 %)


def speed_ref(registry: NodeAccess, node: int) -> tuple[int, int]:
    """The drive's max speed object: MDi PA-103 2006h:08, else 6080h Max motor speed."""
    data = registry.profile_data(node)
    return data.quirks.max_speed_object if data else (0x6080, 0)  # Max motor speed


def default_limits(
    registry: NodeAccess, settings: Settings, node: int, statics: Statics | None
) -> MotionLimits:
    """The drive's overspeed object (MDi PA-103 2006h:08, else 6080h) and 6072h, as read or
    as its dictionary's defaults, capped by the settings."""
    ref = speed_ref(registry, node)
    read_rpm = statics.overspeed_rpm if statics and statics.overspeed_rpm else None
    read_torque = statics.max_torque if statics and statics.max_torque else None
    rpm = float(read_rpm or od_default(registry, node, *ref) or DEFAULT_MAX_RPM)
    torque_raw = read_torque or od_default(registry, node, io.MAX_TORQUE, 0)
    torque_pct = float(torque_raw) / 10 if torque_raw else DEFAULT_MAX_TORQUE_PCT
    # 6071h's own range caps a torque jog too (MDi-S1-C: ±1000 = 100 % while 6072h
    # allows 300 %): a set-point past it is refused by the drive (abort 06090031h)
    target = registry.od(node).get(io.TARGET_TORQUE, 0)
    if target is not None and isinstance(target.high, int | float) and target.high > 0:
        torque_pct = min(torque_pct, float(target.high) / 10)
    if settings.motion_max_velocity_rpm:
        rpm = min(rpm, settings.motion_max_velocity_rpm)
    if settings.motion_max_torque_pct:
        torque_pct = min(torque_pct, settings.motion_max_torque_pct)
    return MotionLimits(
        max_velocity_rpm=rpm,
        max_torque_pct=torque_pct,
        min_position_rev=None,
        max_position_rev=None,
    )


def pt_speed_limit(
    registry: NodeAccess, node: int, statics: Statics | None
) -> tuple[float | None, str]:
    """What caps the speed in profile torque: (rpm or None when unknown, the object)."""
    index, sub, named = speed_object(registry, node)
    read = statics.overspeed_rpm if statics and statics.overspeed_rpm else None
    rpm = read or od_default(registry, node, index, sub)
    return (float(rpm) if rpm else None), named


def speed_object(registry: NodeAccess, node: int) -> tuple[int, int, str]:
    """The drive's max speed object (MDi PA-103 2006h:08, else 6080h Max motor speed) and
    how the page names it: "2006h:08 PA-103 Maximum speed"."""
    index, sub = speed_ref(registry, node)
    obj = registry.od(node).objects.get(index)
    entry = obj.subs.get(sub) if obj else None
    name = entry.name if entry else (obj.name if obj else "max speed")
    where = f"{index:04X}h:{sub:02X}" if sub else f"{index:04X}h"
    return index, sub, f"{where} {name}"


def od_default(registry: NodeAccess, node: int, index: int, sub: int) -> float | None:
    obj = registry.od(node).objects.get(index)
    entry = obj.subs.get(sub) if obj else None
    value = entry.default if entry else None
    return float(value) if isinstance(value, int | float) and value > 0 else None
