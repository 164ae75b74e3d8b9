"""What the service remembers about one axis between requests, and the pure assembly of the
DriveState the API returns from a reading (`build_state`)."""

from __future__ import annotations

import asyncio
import time
from dataclasses import dataclass, field
from typing import Literal

from servodesk.models.motion import (
    DriveLimits,
    DriveState,
    FaultInfo,
    HomingProgress,
    MotionLimits,
    MoveProgress,
    SpeedLimit,
    TravelEnds,
    TravelInfo,
)
from servodesk.motion.drive_io import Snapshot, Statics, Travel
from servodesk.motion.homing import homing_phase
from servodesk.motion.units import DriveUnits
from servodesk.motion.words import (
    STATE_NAMES,
    Transition,
    mode_key,
    state_label,
    status_bits,
    transition,
)
from servodesk_data import DriveData
from servodesk_protocol.cia402 import (
    CW_HALT,
    CW_QUICK_STOP,
    SW_INTERNAL_LIMIT,
    SW_MODE_BIT13,
    SW_REFERENCE_FOUND,
    SW_TARGET_REACHED,
    Cia402State,
    OperationMode,
    decode_state,
    supported_modes,
)

DEFAULT_POSITION_WINDOW = 100  # user units = 1/1000 rev, what the drives use without 6067h
COMMAND_LATENCY_S = 0.002  # a frame the drive sent before it took a command may arrive this late
INPUT_BITS = {"negative_limit": 0, "positive_limit": 1, "home_switch": 2}  # 60FDh
SOURCE_NAMES = {"inputs": "digital_inputs"}  # a Snapshot field -> its DriveState name


@dataclass
class Axis:
    node: int
    limits: MotionLimits  # in force: the user's choice under the drive's own
    statics: Statics | None = None
    chosen_limits: MotionLimits | None = None  # what PUT …/drive/limits set; None: the drive's
    drive_limits: DriveLimits | None = None  # the drive's own as last read
    limits_read_at: float = 0.0  # time.monotonic() of the last read of the drive's limits
    limit_turn: int = 0  # which limit object a polled reading reads next
    sim_switches: bool = True  # still ask for the simulator's switch objects 5FF1h/5FF2h
    last: Snapshot | None = None
    last_at: float = 0.0  # when the reading in `last` started (an older one never replaces it)
    sdo_read_at: dict[str, float] = field(default_factory=dict)  # polled SDO reads, by field
    # the latest SDO reading of each live value (value, time.monotonic()): newer than a TPDO
    # frame, it wins (a change the drive holds back for the TPDO's inhibit time)
    sdo_values: dict[str, tuple[int | None, float]] = field(default_factory=dict)
    # what ServoDesk itself last wrote to the drive's command objects (index -> value): a jog
    # writes only what differs; forgotten on every stop and on any write not its own
    sent: dict[int, int] = field(default_factory=dict)
    stop_epoch: int = 0  # counts the stops: a write asked for before one is not sent after it
    commanded_at: float = 0.0  # time.monotonic() of the last state-changing command or stop
    polled: DriveState | None = None  # the pages' shared reading (MotionService.polled_state)
    polled_at: float = 0.0
    poll_lock: asyncio.Lock = field(default_factory=asyncio.Lock)
    state: Cia402State | None = None
    last_transition: Transition | None = None
    homing_method: int | None = None
    homing: HomingProgress | None = None  # the last run's progress, final once it ended
    # time.monotonic() once the drive took the last homing start: a reading begun before it
    # shows the drive from before the run (bit 10 without bit 12) and must not end the run
    homing_since: float = 0.0
    homed: bool = False
    move: MoveProgress | None = None
    target_user: int | None = None  # the last accepted PP target, for relative moves
    # why ServoDesk itself dropped what it fed the axis (a stop, a disable), for the move's
    # message: the drive may not show it yet when the next reading comes
    dropped_by: str | None = None
    jog: str | None = None  # "pv" / "pt" while a jog runs
    queue_task: asyncio.Task[None] | None = None
    queued: list[object] = field(default_factory=list)

    def commanded(self, sent_at: float | None = None) -> None:
        """A command sent at `sent_at` (now) changed, or may have changed, the drive's state:
        TPDO frames that arrived before it (and a bus latency) and the pages' shared reading no
        longer show the drive. Called once the command is sent: a frame the drive sent in
        answer may already have arrived, so the time is when it was asked for."""
        at = (time.monotonic() if sent_at is None else sent_at) + COMMAND_LATENCY_S
        self.commanded_at = max(self.commanded_at, at)
        self.polled = None

    def saw(self, state: Cia402State) -> None:
        """Record a reading's state (and the transition that led to it)."""
        if self.state is not None and state is not self.state:
            self.last_transition = transition(self.state, state)
        self.state = state

    def cancel_queue(self) -> None:
        task, self.queue_task = self.queue_task, None
        self.queued.clear()
        if task is not None and not task.done() and task is not asyncio.current_task():
            task.cancel()


