"""The limits in force on an axis and where its travel ends.

The limits in force are what the user chose (PUT …/drive/limits), never above the drive's own:
its max speed object (MDi-S1-C: PA-103 2006h:08, MDi-S1-C CANopen manual table 2.31; else 6080h)
and 6072h Max torque. Those are parameters a user changes while the axis is up (on the
Parameters page, the drive's keypad, another tool), so they are read again, with the travel
objects, whenever the drive state is read and the last reading is older than a second: two to
six short uploads a second per watched drive, and a change shows within a second whoever made it.

Travel: the simulator's limit switches 5FF1h/5FF2h (simulator-only objects; a drive that refuses
them once is not asked again) and 607Dh Software position limit where the dictionary has it.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

from servodesk.models.motion import DriveLimits, MotionLimits
from servodesk.motion import drive_io as io
from servodesk.motion.core import DriveIo
from servodesk.motion.errors import LimitError
from servodesk.motion.rated import default_limits, pt_speed_limit, speed_object, speed_ref

LIMITS_REFRESH_S = 1.0  # the drive's own limits are at most this old while the state is read
# … while the pages poll it: their 2 uploads per reading go to the live values first
LIMITS_REFRESH_POLLED_S = 2.0
SIM_PREFIX = "SIM "  # how the shipped dictionaries name the simulator-only objects


class Limits:
    """The limits in force on each axis (kept in its Axis), the drive's own read again while
    its state is read, and the checks every command passes before anything is sent."""

    def __init__(self, drive: DriveIo) -> None:
        self._drive = drive

    # ------------------------------------------------------------------ the API

    def limits(self, node: int) -> MotionLimits:
        self._drive.registry.info(node)  # NodeNotFoundError for an unknown node
        return self._drive.axis(node).limits

    def set_limits(self, node: int, limits: MotionLimits) -> MotionLimits:
        """Server-side limits for every later command of this node (never above the drive's
        own overspeed object and 6072h; if the drive's own later go below them, those rule)."""
        drive = self._default_limits(node, self._drive.axis(node).statics)
        if limits.max_velocity_rpm > drive.max_velocity_rpm:
            raise LimitError(
                node,
                "error.speed_above_drive",
                rpm=str(limits.max_velocity_rpm),
                limit=f"{drive.max_velocity_rpm:g}",
            )
        if limits.max_torque_pct > drive.max_torque_pct:
            raise LimitError(
                node,
                "error.torque_above_drive",
                pct=str(limits.max_torque_pct),
                limit=f"{drive.max_torque_pct:g}",
            )
        low, high = limits.min_position_rev, limits.max_position_rev
        if low is not None and high is not None and low >= high:
            raise LimitError(node, "error.travel_empty", low=str(low), high=str(high))
        self._drive.axis(node).chosen_limits = limits
        self._follow_drive(node)
        return self._drive.axis(node).limits

    def pt_speed_limit(self, node: int) -> tuple[float | None, str]:
        """What caps the speed in profile torque: (rpm or None when unknown, the object)."""
        return pt_speed_limit(self._drive.registry, node, self._drive.axis(node).statics)

    def travel(self, node: int) -> tuple[float | None, float | None]:
        """ServoDesk's own travel limits (rev) of the node, as set with PUT …/drive/limits."""
        limits = self._drive.axis(node).limits
        return limits.min_position_rev, limits.max_position_rev

    # ------------------------------------------------------------------ reading

    async def refresh_statics(self, node: int) -> None:
        """All the rarely changing objects (first contact, every enable), the simulator's
        switch objects only of a drive that has them."""
        ref = speed_ref(self._drive.registry, node)
        switches = self._asks_switches(node)
        statics = await self._drive.run(
            node,
            lambda r: io.read_statics(r, ref, switches=switches),
            "read drive facts",
        )
        axis = self._drive.axis(node)
        axis.statics = statics
        axis.limits_read_at = time.monotonic()
        self._follow_drive(node)

    async def before_reading(self, node: int, sdo_budget: int | None) -> int | None:
        """The drive's own limits are read again every LIMITS_REFRESH_S while the state is
        read: all at once, or one object per polled reading (within its SDO budget); the
        reading's SDO budget left (Readings.snapshot)."""
        axis = self._drive.axis(node)
        every = LIMITS_REFRESH_S if sdo_budget is None else LIMITS_REFRESH_POLLED_S
        stale = time.monotonic() - axis.limits_read_at > every
        if axis.statics is not None and stale:
            if sdo_budget is None:
                await self._refresh_limits(node)
            else:
                await self._refresh_one_limit(node)
                sdo_budget = max(sdo_budget - 1, 1)
        return sdo_budget

    def _limit_objects(self, node: int) -> io.Objects:
        ref = speed_ref(self._drive.registry, node)
        return io.limit_objects(ref, switches=self._asks_switches(node))

    async def _refresh_limits(self, node: int) -> None:
        axis = self._drive.axis(node)
        objects = self._limit_objects(node)
        values = await self._drive.run(
            node, lambda r: io.read_objects(r, objects), "read drive limits"
        )
        axis.limits_read_at = time.monotonic()
        self._apply_limits(node, io.limits_of(values))

    async def _refresh_one_limit(self, node: int) -> None:
        """The next of the limit objects in turn; a round done counts as a full refresh."""
        axis = self._drive.axis(node)
        objects = self._limit_objects(node)
        names = list(objects)
        name = names[axis.limit_turn % len(names)]
        index, sub, signed = objects[name]
        value = await self._drive.run(
            node,
            lambda r: io.read(r, index, sub, signed=signed),
            "read a drive limit",
            command=False,  # part of the pages' shared reading
        )
        axis.limit_turn += 1
        if axis.limit_turn % len(names) == 0:
            axis.limits_read_at = time.monotonic()
        values = io.limit_values(axis.statics) if axis.statics else {}
        values[name] = value
        self._apply_limits(node, io.limits_of({n: values.get(n) for n in objects}))

    def _apply_limits(self, node: int, read: io.Limits) -> None:
        axis = self._drive.axis(node)
        if axis.statics is not None:
            axis.statics = replace(
                axis.statics,
                overspeed_rpm=read.overspeed_rpm,
                max_torque=read.max_torque,
                travel=read.travel,
            )
        self._follow_drive(node)

    def _asks_switches(self, node: int) -> bool:
        """The simulator's switch objects are asked for only while the drive answers them and
        its dictionary names them the simulator's (a real drive has no 5FF1h/5FF2h)."""
        axis = self._drive.axis(node)
        travel = axis.statics.travel if axis.statics else None
        if axis.statics is not None and (travel is None or travel.switches is None):
            axis.sim_switches = False  # asked once and refused (or not in the dictionary)
        entry = self._drive.registry.od(node).get(io.SIM_NEGATIVE_SWITCH, 0)
        return axis.sim_switches and entry is not None and entry.name.startswith(SIM_PREFIX)

    def _follow_drive(self, node: int) -> None:
        """The limits in force: the user's choice under the drive's own as last read."""
        axis = self._drive.axis(node)
        drive = self._default_limits(node, axis.statics)
        chosen = axis.chosen_limits
        axis.limits = (
            drive
            if chosen is None
            else MotionLimits(
                max_velocity_rpm=min(chosen.max_velocity_rpm, drive.max_velocity_rpm),
                max_torque_pct=min(chosen.max_torque_pct, drive.max_torque_pct),
                min_position_rev=chosen.min_position_rev,
                max_position_rev=chosen.max_position_rev,
            )
        )
        axis.drive_limits = DriveLimits(
            max_velocity_rpm=drive.max_velocity_rpm,
            velocity_source=self._speed_source(node),
            max_torque_pct=drive.max_torque_pct,
            torque_source="6072h Max torque",
        )

    def _default_limits(self, node: int, statics: io.Statics | None) -> MotionLimits:
        return default_limits(self._drive.registry, self._drive.settings, node, statics)

    def _speed_source(self, node: int) -> str:
        _, _, named = speed_object(self._drive.registry, node)
        capped = self._drive.settings.motion_max_velocity_rpm
        tail = f", capped at {capped:g} rpm by ServoDesk's settings" if capped else ""
        return f"{named}{tail}"

    # ------------------------------------------------------------------ checks

    def check_velocity(self, node: int, rpm: float) -> None:
        limit = self._drive.axis(node).limits.max_velocity_rpm
        if not math.isfinite(rpm) or abs(rpm) > limit:
            raise LimitError(node, "error.speed_beyond", rpm=f"{rpm:g}", limit=f"{limit:g}")

    def check_jog(self, node: int, mode: str, value: float) -> None:
        if mode == "pv":
            self.check_velocity(node, value)
            return
        limit = self._drive.axis(node).limits.max_torque_pct
        if not math.isfinite(value) or abs(value) > limit:
            raise LimitError(node, "error.torque_beyond", pct=f"{value:g}", limit=f"{limit:g}")

    def check_travel(self, node: int, target_rev: float) -> None:
        limits = self._drive.axis(node).limits
        low, high = limits.min_position_rev, limits.max_position_rev
        if (low is not None and target_rev < low) or (high is not None and target_rev > high):
            raise LimitError(
                node,
                "error.travel_outside",
                target=f"{target_rev:.4f}",
                low=str(low) if low is not None else "−∞",
                high=str(high) if high is not None else "+∞",
            )
