"""The motion side of a simulated drive: CiA 402 state machine, operating modes, plant, monitors.

Inputs come from the object values (6040h through `on_controlword`, the rest read each period),
outputs are published with `ValueStore.set` (6041h, 6061h, 6063h, 6064h, 606Ch, 6077h, 60F4h,
60FDh). Time only advances through `step(dt)`. Units are described in plant.py.

Choices where the manuals leave room:
- 6065h following error window absent (the MDi manual lists none): 3 motor revolutions;
  0xFFFFFFFF switches the check off (CiA 402).
- Quick stop 605Ah absent: 2 (CiA 402 default). 3/4/7/8 brake with the deceleration the 6072h
  torque gives the plant's inertia; values outside 0–8 use the quick-stop ramp. Fault reaction
  always uses 6085h (605Eh is not read).
- Disable operation (5) and shutdown (8) switch the power stage off at once (605Bh/605Ch are
  not read).
- Limit switches (outside homing) per profile: a fault on running into one (Kinco, CiA 402), or
  drive-inhibit inputs (MDi): one stops the motion toward it and sets statusword bit 11
  "internal limit active" while active, both raise MDi alarm 7 (see drive_inhibit.py).
- Statusword bits 10/12/13 come from the running mode in Operation enabled only; the error
  bits 13 (PP following error, HM homing error) stay visible through the fault they cause,
  until the drive is enabled again (PP) or homing is started again (HM).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

from servodesk_data import LimitSwitchReaction
from servodesk_protocol.cia402 import (
    CW_FAULT_RESET,
    SW_INTERNAL_LIMIT,
    SW_MODE_BIT13,
    SW_REFERENCE_FOUND,
    Cia402State,
    OperationMode,
    QuickStopOption,
    quick_stop_stays,
)
from servodesk_sim.cia402 import next_state, statusword_bits
from servodesk_sim.drive_inhibit import DriveInhibit
from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.modes import (
    Axis,
    Homing,
    Interpolated,
    Mode,
    ProfilePosition,
    ProfileTorque,
    ProfileVelocity,
    Setpoint,
    StopRamp,
    Switches,
    read_switches,
)
from servodesk_sim.modes.common import acceleration
from servodesk_sim.modes.homing import Phase
from servodesk_sim.plant import (
    DEFAULT_MAX_TORQUE,
    ControlKind,
    Plant,
    PlantCommand,
    PlantParams,
    Scaling,
    publish_feedback,
    read_or,
)
from servodesk_sim.values import ValueStore

DEFAULT_MAX_SPEED_RPM = 6000  # MDi 2006h:08 factory value
FOLLOWING_ERROR_DEFAULT_REV = 3.0  # when the drive has no 6065h
LIMIT_APPROACH_RPM = 0.1  # slower than this counts as standing at a limit switch

_S = Cia402State
_POWERED = frozenset({_S.OPERATION_ENABLED, _S.QUICK_STOP_ACTIVE, _S.FAULT_REACTION_ACTIVE})
_BOTH_LIMITS = Switches.NEGATIVE_LIMIT | Switches.POSITIVE_LIMIT


@dataclass(frozen=True)
class MotionConfig:
    supported_modes: frozenset[int]  # 6502h; MDi {1, 3, 4, 6, 7}
    homing_methods: frozenset[int]  # {17, 18, 23, 27, 35} (+ profile additions)
    immediate_setpoint: bool  # PP controlword bit 5 honoured (MDi: False)
    unsupported_mode_display: int | None  # MDi: 6061h shows 0; None: keep the old mode
    reference_found_bit15: bool  # Kinco statusword 0x8000 after homing (Kinco manual §5.4.6)
    max_speed: tuple[int, int, str]  # overspeed limit object and unit ("rpm")
    # MDi: INHIBIT (MDi-S1-C CANopen manual §4.1 alarm 7); Kinco, CiA 402: FAULT
    limit_switch_reaction: LimitSwitchReaction = LimitSwitchReaction.FAULT
    ip_period_ms: tuple[int, int] = (1, 20)  # 60C2h clamp (MDi-S1-C manual §3.8 note 5)
    homing_timeout_s: float = 60.0  # "回零发生超时" (MDi-S1-C manual §3.7.1 bit 13)
    plant: PlantParams = field(default_factory=PlantParams)

    def __post_init__(self) -> None:
        if self.max_speed[2] != "rpm":
            raise ValueError(f"max speed unit {self.max_speed[2]!r} is not supported (rpm only)")


class MotionCore:
    def __init__(
        self,
        values: ValueStore,
        config: MotionConfig,
        on_fault: Callable[[FaultKind], None],
        fault_reset: Callable[[], bool],
    ) -> None:
        self._values = values
        self._config = config
        self._on_fault = on_fault
        self._fault_reset = fault_reset
        self._plant = Plant(config.plant)
        self._origin = 0.0  # motor increments that read as user position 0
        # Transitions 0 and 1 (self-test, initialisation) are over once the drive exists.
        self._state = _S.SWITCH_ON_DISABLED
        self._controlword = 0
        self._homing = Homing(config.homing_methods, config.homing_timeout_s)
        self._modes: dict[int, Mode] = {
            OperationMode.PROFILE_POSITION: ProfilePosition(config.immediate_setpoint),
            OperationMode.PROFILE_VELOCITY: ProfileVelocity(),
            OperationMode.PROFILE_TORQUE: ProfileTorque(),
            OperationMode.HOMING: self._homing,
            OperationMode.INTERPOLATED_POSITION: Interpolated(config.ip_period_ms),
        }
        self._mode_number: int | None = None
        self._mode: Mode | None = None
        self._stop = StopRamp()
        self._inhibit = DriveInhibit()
        self._setpoint = Setpoint(ControlKind.OFF)
        self._fault_reported = False
        self._following_error = False
        # What the last control period ended with, if it left the axis unpowered at rest: the
        # store's change count, the state and the controlword (see `step`).
        self._rest_mark: tuple[int, Cia402State, int] | None = None
        axis = self._axis()
        self._update_mode(axis)
        self._publish(axis)

    @property
    def state(self) -> Cia402State:
        return self._state

    # --- events from the drive -------------------------------------------------------------

    def on_controlword(self, value: int) -> None:
        previous, self._controlword = self._controlword, value & 0xFFFF
        axis = self._axis()
        self._update_mode(axis)
        if self._state is _S.FAULT:
            edge = value & CW_FAULT_RESET and not previous & CW_FAULT_RESET
            if edge and self._fault_reset():
                self._enter(_S.SWITCH_ON_DISABLED, axis)  # transition 15
        else:
            new, transition = next_state(
                self._state,
                value,
                previous_controlword=previous,
                quick_stop_option=self._quick_stop_option(),
            )
            if transition is not None:
                self._enter(new, axis)
        if self._state is _S.OPERATION_ENABLED and self._mode is not None:
            self._mode.on_controlword(self._values, value, previous)
        self._publish_status(axis)

    def on_sync(self) -> None:
        mode = self._mode
        if self._state is _S.OPERATION_ENABLED and isinstance(mode, Interpolated):
            mode.on_sync(self._values)

    def quick_stop(self) -> None:
        axis = self._axis()
        if self._state is _S.OPERATION_ENABLED:
            self._enter(_S.QUICK_STOP_ACTIVE, axis)  # as transition 11
        elif self._state in (_S.READY_TO_SWITCH_ON, _S.SWITCHED_ON):
            self._enter(_S.SWITCH_ON_DISABLED, axis)  # as transition 7/10
        self._publish_status(axis)

    def disable(self) -> None:
        self._state = _S.SWITCH_ON_DISABLED
        self._setpoint = Setpoint(ControlKind.OFF)
        self._publish_status(self._axis())

    def enter_fault(self) -> None:
        if self._state in (_S.FAULT_REACTION_ACTIVE, _S.FAULT):
            return
        if self._state in _POWERED:
            self._state = _S.FAULT_REACTION_ACTIVE
            self._start_stop_ramp(self._axis())
        else:
            self._state = _S.FAULT  # nothing to brake: 13 and 14 at once
        self._publish_status(self._axis())

    # --- control period --------------------------------------------------------------------

    def step(self, dt: float) -> None:
        if self._rest_mark is not None and self._rest_mark == (
            self._values.changes,
            self._state,
            self._controlword,
        ):
            # Unpowered, at rest, and nothing written or commanded since the last period: this
            # one would publish the same values again. Skipped, so that three idle simulated
            # drives do not keep a core a third busy (and the tool beside them waiting for the
            # interpreter lock).
            return
        axis = self._axis()
        self._update_mode(axis)
        setpoint = self._control(dt, axis)
        if setpoint.position_shift is not None:
            # Homing done: move the origin so every user position reads `shift` more.
            self._origin -= axis.scaling.to_increments(setpoint.position_shift)
        self._setpoint = setpoint
        self._plant.step(dt, self._command(setpoint, axis))
        after = self._axis()
        self._monitor(setpoint, after)
        self._publish(after)
        resting = self._state not in _POWERED and self._plant.at_rest
        self._rest_mark = (
            (self._values.changes, self._state, self._controlword) if resting else None
        )

    def _control(self, dt: float, axis: Axis) -> Setpoint:
        state = self._state
        if state is _S.OPERATION_ENABLED:
            if self._mode is None:
                return Setpoint(ControlKind.POSITION, position=self._stop.position)
            return self._inhibited(dt, self._mode.step(dt, self._values, axis), axis)
        if state in (_S.QUICK_STOP_ACTIVE, _S.FAULT_REACTION_ACTIVE):
            return self._braking(dt, axis)
        return Setpoint(ControlKind.OFF, position=axis.position, velocity=axis.velocity)

    def _inhibited(self, dt: float, demand: Setpoint, axis: Axis) -> Setpoint:
        """The mode's demand, unless a drive-inhibit input refuses it (drive_inhibit.py)."""
        mode = self._mode
        if not self._limits_inhibit() or mode is None or mode is self._homing:
            return demand
        dec = acceleration(read_or(self._values, 0x6085, 0, 100000))  # Quick stop deceleration
        held = self._inhibit.apply(dt, demand, self._setpoint, axis, dec)
        if held is None:
            return demand
        mode.take_over(held.position)  # the refused demand does not wind up behind the hold
        return replace(held, fault=demand.fault)

    def _limits_inhibit(self) -> bool:
        return self._config.limit_switch_reaction is LimitSwitchReaction.INHIBIT

    def _braking(self, dt: float, axis: Axis) -> Setpoint:
        option = self._quick_stop_option()
        fault = self._state is _S.FAULT_REACTION_ACTIVE
        if not fault and option in _AT_TORQUE_LIMIT:
            dec = self._torque_limited_deceleration(axis.scaling)
        else:
            slow = not fault and option in _SLOW_DOWN
            # 6084h profile deceleration for 1/5, 6085h quick stop deceleration otherwise
            dec = acceleration(read_or(self._values, 0x6084 if slow else 0x6085, 0, 100000))
        setpoint = self._stop.step(dt, dec)
        if self._stop.stopped and fault:
            self._state = _S.FAULT  # transition 14
        elif self._stop.stopped and not quick_stop_stays(option):
            self._state = _S.SWITCH_ON_DISABLED  # transition 12
        return setpoint

    def _torque_limited_deceleration(self, scaling: Scaling) -> float:
        """User units/s² that the 6072h torque brakes the axis with (605Ah = 3, 4, 7, 8)."""
        params = self._config.plant
        limit = read_or(self._values, 0x6072, 0, DEFAULT_MAX_TORQUE)  # Max torque
        # 90 %: the loops keep some torque to correct with, so the axis does stop at the end.
        rad_per_s2 = 0.9 * limit / 1000.0 * params.rated_torque / params.inertia
        increments = rad_per_s2 * params.encoder_resolution / (2.0 * math.pi)
        return max(abs(scaling.to_user(increments)), 1.0)

    def _command(self, setpoint: Setpoint, axis: Axis) -> PlantCommand:
        scaling = axis.scaling
        limit = read_or(self._values, 0x6072, 0, DEFAULT_MAX_TORQUE)  # Max torque
        kind = setpoint.kind
        if kind is ControlKind.POSITION:
            return PlantCommand(
                kind,
                position=self._origin + scaling.to_increments(setpoint.position),
                velocity=scaling.to_increments(setpoint.velocity),
                torque_limit=limit,
            )
        if kind is ControlKind.VELOCITY:
            velocity = scaling.to_increments(setpoint.velocity)
            return PlantCommand(kind, velocity=velocity, torque_limit=limit)
        if kind is ControlKind.TORQUE:
            return PlantCommand(
                kind,
                torque=-setpoint.torque if scaling.reversed else setpoint.torque,
                velocity_limit=abs(scaling.to_increments(setpoint.velocity_limit)),
                torque_limit=limit,
            )
        return PlantCommand(ControlKind.OFF)

    # --- monitors --------------------------------------------------------------------------

    def _monitor(self, setpoint: Setpoint, axis: Axis) -> None:
        fault = setpoint.fault
        if fault is None and self._state in (_S.OPERATION_ENABLED, _S.QUICK_STOP_ACTIVE):
            fault = self._check(setpoint, axis)
        if fault is not None and not self._fault_reported:
            self._fault_reported = True
            self._on_fault(fault)

    def _check(self, setpoint: Setpoint, axis: Axis) -> FaultKind | None:
        # Compared at the 1 rpm resolution of 606Ch, so running at the limit is no overspeed.
        if round(abs(self._plant.rpm)) > self._max_speed_rpm():
            return FaultKind.OVERSPEED  # MDi alarm 1 "超速"
        if setpoint.kind is ControlKind.POSITION:
            window = self._following_error_window(axis.scaling)
            if abs(setpoint.position - axis.position) > window:
                self._following_error = True
                return FaultKind.FOLLOWING_ERROR  # MDi alarm 4 "位置超差"
        if self._limits_inhibit():
            if axis.switches & _BOTH_LIMITS == _BOTH_LIMITS:
                return FaultKind.BOTH_LIMITS  # MDi alarm 7 "CCW/CW 驱动禁止输入都 OFF"
        elif self._state is _S.OPERATION_ENABLED and self._mode is not self._homing:
            # Homing uses the limit switches itself; elsewhere running into one is a fault.
            speed = self._plant.rpm  # motor frame, like the switch positions
            if axis.switches & Switches.NEGATIVE_LIMIT and speed < -LIMIT_APPROACH_RPM:
                return FaultKind.NEGATIVE_LIMIT
            if axis.switches & Switches.POSITIVE_LIMIT and speed > LIMIT_APPROACH_RPM:
                return FaultKind.POSITIVE_LIMIT
        return None

    def _following_error_window(self, scaling: Scaling) -> float:
        window = read_or(self._values, 0x6065, 0, -1)  # Following error window
        if window == 0xFFFFFFFF:
            return float("inf")
        if window >= 0:
            return float(window)
        revolution = abs(scaling.to_user(scaling.encoder_resolution))
        return FOLLOWING_ERROR_DEFAULT_REV * revolution

    def _max_speed_rpm(self) -> float:
        index, subindex, _unit = self._config.max_speed
        return float(read_or(self._values, index, subindex, DEFAULT_MAX_SPEED_RPM))

    # --- helpers ---------------------------------------------------------------------------

    def _quick_stop_option(self) -> int:
        return read_or(
            self._values, 0x605A, 0, QuickStopOption.QUICK_STOP_RAMP
        )  # Quick stop option code

    def _enter(self, state: Cia402State, axis: Axis) -> None:
        self._state = state
        if state is _S.OPERATION_ENABLED:
            self._fault_reported = False
            self._following_error = False
            self._start_mode(axis)
        elif state is _S.QUICK_STOP_ACTIVE:
            if self._quick_stop_option() == QuickStopOption.DISABLE_DRIVE:
                self._state = _S.SWITCH_ON_DISABLED  # 605Ah = 0: coast, transition 12 at once
            else:
                self._start_stop_ramp(axis)

    def _start_stop_ramp(self, axis: Axis) -> None:
        last = self._setpoint
        if last.kind is ControlKind.POSITION:
            self._stop.start(last.position, last.velocity)
        else:
            self._stop.start(axis.position, axis.velocity)

    def _start_mode(self, axis: Axis) -> None:
        self._stop.start(axis.position, 0.0)  # standstill target when no mode runs
        self._inhibit.reset()
        if self._mode is not None:
            self._mode.start(self._values, axis)

    def _update_mode(self, axis: Axis) -> None:
        requested = read_or(self._values, 0x6060, 0, 0)  # Modes of operation
        shown: int | None = requested
        if requested not in self._config.supported_modes:
            shown = self._config.unsupported_mode_display
        if shown is None or shown == self._mode_number:
            return
        self._mode_number = shown
        self._mode = self._modes.get(shown)
        self._values.set(0x6061, 0, shown)  # Modes of operation display
        if self._state is _S.OPERATION_ENABLED:
            self._start_mode(axis)
            if self._mode is not None:
                self._mode.on_controlword(self._values, self._controlword, self._controlword)

    def _axis(self) -> Axis:
        values = self._values
        scaling = Scaling.read(values)
        plant = self._plant
        motor = plant.position
        sign = -1.0 if scaling.reversed else 1.0
        return Axis(
            position=scaling.to_user(motor - self._origin),
            velocity=scaling.to_user(plant.velocity),
            torque=sign * plant.torque,
            switches=read_switches(values, motor),
            motor_velocity=plant.velocity,
            max_speed=abs(scaling.rpm_to_user(self._max_speed_rpm())),
            scaling=scaling,
        )

    def _publish(self, axis: Axis) -> None:
        setpoint = self._setpoint
        demand = setpoint.position if setpoint.kind is ControlKind.POSITION else axis.position
        publish_feedback(self._values, self._plant, axis.scaling, self._origin, demand)
        self._values.set(0x60FD, 0, int(axis.switches))  # Digital inputs
        self._publish_status(axis)

    def _publish_status(self, axis: Axis) -> None:
        word = statusword_bits(self._state)
        mode = self._mode
        if self._state is _S.OPERATION_ENABLED and mode is not None:
            word |= mode.status_bits(axis)
        # Error bits 13 stay visible through the fault they caused, until re-enabled / rehomed.
        if self._following_error and isinstance(mode, ProfilePosition):
            word |= SW_MODE_BIT13  # PP bit 13 "跟随误差" (MDi-S1-C manual §3.4.1)
        if mode is self._homing and self._homing.phase is Phase.ERROR:
            word |= SW_MODE_BIT13  # HM bit 13 "回零错误"
        if (
            self._state is _S.OPERATION_ENABLED
            and self._limits_inhibit()
            and mode is not self._homing
            and axis.switches & _BOTH_LIMITS
        ):
            word |= SW_INTERNAL_LIMIT  # a drive-inhibit input refuses one direction
        if self._config.reference_found_bit15 and self._homing.referenced:
            word |= SW_REFERENCE_FOUND
        self._values.set(0x6041, 0, word)  # Statusword


_SLOW_DOWN = frozenset({QuickStopOption.SLOW_DOWN_RAMP, QuickStopOption.SLOW_DOWN_RAMP_STAY})
_AT_TORQUE_LIMIT = frozenset(
    {
        QuickStopOption.CURRENT_LIMIT,
        QuickStopOption.VOLTAGE_LIMIT,
        QuickStopOption.CURRENT_LIMIT_STAY,
        QuickStopOption.VOLTAGE_LIMIT_STAY,
    }
)
