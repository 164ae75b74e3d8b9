"""Homing (6060h = 6): the method, speeds, acceleration and offset written, then started by
bit 4 0 → 1 and waited for until the drive shows it took the start; its progress shows in the
drive state (homing.py reads it from the statusword)."""

from __future__ import annotations

import math
import time

from servodesk.errors import InvalidValueError
from servodesk.models.motion import DriveState, HomeRequest, HomingMethodInfo
from servodesk.motion import drive_io as io
from servodesk.motion.core import DriveIo, state_of
from servodesk.motion.drive_limits import Limits
from servodesk.motion.homing import homing_phase, methods_for
from servodesk.motion.readings import Readings
from servodesk_protocol.cia402 import Cia402State, OperationMode, make_enable_operation


class Homing:
    """The homing methods a drive offers, and a homing run started on it."""

    def __init__(self, drive: DriveIo, readings: Readings, limits: Limits) -> None:
        self._drive, self._readings, self._limits = drive, readings, limits

    def homing_methods(self, node: int) -> list[HomingMethodInfo]:
        data = self._drive.registry.profile_data(node)
        return methods_for(data.quirks.homing_methods if data else None)

    async def home(self, node: int, request: HomeRequest) -> DriveState:
        """Homing (6060h = 6) with 6098h, speeds 6099h:01/02, acceleration 609Ah and offset
        607Ch; started by bit 4 0 → 1 (Kinco servo CANopen manual §5.4.6: Fh then 1Fh).
        Progress shows in state().homing from statusword bits 10/12/13."""
        listed = {info.method for info in self.homing_methods(node)}
        if request.method not in listed:
            raise InvalidValueError(
                f"node {node} supports homing methods {sorted(listed)}, not {request.method}"
            )
        for rpm in (request.fast_rpm, request.slow_rpm):
            if rpm is not None:
                self._limits.check_velocity(node, rpm)
        axis = self._drive.axis(node)
        axis.cancel_queue()
        axis.jog = None
        axis.move = None
        await self._readings.require_enabled(node)
        units = self._drive.units(node)
        await self._readings.set_mode(node, OperationMode.HOMING)
        await self._drive.write(node, io.HOMING_METHOD, 0, request.method, io.I8)
        if request.fast_rpm is not None:
            await self._drive.write(
                node, io.HOMING_SPEEDS, 1, units.rpm_to_velocity(request.fast_rpm), io.U32
            )
        if request.slow_rpm is not None:
            await self._drive.write(
                node, io.HOMING_SPEEDS, 2, units.rpm_to_velocity(request.slow_rpm), io.U32
            )
        if request.acceleration_rpm_s is not None:
            accel = units.rpm_s_to_acceleration(request.acceleration_rpm_s)
            await self._drive.write(node, io.HOMING_ACCELERATION, 0, accel, io.U32)
        if request.offset_inc is not None:
            await self._drive.write(
                node, io.HOME_OFFSET, 0, units.inc_to_user(request.offset_inc), io.I32
            )
        await self._drive.controlword(node, make_enable_operation())
        await self._drive.controlword(node, make_enable_operation(new_setpoint=True))
        axis.homing_method = request.method
        axis.homing = None  # a new run: the last one's end is no longer shown
        axis.homed = False
        axis.target_user = None
        axis.homing_since = math.inf  # no reading judges the run before the drive took it
        try:
            await self._readings.wait(node, _took_start, self._readings.transition_timeout(node))
        finally:
            # Read by SDO after the start went out, the drive answers in order: a TPDO or a
            # page's reading from before the start (bit 10 without bit 12, "not started")
            # can no longer end the run. Not taken in time, the next reading says so.
            axis.homing_since = time.monotonic()
        return await self._readings.state(node)


def _took_start(statusword: int) -> bool:
    """The drive shows the run (in progress, attained or error), or left Operation enabled."""
    if state_of(statusword) is not Cia402State.OPERATION_ENABLED:
        return True
    return homing_phase(statusword)[0] != "interrupted"