def units_of(statics: Statics | None, data: DriveData | None) -> DriveUnits:
    if statics is None:
        return DriveUnits.of(None, None, velocity_actual_rpm=True)
    # the three profiles report 606Ch in rpm (docs/simulator.md "Units"); CiA 402 otherwise
    return DriveUnits.of(statics.counts_per_rev, statics.gear, velocity_actual_rpm=data is not None)


def fault_info(
    code: int | None,
    faulted: bool,
    data: DriveData | None,
    source: str,
    source_zh: str | None = None,
) -> FaultInfo | None:
    """603Fh decoded from the profile's fault table (MDi: the alarm number; Kinco: the low 16
    bits of its code)."""
    if not faulted:
        return None
    if code is None or code == 0:
        return FaultInfo(code=0, code_hex="0x0000", name=None, text=None, source=None)
    entry = None
    if data is not None:
        entry = data.fault(code) or next((f for f in data.faults if f.code & 0xFFFF == code), None)
    return FaultInfo(
        code=code,
        code_hex=f"0x{code:04X}",
        name=entry.name_en if entry else None,
        text=entry.what_to_check if entry else None,
        source=source if entry else None,
        name_zh=entry.chinese_name if entry else None,
        text_zh=entry.what_to_check_zh if entry else None,
        source_zh=source_zh if entry else None,
    )


def position_window(statics: Statics | None) -> int:
    if statics is None or not statics.position_window:
        return DEFAULT_POSITION_WINDOW
    return statics.position_window


