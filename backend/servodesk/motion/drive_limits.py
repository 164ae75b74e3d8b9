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

import time
from dataclasses import replace

from servodesk.motion import drive_io as io
from servodesk.motion.core import MotionCore
from servodesk.motion.drive_io import Snapshot
from servodesk.motion.errors import LimitError
from servodesk.motion.schemas import DriveLimits, MotionLimits

LIMITS_REFRESH_S = 1.0  # the drive's own limits are at most this old while the state is read
# … while the pages poll it: their 2 uploads per reading go to the live values first
LIMITS_REFRESH_POLLED_S = 2.0
SIM_PREFIX = "SIM "  # how the shipped dictionaries name the simulator-only objects


class LimitOps(MotionCore):
    # ------------------------------------------------------------------ the API

    def limits(self, node: int) -> MotionLimits:
        self._registry.info(node)  # NodeNotFoundError for an unknown node
        return self._axis(node).limits

    def set_limits(self, node: int, limits: MotionLimits) -> MotionLimits:
        """Server-side limits for every later command of this node (never above the drive's
        own overspeed object and 6072h; if the drive's own later go below them, those rule)."""
        drive = self._default_limits(node, self._axis(node).statics)
        if limits.max_velocity_rpm > drive.max_velocity_rpm:
            raise LimitError(
                node,
                f"{limits.max_velocity_rpm} rpm is above the drive's own limit "
                f"{drive.max_velocity_rpm:g} rpm",
            )
        if limits.max_torque_pct > drive.max_torque_pct:
            raise LimitError(
                node,
                f"{limits.max_torque_pct} % is above the drive's max torque "
                f"{drive.max_torque_pct:g} % (6072h)",
            )
        low, high = limits.min_position_rev, limits.max_position_rev
        if low is not None and high is not None and low >= high:
            raise LimitError(node, f"travel limits {low} … {high} rev are empty")
        self._axis(node).chosen_limits = limits
        self._follow_drive(node)
        return self._axis(node).limits

    # ------------------------------------------------------------------ reading

    async def _refresh_statics(self, node: int) -> None:
        """All the rarely changing objects (first contact, every enable); in place of
        MotionCore's, so the simulator's switch objects are not asked of a drive without them."""
        data = self._registry.profile_data(node)
        speed_ref = data.quirks.max_speed_object if data else (0x6080, 0)  # Max motor speed
        switches = self._asks_switches(node)
        statics = await self._run(
            node,
            lambda r: io.read_statics(r, speed_ref, switches=switches),
            "read drive facts",
        )
        axis = self._axis(node)
        axis.statics = statics
        axis.limits_read_at = time.monotonic()
        self._follow_drive(node)

    async def _snapshot(self, node: int, *, sdo_budget: int | None = None) -> Snapshot:
        """The drive's own limits are read again every LIMITS_REFRESH_S while the state is
        read: all at once, or one object per polled reading (within its SDO budget)."""
        axis = self._axis(node)
        every = LIMITS_REFRESH_S if sdo_budget is None else LIMITS_REFRESH_POLLED_S
        stale = time.monotonic() - axis.limits_read_at > every
        if axis.statics is not None and stale:
            if sdo_budget is None:
                await self._refresh_limits(node)
            else:
                await self._refresh_one_limit(node)
                sdo_budget = max(sdo_budget - 1, 1)
        return await super()._snapshot(node, sdo_budget=sdo_budget)

    def _limit_objects(self, node: int) -> io.Objects:
        data = self._registry.profile_data(node)
        speed_ref = data.quirks.max_speed_object if data else (0x6080, 0)  # Max motor speed
        return io.limit_objects(speed_ref, switches=self._asks_switches(node))

    async def _refresh_limits(self, node: int) -> None:
        axis = self._axis(node)
        objects = self._limit_objects(node)
        values = await self._run(node, lambda r: io.read_objects(r, objects), "read drive limits")
        axis.limits_read_at = time.monotonic()
        self._apply_limits(node, io.limits_of(values))

    async def _refresh_one_limit(self, node: int) -> None:
        """The next of the limit objects in turn; a round done counts as a full refresh."""
        axis = self._axis(node)
        objects = self._limit_objects(node)
        names = list(objects)
        name = names[axis.limit_turn % len(names)]
        index, sub, signed = objects[name]
        value = await self._run(
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
        axis = self._axis(node)
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
        axis = self._axis(node)
        travel = axis.statics.travel if axis.statics else None
        if axis.statics is not None and (travel is None or travel.switches is None):
            axis.sim_switches = False  # asked once and refused (or not in the dictionary)
        entry = self._registry.od(node).get(io.SIM_NEGATIVE_SWITCH, 0)
        return axis.sim_switches and entry is not None and entry.name.startswith(SIM_PREFIX)

    def _follow_drive(self, node: int) -> None:
        """The limits in force: the user's choice under the drive's own as last read."""
        axis = self._axis(node)
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

    def _speed_source(self, node: int) -> str:
        _, _, named = self._speed_object(node)
        capped = self._settings.motion_max_velocity_rpm
        tail = f", capped at {capped:g} rpm by ServoDesk's settings" if capped else ""
        return f"{named}{tail}"
