"""A drive's units for the scope: its position factor and encoder resolution, read by SDO."""

from __future__ import annotations

from servodesk.errors import ServodeskError
from servodesk.motion.units import DriveUnits
from servodesk.nodes.access import NodeAccess

ENCODER_RESOLUTION = 0x608F  # :01 increments per :02 motor revolutions
GEAR_RATIO = 0x6091  # :01 motor increments per :02 user units (position factor)


async def drive_units(access: NodeAccess, node: int) -> DriveUnits:
    """The drive's position factor and encoder resolution, where it has them."""
    od = access.od(node)

    async def read(index: int, subindex: int) -> int | None:
        if od.get(index, subindex) is None:
            return None
        try:
            data = await access.session(node).upload(index, subindex)
        except ServodeskError:
            return None
        return int.from_bytes(data, "little")

    counts, revs = await read(ENCODER_RESOLUTION, 1), await read(ENCODER_RESOLUTION, 2)
    motor, user = await read(GEAR_RATIO, 1), await read(GEAR_RATIO, 2)
    per_rev = counts // revs if counts and revs else counts
    gear = (motor, user) if motor and user else None
    # the three profiles report 606Ch in rpm (docs/simulator.md "Units"); a drive without a
    # profile in 60FFh's units, as CiA 402 leaves it to the device (motion/axis.py)
    rpm = access.profile_data(node) is not None
    return DriveUnits.of(per_rev, gear, velocity_actual_rpm=rpm)
