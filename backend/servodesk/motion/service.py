"""MotionService: the CiA 402 drive panel over each node's session.

Every drive access is a step on the node's worker thread (`NodeSession.run`); stopping uses the
session's priority lane so it never waits behind queued SDO work or a transaction. The state
machine follows MDi-S1-C CANopen manual §3.2 (figure 3.2) with the controlwords of
`servodesk_protocol.cia402`; a transition that does not happen within the drive's time
(settings.motion_transition_timeout[s]) raises EnableBlockedError naming what blocks it.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable

import canopen

from servodesk.errors import CommTimeoutError, NodeStoppedError, SdoAbortError, ServodeskError
from servodesk.events.bus import BusEvent, EventKind
from servodesk.motion import drive_io as io
from servodesk.motion.core import state_of
from servodesk.motion.ip import IpOps
from servodesk.motion.schemas import DriveCommand, DriveState, EnableReason
from servodesk.motion.stopping import (
    QUICK_STOP_DECELERATION,
    StopPlan,
    quick_stop_axis,
    stop_axis,
)
from servodesk.motion.words import state_label
from servodesk.network.sync import SyncService
from servodesk.nodes.access import NodeAccess
from servodesk.pdo.commands import RpdoRoutes
from servodesk.pdo.feed import TpdoFeeds
from servodesk.pdo.service import PdoService
from servodesk.settings import Settings
from servodesk_protocol.cia402 import (
    CONTROLWORD,
    Cia402State,
    enable_sequence,
    make_disable_operation,
    make_disable_voltage,
    make_enable_operation,
    make_fault_reset,
    make_quick_stop,
    make_shutdown,
    make_switch_on,
)

S = Cia402State
log = logging.getLogger(__name__)

DEVICE_PROFILE_AREA = 0x6000  # CiA 402 objects from here; 1000h–5FFFh are not motion's
NOT_A_WRITE = frozenset({"jog-stop", "pdo-apply"})  # tool-write events that leave 6040h… be
RESETS = frozenset({"reset-node", "reset-communication"})  # NMT commands that reset objects
MAX_STEPS = 8  # the longest way to Operation enabled (from Quick stop active) is 4 steps
FAULTED = (S.FAULT, S.FAULT_REACTION_ACTIVE)  # enable refuses these: a fault is reset on purpose
# set-points a drive follows at once in Operation enabled (PV, PT): 0 before every enable
ZEROED_ON_ENABLE = ((io.TARGET_VELOCITY, io.I32), (io.TARGET_TORQUE, io.I16))


class MotionService(IpOps):
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
        super().__init__(registry, settings, sync=sync, on_statusword=on_statusword)
        self._pdos = pdos
        if pdos is not None:
            self._feeds = TpdoFeeds(
                pdos,
                operational=self._operational,
                sync_period_s=lambda: _sync_period_s(sync),
            )
            self._routes = RpdoRoutes(pdos, operational=self._operational)

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

    async def polled_state(self, node: int) -> DriveState:
        """The drive state the pages poll: one reading per `drive_poll_period` shared by every
        caller, its SDO part within `drive_poll_sdo_budget` uploads (what TPDOs carry is
        current in every reading)."""
        axis = self._axis(node)
        async with axis.poll_lock:
            if axis.polled is not None and (
                time.monotonic() - axis.polled_at < self._settings.drive_poll_period
            ):
                return axis.polled
            started = time.monotonic()
            snap = await self._snapshot(node, sdo_budget=self._settings.drive_poll_sdo_budget)
            state = self._build(node, snap)
            if started >= axis.commanded_at:  # not shared when a command came meanwhile
                axis.polled, axis.polled_at = state, time.monotonic()
            return state

    # ------------------------------------------------------------------ state machine

    async def enable(self, node: int) -> DriveState:
        """To Operation enabled from whatever state the drive is in (enable_sequence; quick stop
        left through Switch on disabled). A fault is never reset here: a drive in Fault (or
        falling into it on the way) answers EnableBlockedError naming the fault, with nothing
        sent — resetting it is its own act (fault_reset), after its cause is removed."""
        snap = await self._reachable(node)
        state = state_of(snap.statusword)
        if state in FAULTED:
            raise await self._blocked(node)
        await self._refresh_statics(node)
        if state is S.OPERATION_ENABLED:
            return self._build(node, snap)  # nothing to do: a running move or jog runs on
        self._axis(node).target_user = None
        await self._zero_setpoints(node)
        for _ in range(MAX_STEPS):
            if state is S.OPERATION_ENABLED:
                return await self.state(node)
            if state in FAULTED:
                break
            left = _leaves(state)
            if state is S.NOT_READY_TO_SWITCH_ON:
                # the drive leaves it by itself (transition 1)
                ok, sw = await self._wait(node, left, self._transition_timeout(node))
            else:
                await self._controlword(node, enable_sequence(state)[0])
                ok, sw = await self._wait(node, left, self._transition_timeout(node))
            if not ok:
                raise await self._blocked(node)
            state = state_of(sw)
        raise await self._blocked(node)

    async def _zero_setpoints(self, node: int) -> None:
        """Target velocity and target torque to 0 before the drive is enabled: in PV and PT a
        drive runs to whatever 60FFh / 6071h hold the moment it is in Operation enabled, and
        after a quick stop they still hold the stopped jog's set-point."""
        od = self._registry.od(node)
        for index, kind in ZEROED_ON_ENABLE:
            if od.get(index, 0) is None:
                continue
            try:
                await self._write(node, index, 0, 0, kind)
            except SdoAbortError as error:  # not writable on this drive: it cannot hold one
                log.info("node %d: %04Xh not zeroed before enable: %s", node, index, error)

    async def disable(self, node: int) -> DriveState:
        """Power stage off: shutdown (transitions 8, 6) to Ready to switch on; a quick stop
        is left with disable voltage (12)."""
        self._drop_tasks(node, "stopped: the drive was disabled")
        snap = await self._reachable(node)
        state = state_of(snap.statusword)
        if state in (S.OPERATION_ENABLED, S.SWITCHED_ON):
            await self._controlword(node, make_shutdown())
            ok, _ = await self._wait(
                node, lambda w: state_of(w) is S.READY_TO_SWITCH_ON, self._transition_timeout(node)
            )
        elif state is S.QUICK_STOP_ACTIVE:
            await self._controlword(node, make_disable_voltage())
            ok, _ = await self._wait(
                node, lambda w: state_of(w) is S.SWITCH_ON_DISABLED, self._transition_timeout(node)
            )
        else:
            ok = True
        if not ok:
            raise await self._blocked(node, target=S.READY_TO_SWITCH_ON)
        return await self.state(node)

    async def quick_stop(self, node: int) -> DriveState:
        """Quick stop (controlword 0002h, transition 11): the drive stops as 605Ah says and
        stays in Quick stop active (5–8) or ends in Switch on disabled. Sent on the priority
        lane; in any other state 0002h only disables voltage, so it is always safe."""
        self._drop_tasks(node, "stopped by quick stop (controlword bit 2 = 0)")
        await self._registry.session(node).priority(
            lambda r: io.write_controlword(r, make_quick_stop()), what=f"quick stop node {node}"
        )
        self._axis(node).sent[CONTROLWORD] = make_quick_stop()
        self._axis(node).commanded()
        try:
            return await self.state(node)
        except CommTimeoutError as error:
            # the stop went out and the drive confirmed it: a busy drive that is slow to answer
            # the reading after it does not turn that into a failed stop
            log.warning("node %d: quick stop sent; the state after it: %s", node, error)
            return self._unreadable_state(node)

    async def fault_reset(self, node: int) -> DriveState:
        """Fault → Switch on disabled (15) on a real 0 → 1 edge of bit 7: 0000h, then 0080h,
        then 0000h again (a bit 7 left high blocks every later command)."""
        snap = await self._reachable(node)
        if state_of(snap.statusword) is not S.FAULT and not snap.statusword & 0x0008:
            return self._build(node, snap)
        await self._controlword(node, make_disable_voltage())
        await self._controlword(node, make_fault_reset())
        ok, _ = await self._wait(
            node, lambda w: state_of(w) is not S.FAULT, self._transition_timeout(node)
        )
        await self._controlword(node, make_disable_voltage())
        if not ok:
            raise await self._blocked(node, target=S.SWITCH_ON_DISABLED)
        return await self.state(node)

    async def command(self, node: int, command: DriveCommand) -> DriveState:
        """One controlword command of the state machine (MDi-S1-C CANopen manual §3.2.2,
        figure 3.2): shutdown 0006h, switch on 0007h, enable operation 000Fh, disable operation
        0007h, disable voltage 0000h; quick stop and fault reset as quick_stop()/fault_reset().
        A command with no transition from the drive's state sends nothing; a transition that
        does not happen in the drive's time raises EnableBlockedError with what blocks it."""
        if command == "quick_stop":
            return await self.quick_stop(node)
        if command == "fault_reset":
            return await self.fault_reset(node)
        word, target, starts = COMMANDS[command]
        name = command.replace("_", " ")
        snap = await self._reachable(node)
        state = state_of(snap.statusword)
        number = starts.get(state)
        if number is None:
            raise await self._blocked(
                node,
                extra=[_no_transition(name, state, starts)],
                target=target,
                goal=f"take {name}",
            )
        if target is not S.OPERATION_ENABLED:
            self._drop_tasks(node)
        else:
            await self._refresh_statics(node)
            self._axis(node).target_user = None
            await self._zero_setpoints(node)
        await self._controlword(node, word)
        ok, _ = await self._wait(
            node, lambda w: state_of(w) is target, self._transition_timeout(node)
        )
        if not ok:
            raise await self._blocked(node, target=target, goal=f"take {name} ({number})")
        self._axis(node).last_transition = f"{name} ({number})"
        return await self.state(node)

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
            self._axis(node).sent[CONTROLWORD] = make_quick_stop()
            self._axis(node).commanded()
            return "quick stop"
        plan = self._stop_plan(node, deceleration_rpm_s, drive_deceleration)
        outcome = await session.priority(lambda r: stop_axis(r, plan), what=what)
        self._axis(node).sent.update(outcome.wrote)
        self._axis(node).commanded()
        self._saw_statusword(node, outcome.statusword)
        return outcome.how

    def _stop_plan(
        self, node: int, deceleration_rpm_s: float | None, drive_deceleration: bool
    ) -> StopPlan:
        od = self._registry.od(node)
        axis = self._axis(node)
        supported = axis.statics.supported_raw if axis.statics else None
        pv = (
            bool(supported >> 2 & 1)  # 6502h bit 2: profile velocity
            if supported is not None
            else od.get(io.TARGET_VELOCITY, 0) is not None
        )
        decel = None
        if deceleration_rpm_s is not None:
            decel = max(1, self._units(node).rpm_s_to_acceleration(deceleration_rpm_s))
        ramps = (io.PROFILE_DECELERATION, io.PROFILE_ACCELERATION)
        return StopPlan(
            deceleration=decel,
            use_drive_quick_stop_deceleration=drive_deceleration
            and od.get(QUICK_STOP_DECELERATION, 0) is not None,
            ramp_objects=tuple(i for i in ramps if od.get(i, 0) is not None),
            pv_supported=pv,
            has_target_torque=od.get(io.TARGET_TORQUE, 0) is not None,
        )

    async def velocity_rpm(self, node: int) -> float:
        """606Ch now, in rpm: from a TPDO carrying it, else one upload on the node's queue
        (the jog watchdog's reading)."""
        given, _ = self._carried(node)
        raw = given.get("velocity")
        if "velocity" not in given:
            raw = await self._run(
                node, lambda r: io.read(r, io.VELOCITY_ACTUAL, signed=True), "read 606Ch"
            )
        return self._units(node).actual_velocity_rpm(raw or 0)

    async def reading(self, node: int) -> tuple[float, float]:
        """606Ch (rpm) and 6064h (rev): what a jog's watch needs for its speed cap and
        ServoDesk's travel limits; from TPDOs carrying them, the rest in one step by SDO."""
        given, _ = self._carried(node)

        def read(remote: canopen.RemoteNode) -> tuple[int | None, int | None]:
            velocity = (
                given["velocity"]
                if "velocity" in given
                else io.read(remote, io.VELOCITY_ACTUAL, signed=True)
            )
            position = (
                given["position"]
                if "position" in given
                else io.read(remote, io.POSITION_ACTUAL, signed=True)
            )
            return velocity, position

        if "velocity" in given and "position" in given:
            velocity, position = given["velocity"], given["position"]
        else:
            velocity, position = await self._run(node, read, "read 606Ch and 6064h")
        units = self._units(node)
        rev = units.inc_to_rev(units.user_to_inc(position or 0))
        return units.actual_velocity_rpm(velocity or 0), rev

    def travel(self, node: int) -> tuple[float | None, float | None]:
        """ServoDesk's own travel limits (rev) of the node, as set with PUT …/drive/limits."""
        limits = self._axis(node).limits
        return limits.min_position_rev, limits.max_position_rev

    async def set_mode(self, node: int, mode: str) -> DriveState:
        """Write 6060h ("pp", "pv", "pt", "hm", "ip", …) and wait for 6061h to show it."""
        await self._set_mode(node, self._mode_value(node, mode))
        return await self.state(node)

    # ------------------------------------------------------------------ helpers

    def _drop_tasks(self, node: int, why: str | None = None) -> None:
        """Whatever the service was feeding the axis ends: queue, jog, IP stream; `why` is
        what an interrupted move says until the drive shows it."""
        axis = self._axis(node)
        axis.dropped_by = why
        # a stop writes the controlword on its own lane (and says what it wrote, stop())
        axis.sent.pop(CONTROLWORD, None)
        axis.stop_epoch += 1  # motion writes queued before it are refused (MotionCore._write)
        axis.commanded()
        axis.cancel_queue()
        axis.jog = None
        axis.target_user = None
        self.cancel_stream(node)

    async def _reachable(self, node: int) -> io.Snapshot:
        """A reading, or EnableBlockedError naming NMT Stopped / no answer."""
        try:
            return await self._snapshot(node)
        except (CommTimeoutError, NodeStoppedError) as error:
            reasons = (
                []
                if self._nmt(node) == "stopped"
                else [EnableReason(code="timeout", message=str(error))]
            )
            raise await self._blocked(node, extra=reasons) from error


