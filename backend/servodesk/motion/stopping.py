"""How a jog's axis is brought to rest: the blocking step that runs on the node's priority lane,
and the plan it follows (DESIGN: Motion safety).

A halt (controlword bit 8) stops a profile-velocity axis on its deceleration, but in profile
torque CiA 402 only ramps the torque to zero: the axis coasts on (an unloaded axis at 2 %
torque ran several revolutions into its limit switch). So a torque jog is stopped by taking the
axis into profile velocity with target 0 — the drive takes over the running speed and brakes
it under speed control — and its torque set-point goes to 0; a drive without profile velocity
gets a quick stop (0002h), which brakes on 6085h. Either way the deceleration is bounded by
ServoDesk, never the client's ramp alone: the profile deceleration objects are written first
(a slow ramp chosen for the jog would otherwise take minutes to stop).
"""

from __future__ import annotations

from dataclasses import dataclass

import canopen
from canopen.sdo.exceptions import SdoAbortedError

from servodesk.motion import drive_io as io
from servodesk.motion.core import state_of
from servodesk_protocol.cia402 import (
    CONTROLWORD,
    CW_FAULT_RESET,
    CW_HALT,
    CW_NEW_SETPOINT,
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    Cia402State,
    OperationMode,
    make_quick_stop,
)

QUICK_STOP_DECELERATION = 0x6085  # Quick stop deceleration


@dataclass(frozen=True, slots=True)
class StopPlan:
    """What the stop step may write, decided on the loop from the node's dictionary."""

    deceleration: int | None  # raw 6083h/6084h units; None: leave the ramp as it is
    use_drive_quick_stop_deceleration: bool  # take 6085h where it is steeper
    ramp_objects: tuple[int, ...]  # of 6083h/6084h, those the drive has
    pv_supported: bool  # a torque jog can be braked under speed control
    has_target_torque: bool


@dataclass(frozen=True, slots=True)
class StopOutcome:
    statusword: int
    how: str  # "halt", "halt in profile velocity", "quick stop", "nothing moves"
    deceleration: int | None  # the raw deceleration written, if any
    wrote: tuple[tuple[int, int], ...] = ()  # (object, value) the drive confirmed, in order


def stop_axis(remote: canopen.RemoteNode, plan: StopPlan) -> StopOutcome:
    """One step on the node's thread: read 6041h/6061h, bound the ramp, then halt (or brake a
    torque jog as the module says). Nothing is enabled that was not."""
    sw = io.read_statusword(remote)
    if state_of(sw) is not Cia402State.OPERATION_ENABLED:
        return StopOutcome(sw, "nothing moves", None)  # braking or off: nothing to add
    mode = io.read(remote, MODES_DISPLAY, signed=True)
    torque = mode == OperationMode.PROFILE_TORQUE
    if torque and not plan.pv_supported:
        io.write_controlword(remote, make_quick_stop())
        return StopOutcome(sw, "quick stop", None, ((CONTROLWORD, make_quick_stop()),))
    wrote: list[tuple[int, int]] = []
    decel = _bounded_deceleration(remote, plan)
    if decel is not None:
        for index in plan.ramp_objects:
            if _try_write(remote, index, 0, decel, io.U32):
                wrote.append((index, decel))
    if torque:
        io.write(remote, io.TARGET_VELOCITY, 0, 0, io.I32)
        io.write(remote, MODES_OF_OPERATION, 0, int(OperationMode.PROFILE_VELOCITY), io.I8)
        wrote += [(io.TARGET_VELOCITY, 0), (MODES_OF_OPERATION, OperationMode.PROFILE_VELOCITY)]
    cw = io.read(remote, CONTROLWORD, signed=False) or 0x000F
    halted = (cw | CW_HALT) & ~CW_NEW_SETPOINT & ~CW_FAULT_RESET
    io.write_controlword(remote, halted)
    wrote.append((CONTROLWORD, halted))
    if torque and plan.has_target_torque and _try_write(remote, io.TARGET_TORQUE, 0, 0, io.I16):
        wrote.append((io.TARGET_TORQUE, 0))  # a later PT start begins at 0
    how = "halt in profile velocity" if torque else "halt"
    return StopOutcome(sw, how, decel, tuple(wrote))


def quick_stop_axis(remote: canopen.RemoteNode) -> int:
    """Quick stop 0002h (transition 11): brakes on 6085h whatever the mode."""
    io.write_controlword(remote, make_quick_stop())
    return io.read_statusword(remote)


def _bounded_deceleration(remote: canopen.RemoteNode, plan: StopPlan) -> int | None:
    if plan.deceleration is None:
        return None
    decel = plan.deceleration
    if plan.use_drive_quick_stop_deceleration:
        quick = io.read(remote, QUICK_STOP_DECELERATION, signed=False)
        if quick:
            decel = max(decel, quick)
    return decel


def _try_write(
    remote: canopen.RemoteNode, index: int, sub: int, value: int, kind: tuple[int, bool]
) -> bool:
    """A write the stop can do without: a drive that refuses it still gets the halt."""
    try:
        io.write(remote, index, sub, value, kind)
    except SdoAbortedError:
        return False
    return True