def build_state(
    axis: Axis,
    snap: Snapshot,
    *,
    nmt_state: str,
    data: DriveData | None,
    fault_source: str,
    fault_source_zh: str | None = None,
    pt_speed_limit: SpeedLimit | None = None,
) -> DriveState:
    """The API's DriveState from one reading (pure; `axis` supplies what was remembered)."""
    units = units_of(axis.statics, data)
    sw = snap.statusword
    try:
        state = decode_state(sw)
    except ValueError:
        state = Cia402State.NOT_READY_TO_SWITCH_ON
    position_user = snap.position or 0
    position_inc = units.user_to_inc(position_user)
    supported = (
        supported_modes(axis.statics.supported_raw)
        if axis.statics and axis.statics.supported_raw is not None
        else frozenset(int(m) for m in data.quirks.supported_modes)
        if data
        else frozenset()
    )
    inputs = {
        name: bool(snap.inputs >> bit & 1) if snap.inputs is not None else False
        for name, bit in INPUT_BITS.items()
    }
    bit15 = data is not None and data.quirks.homing_reference_found_bit15
    fault = fault_info(snap.error_code, state in _FAULTED, data, fault_source, fault_source_zh)
    homing = _homing(axis, snap, state, position_inc, fault)
    if homing is not None and homing.phase == "attained":
        axis.homed = True
    homed: bool | None = bool(sw & SW_REFERENCE_FOUND) if bit15 else (axis.homed or None)
    move = _move(axis, snap, state, fault)
    supported_keys = [k for m in sorted(supported) if (k := mode_key(m)) is not None]
    return DriveState(
        node=axis.node,
        state=STATE_NAMES[state],
        state_label=state_label(state),
        statusword=sw,
        status_bits=status_bits(sw, snap.mode_display, reference_found_bit15=bit15),
        controlword=snap.controlword or 0,
        last_transition=axis.last_transition.message if axis.last_transition else None,
        last_transition_id=axis.last_transition.message_id if axis.last_transition else None,
        last_transition_params=dict(axis.last_transition.params) if axis.last_transition else {},
        mode=mode_key(snap.mode),
        mode_display=mode_key(snap.mode_display),
        supported_modes=supported_keys,
        position_inc=position_inc,
        position_rev=units.inc_to_rev(position_inc),
        velocity_rpm=units.actual_velocity_rpm(snap.velocity or 0),
        torque_pct=None if snap.torque is None else units.torque_to_pct(snap.torque),
        following_error_inc=(
            None if snap.following_error is None else units.user_to_inc(snap.following_error)
        ),
        digital_inputs=snap.inputs,
        inputs=inputs,
        homed=homed,
        homing=homing,
        move=move,
        target_reached=bool(sw & SW_TARGET_REACHED),
        fault=fault,
        nmt_state=nmt_state,
        counts_per_rev=units.counts_per_rev,
        gear_ratio=axis.statics.gear if axis.statics else None,
        limits=axis.limits,
        pt_speed_limit=pt_speed_limit if "pt" in supported_keys else None,
        drive_limits=axis.drive_limits,
        sources={SOURCE_NAMES.get(name, name): where for name, where in snap.sources.items()},
        travel=travel_info(axis.statics.travel, units) if axis.statics else None,
    )


_FAULTED = (Cia402State.FAULT, Cia402State.FAULT_REACTION_ACTIVE)


def _homing(
    axis: Axis,
    snap: Snapshot,
    state: Cia402State,
    position_inc: int,
    fault: FaultInfo | None,
) -> HomingProgress | None:
    """The run's progress from statusword bits 10/12/13 while the drive homes; once the run
    has ended (attained, error, interrupted) that stays what the card shows until the next
    run — the drive leaving homing mode afterwards (to PP, say) does not undo it."""
    last = axis.homing
    if axis.homing_method is None or (last is not None and last.phase != "running"):
        return last
    if snap.taken_at is not None and snap.taken_at < axis.homing_since:
        return last  # begun before the drive took the start: it cannot judge this run
    if snap.mode_display != OperationMode.HOMING:
        progress = HomingProgress(
            method=axis.homing_method,
            phase="interrupted",
            message=f"the drive left homing mode before it was attained ({_mode_text(snap)})",
            position_inc=None,
        )
    elif state is not Cia402State.OPERATION_ENABLED:
        progress = HomingProgress(
            method=axis.homing_method,
            phase="interrupted",
            message=interruption(snap, state, fault),
            position_inc=None,
        )
    else:
        phase, message = homing_phase(snap.statusword)
        progress = HomingProgress(
            method=axis.homing_method,
            phase=phase,
            message=message,
            position_inc=position_inc if phase == "attained" else None,
        )
    axis.homing = progress
    return progress


def _mode_text(snap: Snapshot) -> str:
    shown = mode_key(snap.mode_display)
    return f"6061h shows {shown.upper()}" if shown else "6061h shows no mode"