def _sync_period_s(sync: SyncService | None) -> float | None:
    config = sync.get() if sync is not None else None
    if config is None or not config.producing or not config.period_us:
        return None
    return config.period_us / 1_000_000


# command -> (controlword, the state it leads to, {state it starts from: transition number})
COMMANDS: dict[str, tuple[int, Cia402State, dict[Cia402State, int]]] = {
    "shutdown": (
        make_shutdown(),
        S.READY_TO_SWITCH_ON,
        {S.SWITCH_ON_DISABLED: 2, S.SWITCHED_ON: 6, S.OPERATION_ENABLED: 8},
    ),
    "switch_on": (make_switch_on(), S.SWITCHED_ON, {S.READY_TO_SWITCH_ON: 3}),
    "enable_operation": (
        make_enable_operation(),
        S.OPERATION_ENABLED,
        {S.SWITCHED_ON: 4, S.QUICK_STOP_ACTIVE: 16},
    ),
    "disable_operation": (make_disable_operation(), S.SWITCHED_ON, {S.OPERATION_ENABLED: 5}),
    "disable_voltage": (
        make_disable_voltage(),
        S.SWITCH_ON_DISABLED,
        {
            S.READY_TO_SWITCH_ON: 7,
            S.OPERATION_ENABLED: 9,
            S.SWITCHED_ON: 10,
            S.QUICK_STOP_ACTIVE: 12,
        },
    ),
}


def _no_transition(name: str, state: Cia402State, starts: dict[Cia402State, int]) -> EnableReason:
    froms = ", ".join(f"{state_label(s)} ({n})" for s, n in starts.items())
    return EnableReason(
        code="no_transition",
        message=f"{name} takes no transition from {state_label(state)}: it works from "
        f"{froms}; nothing was sent",
    )


def _leaves(state: Cia402State) -> Callable[[int], bool]:
    """A statusword test: the drive is no longer in `state`."""
    return lambda statusword: state_of(statusword) is not state
