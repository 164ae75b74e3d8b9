"""MotionService: the CiA 402 drive panel over each node's session.

Every drive access is a step on the node's worker thread (`NodeSession.run`); stopping uses the
session's priority lane so it never waits behind queued SDO work or a transaction. The state
machine follows MDi-S1-C CANopen manual §3.2 (figure 3.2) with the controlwords of
`servodesk_protocol.cia402` (state_machine.py); a transition that does not happen within the
drive's time (settings.motion_transition_timeout[s]) raises EnableBlockedError naming what
blocks it.

The service is what the rest of the app calls (the routes, motion/safety.py and its jog
watchdog, the live channel, commissioning). It keeps the stop paths and the bus events itself;
the rest is done by small parts, each given the shared core and only the parts it calls, whose
methods it hands out as its own (docs/architecture.md, "The motion service"):

    DriveIo (core.py)                per-node axes; node steps, command writes (RPDO or SDO),
                                     6041h, what the TPDOs carry; the registry and settings
    Limits (drive_limits.py)         the limits in force, the drive's own read again, the checks
    Readings (readings.py)           readings and DriveState, the pages' poll, the jog watch's
                                     reading, waits, 6060h → 6061h, why a transition failed
    Moves (moves.py)                 PP set-points and queues, PV/PT jogs
    Homing (home.py)                 homing runs
    IpStreams (ip.py)                interpolated position streams (ip_stream.py: worker side)
    StateMachine (state_machine.py)  enable, disable, fault reset, controlword commands
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from servodesk.errors import CommTimeoutError, InvalidValueError, ServodeskError
from servodesk.events.bus import BusEvent, EventKind
from servodesk.models.motion import DriveCommand, DriveState
from servodesk.motion import drive_io as io
from servodesk.motion.core import DriveIo
from servodesk.motion.drive_limits import Limits
from servodesk.motion.home import Homing
from servodesk.motion.ip import IpStreams
from servodesk.motion.moves import Moves
from servodesk.motion.readings import Readings
from servodesk.motion.state_machine import StateMachine
from servodesk.motion.stopping import (
    QUICK_STOP_DECELERATION,
    StopPlan,
    quick_stop_axis,
    stop_axis,
)
from servodesk.motion.words import MODE_VALUES
from servodesk.network.sync import SyncService
from servodesk.nodes.access import NodeAccess
from servodesk.pdo.commands import RpdoRoutes
from servodesk.pdo.feed import TpdoFeeds
from servodesk.pdo.service import PdoService
from servodesk.settings import Settings
from servodesk_protocol.cia402 import CONTROLWORD, OperationMode, make_quick_stop

log = logging.getLogger(__name__)

DEVICE_PROFILE_AREA = 0x6000  # CiA 402 objects from here; 1000h–5FFFh are not motion's
NOT_A_WRITE = frozenset({"jog-stop", "pdo-apply"})  # tool-write events that leave 6040h… be
RESETS = frozenset({"reset-node", "reset-communication"})  # NMT commands that reset objects


class MotionService:
    def __init__(
        self,
        registry: NodeAccess,
        settings: Settings,
        pdos: PdoService | None = None,
        *,
        sync: SyncService | None = None,
        on_statusword: Callable[[int, int], None] | None = None,
    ) -> None:
        """`on_statusword(node, statusword)` is called on the event loop after every read of
        6041h (services.py hands it to the fault service, which publishes state changes)."""
        self._registry = registry
        self._feeds: TpdoFeeds | None = None  # the drive state from TPDOs
        routes: RpdoRoutes | None = None  # commands in RPDOs
        if pdos is not None:
            self._feeds = TpdoFeeds(
                pdos,
                operational=self._operational,
                sync_period_s=lambda: _sync_period_s(sync),
            )
            routes = RpdoRoutes(pdos, operational=self._operational)
        drive = DriveIo(
            registry, settings, feeds=self._feeds, routes=routes, on_statusword=on_statusword
        )
        limits = Limits(drive)
        readings = Readings(drive, limits)
        moves = Moves(drive, readings, limits)
        homing = Homing(drive, readings, limits)
        streams = IpStreams(drive, readings, limits, sync=sync, routes=routes)
        machine = StateMachine(drive, readings, limits, drop_tasks=self._drop_tasks)
        self._drive, self._readings, self._machine = drive, readings, machine
        # The rest of the public interface is the parts' own methods (their signatures and
        # docstrings): callers outside motion/ see the MotionService they always did.
        self.units, self.forget_sent = drive.units, drive.forget_sent
        self.limits, self.set_limits = limits.limits, limits.set_limits
        self.pt_speed_limit, self.travel = limits.pt_speed_limit, limits.travel
        self.state, self.polled_state = readings.state, readings.polled_state
        self.velocity_rpm, self.reading = readings.velocity_rpm, readings.reading
        self.enable, self.disable = machine.enable, machine.disable
        self.fault_reset = machine.fault_reset
        self.move, self.move_queue = moves.move, moves.move_queue
        self.jog_start, self.jog_update = moves.jog_start, moves.jog_update
        self.jog_ramp = moves.jog_ramp
        self.homing_methods, self.home = homing.homing_methods, homing.home
        self.ip_stream, self.cancel_stream = streams.ip_stream, streams.cancel_stream
        self.stream_points_sent = streams.stream_points_sent

    def close(self) -> None:
        if self._feeds is not None:
            self._feeds.close()

    def on_event(self, event: BusEvent) -> None:
        """A write not the motion service's own, a boot-up, an NMT command or a new bus: what it
        last wrote may no longer be what the drive holds."""
        index = event.data.get("index")
        profile_object = not isinstance(index, int) or index >= DEVICE_PROFILE_AREA
        if event.kind is EventKind.TOOL_WRITE:
            if profile_object and event.data.get("action") not in NOT_A_WRITE:
                self.forget_sent(event.node)  # a CiA 402 object, or a whole load: maybe ours
        elif event.kind is EventKind.BOOT_UP or (
            event.kind is EventKind.NMT and event.data.get("command") in RESETS
        ):
            self.forget_sent(event.node)  # the drive's objects back to their stored values
        elif event.kind is EventKind.BUS:
            self.forget_sent()

    def _operational(self, node: int) -> bool:
        try:
            info = self._registry.info(node)
        except ServodeskError:
            return False
        return info.online and str(info.nmt_state) == "operational"

    # ------------------------------------------------------------------ state machine

    async def quick_stop(self, node: int) -> DriveState:
        """Quick stop (controlword 0002h, transition 11): the drive stops as 605Ah says and
        stays in Quick stop active (5–8) or ends in Switch on disabled. Sent on the priority
        lane; in any other state 0002h only disables voltage, so it is always safe."""
        self._drop_tasks(node, "stopped by quick stop (controlword bit 2 = 0)")
        await self._registry.session(node).priority(
            lambda r: io.write_controlword(r, make_quick_stop()), what=f"quick stop node {node}"
        )
        self._drive.axis(node).sent[CONTROLWORD] = make_quick_stop()
        self._drive.axis(node).commanded()
        try:
            return await self.state(node)
        except CommTimeoutError as error:
            # the stop went out and the drive confirmed it: a busy drive that is slow to answer
            # the reading after it does not turn that into a failed stop
            log.warning("node %d: quick stop sent; the state after it: %s", node, error)
            return self._readings.unreadable_state(node)

    async def command(self, node: int, command: DriveCommand) -> DriveState:
        """One controlword command of the state machine (StateMachine.command); quick stop and
        fault reset as quick_stop()/fault_reset()."""
        if command == "quick_stop":
            return await self.quick_stop(node)
        if command == "fault_reset":
            return await self.fault_reset(node)
        return await self._machine.command(node, command)

    async def stop(
        self,
        node: int,
        *,
        reason: str,
        quick: bool = False,
        deceleration_rpm_s: float | None = None,
        drive_deceleration: bool = False,
    ) -> str:
        """Bring the axis to a stop without waiting behind queued work (priority lane); says
        how ("halt", "halt in profile velocity", "quick stop", "nothing moves").

        Default: the halt bit (8) in Operation enabled — the axis decelerates and stays
        enabled, so a hold-to-run jog can be re-armed; a torque jog is braked in profile
        velocity (motion/stopping.py). `deceleration_rpm_s` bounds the ramp (6083h/6084h
        written first), `drive_deceleration` takes the drive's 6085h where it is steeper.
        `quick`: quick stop 0002h, which ramps as 605Ah says and never enables anything.
        """
        self._drop_tasks(
            node,
            "stopped by quick stop (controlword bit 2 = 0)"
            if quick
            else f"halted (controlword bit 8) before its target: {reason}",
        )
        session = self._registry.session(node)
        what = f"stop node {node}: {reason}"
        if quick:
            await session.priority(quick_stop_axis, what=what)
            self._drive.axis(node).sent[CONTROLWORD] = make_quick_stop()
            self._drive.axis(node).commanded()
            return "quick stop"
        plan = self._stop_plan(node, deceleration_rpm_s, drive_deceleration)
        outcome = await session.priority(lambda r: stop_axis(r, plan), what=what)
        self._drive.axis(node).sent.update(outcome.wrote)
        self._drive.axis(node).commanded()
        self._drive.saw_statusword(node, outcome.statusword)
        return outcome.how

    def _stop_plan(
        self, node: int, deceleration_rpm_s: float | None, drive_deceleration: bool
    ) -> StopPlan:
        od = self._registry.od(node)
        axis = self._drive.axis(node)
        supported = axis.statics.supported_raw if axis.statics else None
        pv = (
            bool(supported >> 2 & 1)  # 6502h bit 2: profile velocity
            if supported is not None
            else od.get(io.TARGET_VELOCITY, 0) is not None
        )
        decel = None
        if deceleration_rpm_s is not None:
            decel = max(1, self._drive.units(node).rpm_s_to_acceleration(deceleration_rpm_s))
        ramps = (io.PROFILE_DECELERATION, io.PROFILE_ACCELERATION)
        return StopPlan(
            deceleration=decel,
            use_drive_quick_stop_deceleration=drive_deceleration
            and od.get(QUICK_STOP_DECELERATION, 0) is not None,
            ramp_objects=tuple(i for i in ramps if od.get(i, 0) is not None),
            pv_supported=pv,
            has_target_torque=od.get(io.TARGET_TORQUE, 0) is not None,
        )

    async def set_mode(self, node: int, mode: str) -> DriveState:
        """Write 6060h ("pp", "pv", "pt", "hm", "ip", …) and wait for 6061h to show it."""
        await self._readings.set_mode(node, _mode_value(mode))
        return await self.state(node)

    # ------------------------------------------------------------------ helpers

    def _drop_tasks(self, node: int, why: str | None = None) -> None:
        """Whatever the service was feeding the axis ends: queue, jog, IP stream; `why` is
        what an interrupted move says until the drive shows it."""
        axis = self._drive.axis(node)
        axis.dropped_by = why
        # a stop writes the controlword on its own lane (and says what it wrote, stop())
        axis.sent.pop(CONTROLWORD, None)
        axis.stop_epoch += 1  # motion writes queued before it are refused (DriveIo.write)
        axis.commanded()
        axis.cancel_queue()
        axis.jog = None
        axis.target_user = None
        self.cancel_stream(node)


def _sync_period_s(sync: SyncService | None) -> float | None:
    config = sync.get() if sync is not None else None
    if config is None or not config.producing or not config.period_us:
        return None
    return config.period_us / 1_000_000


def _mode_value(mode: str) -> OperationMode:
    value = MODE_VALUES.get(mode)
    if value is None:
        raise InvalidValueError(f"unknown operating mode {mode!r}")
    return OperationMode(value)