def _move(
    axis: Axis, snap: Snapshot, state: Cia402State, fault: FaultInfo | None
) -> MoveProgress | None:
    """The last PP move's progress. Once it has ended (reached, error, interrupted) it stays
    so until the next move: a later disable is not its error, a later enable does not
    restart it."""
    move = axis.move
    if move is None:
        return None
    queued = len(axis.queued)
    running = queued > 0 or axis.queue_task is not None
    if move.phase != "moving" and not (move.phase == "reached" and running):
        return move
    phase: Literal["moving", "reached", "error", "interrupted"]
    message = None
    if state is not Cia402State.OPERATION_ENABLED or axis.target_user is None:
        # a quick stop, a fault, a disable, or ServoDesk dropped the move (a jog, a stop)
        message = interruption(snap, state, fault)
        if message == TOOK_THE_AXIS and axis.dropped_by is not None:
            message = axis.dropped_by  # sent, but not yet in what the drive shows
        phase = "interrupted"
    elif snap.statusword & SW_MODE_BIT13:
        phase, message = "error", "following error (statusword bit 13 in profile position)"
    elif (
        snap.statusword & SW_TARGET_REACHED
        and snap.position is not None
        and abs(snap.position - axis.target_user) <= position_window(axis.statics)
    ):
        phase = "reached"
    elif snap.statusword & SW_TARGET_REACHED and snap.statusword & SW_INTERNAL_LIMIT:
        # at rest short of its target, held by a limit (the MDi-S1-C's drive-inhibit inputs
        # stop a move without a fault): the drive will not go on with it
        phase, message = "interrupted", STOPPED_AT_LIMIT
    else:
        phase = "moving"
    if phase == "interrupted":
        queued = 0  # the rest of a sequence is dropped with it
    axis.move = MoveProgress(
        target_inc=move.target_inc, phase=phase, queued=queued, message=message
    )
    return axis.move


TOOK_THE_AXIS = "stopped by ServoDesk before its target (another command took the axis)"
STOPPED_AT_LIMIT = (
    "stopped at a limit before its target (statusword bit 11, internal limit active: a limit "
    "switch or drive-inhibit input); move the other way"
)


def interruption(snap: Snapshot, state: Cia402State, fault: FaultInfo | None) -> str:
    """Why motion ended before its target, from what the drive shows (pure)."""
    control = snap.controlword
    if state in _FAULTED:
        named = f" {fault.name}" if fault and fault.name else ""
        code = f" {fault.code_hex}" if fault else ""
        return f"stopped by fault{code}{named}"
    quick = control is not None and control & 0x0002 and not control & CW_QUICK_STOP
    if state is Cia402State.QUICK_STOP_ACTIVE or quick:
        return "stopped by quick stop (controlword bit 2 = 0)"
    if state is not Cia402State.OPERATION_ENABLED:
        return f"stopped: the drive left Operation enabled for {state_label(state)}"
    if control is not None and control & CW_HALT:
        return "halted (controlword bit 8) before its target"
    return TOOK_THE_AXIS


SIM_SWITCH_NOTE = (
    "simulator-only objects (docs/simulator.md), counted from where the simulated motor "
    "started: the position shown until a homing moves its zero"
)


def travel_info(travel: Travel | None, units: DriveUnits) -> TravelInfo:
    """Where the travel ends, in motor revolutions (pure)."""
    switches = software = None
    if travel is not None and travel.switches is not None:
        low, high = travel.switches
        switches = TravelEnds(
            min_rev=None if low is None else units.inc_to_rev(low),
            max_rev=None if high is None else units.inc_to_rev(high),
            source="5FF1h / 5FF2h SIM limit switch positions",
            simulator=True,
            note=SIM_SWITCH_NOTE,
        )
    if travel is not None and travel.software_limit is not None:
        low, high = travel.software_limit
        switched_off = low == high == 0
        software = TravelEnds(
            min_rev=None if low is None or switched_off else units.user_to_rev(low),
            max_rev=None if high is None or switched_off else units.user_to_rev(high),
            source="607Dh Software position limit",
            note="0 … 0: the drive checks no software limit" if switched_off else "",
        )
    return TravelInfo(switches=switches, software_limit=software)
