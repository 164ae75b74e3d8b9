"""Moving the axis: PP set-points with the new-set-point handshake and a queue, PV and PT jogs.
Every command is checked against the node's limits before anything is sent (Limits)."""

from __future__ import annotations

import asyncio
import logging
from typing import Literal

from servodesk.errors import ServodeskError
from servodesk.models.motion import (
    DriveState,
    MoveProgress,
    MoveQueueRequest,
    MoveRequest,
)
from servodesk.motion import drive_io as io
from servodesk.motion.core import DriveIo
from servodesk.motion.drive_limits import Limits
from servodesk.motion.errors import MotionBusyError
from servodesk.motion.jog import JogRamp
from servodesk.motion.readings import Readings
from servodesk.motion.reason_texts import reason
from servodesk_protocol.cia402 import (
    CONTROLWORD,
    CW_HALT,
    MODES_OF_OPERATION,
    SW_MODE_BIT12,
    OperationMode,
    make_enable_operation,
)

log = logging.getLogger(__name__)
M = OperationMode
DEFAULT_TORQUE_SLOPE = 100.0  # % rated torque per second: 6087h = 1, the drive's finest step


class Moves:
    """Set-points: PP moves (one, or a queue fed as each target is reached) and PV/PT jogs."""

    def __init__(self, drive: DriveIo, readings: Readings, limits: Limits) -> None:
        self._drive, self._readings, self._limits = drive, readings, limits

    # ------------------------------------------------------------------ profile position

    async def move(self, node: int, request: MoveRequest) -> DriveState:
        """One PP set-point (absolute or relative) with 6081h/6083h/6084h. A queued sequence
        running on the axis is dropped."""
        self._drive.axis(node).cancel_queue()
        await self._pp_setpoint(node, request)
        return await self._readings.state(node)

    async def move_queue(self, node: int, request: MoveQueueRequest) -> DriveState:
        """A sequence of set-points: the first is sent now, each next one once the axis has
        reached the previous target (the way every profile takes it, MDi included)."""
        axis = self._drive.axis(node)
        axis.cancel_queue()
        for step in request.moves:  # all checked before the first frame
            self._limits.check_velocity(node, step.velocity_rpm)
        await self._pp_setpoint(node, request.moves[0])
        axis.queued = list(request.moves[1:])
        if axis.queued:
            axis.queue_task = asyncio.create_task(self._run_queue(node))
        return await self._readings.state(node)

    async def _run_queue(self, node: int) -> None:
        axis = self._drive.axis(node)
        try:
            while axis.queued:
                reached = await self._wait_reached(node, self._drive.settings.motion_move_timeout)
                if not reached:
                    log.warning(
                        "node %d: queued move did not reach its target; queue dropped", node
                    )
                    break
                step = axis.queued.pop(0)
                if not isinstance(step, MoveRequest):
                    break
                await self._pp_setpoint(node, step)
        except ServodeskError as error:
            log.warning("node %d: queued move stopped: %s", node, error)
        finally:
            axis.queued.clear()
            if axis.queue_task is asyncio.current_task():
                axis.queue_task = None

    async def _wait_reached(self, node: int, timeout: float) -> bool:
        axis = self._drive.axis(node)
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        while loop.time() < deadline:
            state = await self._readings.state(node)
            if state.move is None or state.move.phase in ("error", "interrupted"):
                return False
            if state.move.phase == "reached":
                return True
            await asyncio.sleep(self._drive.settings.motion_poll_interval)
        return axis.move is not None and axis.move.phase == "reached"

    async def _pp_setpoint(self, node: int, request: MoveRequest) -> None:
        """MDi-S1-C CANopen manual §3.4.2: write the target, then bit 4 0 → 1; the drive
        acknowledges with statusword bit 12; bit 4 back to 0. Bit 12 still 1 means the drive
        cannot take a new set-point yet (MDi: until the running move ended; others: while
        their one-set-point buffer is full), so that is waited for first."""
        axis = self._drive.axis(node)
        units = self._drive.units(node)
        self._limits.check_velocity(node, request.velocity_rpm)
        await self._readings.require_enabled(node)
        snap = axis.last
        current = snap.position if snap and snap.position is not None else 0
        base = axis.target_user if axis.target_user is not None else current
        delta = units.rev_to_user(request.position_rev)
        target = base + delta if request.relative else delta
        self._limits.check_travel(node, units.user_to_rev(target))
        await self._readings.set_mode(node, M.PROFILE_POSITION)
        accel = units.rpm_s_to_acceleration(
            request.acceleration_rpm_s or self._drive.settings.motion_default_acceleration_rpm_s
        )
        immediately = request.immediately and self._immediate_supported(node)
        # absolute target written even for relative requests: the drive's "last target" after
        # an enable is not known to the tool, so relative moves are made absolute here
        await self._drive.write(node, io.TARGET_POSITION, 0, target, io.I32)
        await self._drive.write(
            node, io.PROFILE_VELOCITY, 0, units.rpm_to_velocity(request.velocity_rpm), io.U32
        )
        await self._drive.write(node, io.PROFILE_ACCELERATION, 0, accel, io.U32)
        await self._drive.write(node, io.PROFILE_DECELERATION, 0, accel, io.U32)
        idle = make_enable_operation(change_immediately=immediately)
        await self._drive.controlword(node, idle)  # bit 4 = 0 so the next write is an edge
        if not immediately:
            free, _ = await self._readings.wait(
                node, lambda w: not w & SW_MODE_BIT12, self._drive.settings.motion_move_timeout
            )
            if not free:
                raise MotionBusyError(node, "error.setpoint_held")
        await self._drive.controlword(
            node, make_enable_operation(new_setpoint=True, change_immediately=immediately)
        )
        acked, _ = await self._readings.wait(
            node, lambda w: bool(w & SW_MODE_BIT12), self._drive.settings.motion_setpoint_timeout
        )
        await self._drive.controlword(node, idle)
        if not acked:
            raise await self._readings.blocked(
                node,
                extra=[reason("timeout", "reason.setpoint_not_acknowledged")],
            )
        axis.target_user = target
        axis.move = MoveProgress(
            target_inc=units.user_to_inc(target), phase="moving", queued=len(axis.queued)
        )

    # ------------------------------------------------------------------ jog (PV, PT)

    async def jog_start(
        self,
        node: int,
        mode: Literal["pv", "pt"],
        value: float,
        *,
        acceleration_rpm_s: float | None = None,
        torque_slope_pct_s: float | None = None,
    ) -> None:
        """PV: 60FFh at `value` rpm over 6083h/6084h. PT: 6071h at `value` % rated torque over
        the slope 6087h; the drive caps the speed at its overspeed object (jog_ramp's
        velocity_limit_rpm). The halt bit is cleared: this re-arms a jog that stop() halted.

        Only what the drive does not hold already is written, the set-point as early as it is
        safe: first while the drive cannot follow it yet (halted, or in another mode), else
        after the ramp. From a known enabled state (a TPDO's statusword) that puts the
        set-point on the bus within 3 exchanges; nothing is read to answer."""
        axis = self._drive.axis(node)
        axis.cancel_queue()
        self._limits.check_jog(node, mode, value)
        ramp = self.jog_ramp(node, mode, acceleration_rpm_s, torque_slope_pct_s)
        await self._readings.require_enabled(node)
        units = self._drive.units(node)
        axis.move = None
        if mode == "pv":
            wanted = M.PROFILE_VELOCITY
            accel = units.rpm_s_to_acceleration(ramp.acceleration_rpm_s or 0.0)
            ramps = [(io.PROFILE_ACCELERATION, accel), (io.PROFILE_DECELERATION, accel)]
            setpoint = (io.TARGET_VELOCITY, units.rpm_to_velocity(value), io.I32)
        else:
            wanted = M.PROFILE_TORQUE
            slope = units.pct_per_s_to_slope(ramp.torque_slope_pct_s or DEFAULT_TORQUE_SLOPE)
            ramps = [(io.TORQUE_SLOPE, slope)]
            setpoint = (io.TARGET_TORQUE, units.pct_to_torque(value), io.I16)
        changed = [(index, v, io.U32) for index, v in ramps if axis.sent.get(index) != v]
        shown = self._mode_shown(node)
        in_mode = shown == int(wanted)
        # known not to follow 60FFh/6071h yet: in another mode, or halted (an unknown state
        # takes the ramp first, so the set-point never runs on an old one)
        held = (shown is not None and not in_mode) or bool(axis.sent.get(CONTROLWORD, 0) & CW_HALT)
        for index, v, kind in [setpoint, *changed] if held else [*changed, setpoint]:
            await self._drive.write(node, index, 0, v, kind)
        if not in_mode:
            await self._readings.set_mode(node, wanted)
        if axis.sent.get(CONTROLWORD) != make_enable_operation():
            await self._drive.controlword(node, make_enable_operation())  # halt off
        axis.jog = mode

    def _mode_shown(self, node: int) -> int | None:
        """6061h as known without asking: a TPDO carrying it, else the mode ServoDesk set (and
        saw shown) with no stop or other write since; None when unknown."""
        given, _ = self._drive.carried(node)
        shown = given.get("mode_display")
        return shown if shown is not None else self._drive.axis(node).sent.get(MODES_OF_OPERATION)

    def jog_ramp(
        self,
        node: int,
        mode: Literal["pv", "pt"],
        acceleration_rpm_s: float | None = None,
        torque_slope_pct_s: float | None = None,
    ) -> JogRamp:
        """The ramp a jog runs with (the defaults filled in) and, in PT, the speed limit the
        drive applies: its max speed object (MDi PA-103 2006h:08, else 6080h Max motor speed),
        as read from the drive, else its dictionary's default."""
        if mode == "pv":
            accel = acceleration_rpm_s or self._drive.settings.motion_default_acceleration_rpm_s
            return JogRamp(acceleration_rpm_s=accel)
        rpm, source = self._limits.pt_speed_limit(node)
        return JogRamp(
            torque_slope_pct_s=torque_slope_pct_s or DEFAULT_TORQUE_SLOPE,
            velocity_limit_rpm=rpm,
            velocity_limit_source=source,
        )

    async def jog_update(self, node: int, value: float) -> None:
        """A new speed (rpm) or torque (%) for the running jog; limits checked first."""
        axis = self._drive.axis(node)
        if axis.jog is None:
            raise MotionBusyError(node, "error.no_jog")
        self._limits.check_jog(node, axis.jog, value)
        units = self._drive.units(node)
        if axis.jog == "pv":
            await self._drive.write(
                node, io.TARGET_VELOCITY, 0, units.rpm_to_velocity(value), io.I32
            )
        else:
            await self._drive.write(node, io.TARGET_TORQUE, 0, units.pct_to_torque(value), io.I16)

    def _immediate_supported(self, node: int) -> bool:
        data = self._drive.registry.profile_data(node)
        return data is None or data.quirks.pp_immediate_setpoint  # MDi: only non-immediate
