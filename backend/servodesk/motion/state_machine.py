"""The CiA 402 state machine commands: enable, disable, fault reset and the single controlword
commands, following MDi-S1-C CANopen manual §3.2 (figure 3.2) with the controlwords of
`servodesk_protocol.cia402`; a transition that does not happen within the drive's time
(settings.motion_transition_timeout[s]) raises EnableBlockedError naming what blocks it."""

from __future__ import annotations

import logging
from collections.abc import Callable

from servodesk.errors import CommTimeoutError, NodeStoppedError, SdoAbortError
from servodesk.models.motion import DriveCommand, DriveState, EnableReason
from servodesk.motion import drive_io as io
from servodesk.motion.core import DriveIo, state_of
from servodesk.motion.drive_limits import Limits
from servodesk.motion.readings import Readings
from servodesk.motion.reason_texts import reason
from servodesk.motion.words import state_label, taken
from servodesk_protocol.cia402 import (
    Cia402State,
    enable_sequence,
    make_disable_operation,
    make_disable_voltage,
    make_enable_operation,
    make_fault_reset,
    make_shutdown,
    make_switch_on,
)

S = Cia402State
log = logging.getLogger(__name__)

MAX_STEPS = 8  # the longest way to Operation enabled (from Quick stop active) is 4 steps
FAULTED = (S.FAULT, S.FAULT_REACTION_ACTIVE)  # enable refuses these: a fault is reset on purpose
# set-points a drive follows at once in Operation enabled (PV, PT): 0 before every enable
ZEROED_ON_ENABLE = ((io.TARGET_VELOCITY, io.I32), (io.TARGET_TORQUE, io.I16))


class StateMachine:
    """The commands that take the drive from one CiA 402 state to another (not the stops:
    MotionService keeps those, on the priority lane)."""

    def __init__(
        self,
        drive: DriveIo,
        readings: Readings,
        limits: Limits,
        *,
        drop_tasks: Callable[[int, str | None], None],
    ) -> None:
        self._drive, self._readings, self._limits = drive, readings, limits
        self._drop_tasks = drop_tasks  # whatever the service feeds the axis ends (MotionService)

    async def enable(self, node: int) -> DriveState:
        """To Operation enabled from whatever state the drive is in (enable_sequence; quick stop
        left through Switch on disabled). A fault is never reset here: a drive in Fault (or
        falling into it on the way) answers EnableBlockedError naming the fault, with nothing
        sent — resetting it is its own act (fault_reset), after its cause is removed."""
        snap = await self._reachable(node)
        state = state_of(snap.statusword)
        if state in FAULTED:
            raise await self._readings.blocked(node)
        await self._limits.refresh_statics(node)
        if state is S.OPERATION_ENABLED:
            return self._readings.build(node, snap)  # nothing to do: a running move or jog runs on
        self._drive.axis(node).target_user = None
        await self._zero_setpoints(node)
        for _ in range(MAX_STEPS):
            if state is S.OPERATION_ENABLED:
                return await self._readings.state(node)
            if state in FAULTED:
                break
            left = _leaves(state)
            if state is S.NOT_READY_TO_SWITCH_ON:
                # the drive leaves it by itself (transition 1)
                ok, sw = await self._readings.wait(
                    node, left, self._readings.transition_timeout(node)
                )
            else:
                await self._drive.controlword(node, enable_sequence(state)[0])
                ok, sw = await self._readings.wait(
                    node, left, self._readings.transition_timeout(node)
                )
            if not ok:
                raise await self._readings.blocked(node)
            state = state_of(sw)
        raise await self._readings.blocked(node)

    async def _zero_setpoints(self, node: int) -> None:
        """Target velocity and target torque to 0 before the drive is enabled: in PV and PT a
        drive runs to whatever 60FFh / 6071h hold the moment it is in Operation enabled, and
        after a quick stop they still hold the stopped jog's set-point."""
        od = self._drive.registry.od(node)
        for index, kind in ZEROED_ON_ENABLE:
            if od.get(index, 0) is None:
                continue
            try:
                await self._drive.write(node, index, 0, 0, kind)
            except SdoAbortError as error:  # not writable on this drive: it cannot hold one
                log.info("node %d: %04Xh not zeroed before enable: %s", node, index, error)

    async def disable(self, node: int) -> DriveState:
        """Power stage off: shutdown (transitions 8, 6) to Ready to switch on; a quick stop
        is left with disable voltage (12)."""
        self._drop_tasks(node, "stopped: the drive was disabled")
        snap = await self._reachable(node)
        state = state_of(snap.statusword)
        if state in (S.OPERATION_ENABLED, S.SWITCHED_ON):
            await self._drive.controlword(node, make_shutdown())
            ok, _ = await self._readings.wait(
                node,
                lambda w: state_of(w) is S.READY_TO_SWITCH_ON,
                self._readings.transition_timeout(node),
            )
        elif state is S.QUICK_STOP_ACTIVE:
            await self._drive.controlword(node, make_disable_voltage())
            ok, _ = await self._readings.wait(
                node,
                lambda w: state_of(w) is S.SWITCH_ON_DISABLED,
                self._readings.transition_timeout(node),
            )
        else:
            ok = True
        if not ok:
            raise await self._readings.blocked(node, target=S.READY_TO_SWITCH_ON)
        return await self._readings.state(node)

    async def fault_reset(self, node: int) -> DriveState:
        """Fault → Switch on disabled (15) on a real 0 → 1 edge of bit 7: 0000h, then 0080h,
        then 0000h again (a bit 7 left high blocks every later command)."""
        snap = await self._reachable(node)
        if state_of(snap.statusword) is not S.FAULT and not snap.statusword & 0x0008:
            return self._readings.build(node, snap)
        await self._drive.controlword(node, make_disable_voltage())
        await self._drive.controlword(node, make_fault_reset())
        ok, _ = await self._readings.wait(
            node, lambda w: state_of(w) is not S.FAULT, self._readings.transition_timeout(node)
        )
        await self._drive.controlword(node, make_disable_voltage())
        if not ok:
            raise await self._readings.blocked(node, target=S.SWITCH_ON_DISABLED)
        return await self._readings.state(node)

    async def command(self, node: int, command: DriveCommand) -> DriveState:
        """One controlword command of the state machine (MDi-S1-C CANopen manual §3.2.2,
        figure 3.2): shutdown 0006h, switch on 0007h, enable operation 000Fh, disable operation
        0007h, disable voltage 0000h (quick stop and fault reset: MotionService.command).
        A command with no transition from the drive's state sends nothing; a transition that
        does not happen in the drive's time raises EnableBlockedError with what blocks it."""
        word, target, starts = COMMANDS[command]
        name = command.replace("_", " ")
        snap = await self._reachable(node)
        state = state_of(snap.statusword)
        number = starts.get(state)
        if number is None:
            raise await self._readings.blocked(
                node,
                extra=[_no_transition(name, state, starts)],
                target=target,
                goal=f"take {name}",
            )
        if target is not S.OPERATION_ENABLED:
            self._drop_tasks(node, None)
        else:
            await self._limits.refresh_statics(node)
            self._drive.axis(node).target_user = None
            await self._zero_setpoints(node)
        await self._drive.controlword(node, word)
        ok, _ = await self._readings.wait(
            node, lambda w: state_of(w) is target, self._readings.transition_timeout(node)
        )
        if not ok:
            raise await self._readings.blocked(node, target=target, goal=f"take {name} ({number})")
        self._drive.axis(node).last_transition = taken(command, number)
        return await self._readings.state(node)

    async def _reachable(self, node: int) -> io.Snapshot:
        """A reading, or EnableBlockedError naming NMT Stopped / no answer."""
        try:
            return await self._readings.snapshot(node)
        except (CommTimeoutError, NodeStoppedError) as error:
            reasons = (
                []
                if self._readings.nmt(node) == "stopped"
                else [EnableReason(code="timeout", message=str(error))]
            )
            raise await self._readings.blocked(node, extra=reasons) from error


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
    return reason(
        "no_transition",
        "reason.no_transition",
        command=name,
        state=state_label(state),
        starts=froms,
    )


def _leaves(state: Cia402State) -> Callable[[int], bool]:
    """A statusword test: the drive is no longer in `state`."""
    return lambda statusword: state_of(statusword) is not state
