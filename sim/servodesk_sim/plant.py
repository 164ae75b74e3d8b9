"""Motor + load of a simulated servo axis, its control cascade, and the unit conversions.

Units used by every motion core (the literal reading of MDi-S1-C manual §3.1 and §5.3):

- Positions (607Ah, 607Ch, 6064h, 60C1h:01, 60F4h, 6065h, 6067h) are user units. The gear
  ratio 6091h maps 6091h:01 motor increments to 6091h:02 user units (default 131072 : 100000,
  so 100000 units are one revolution of the 17-bit encoder). 6063h is in encoder increments.
- Velocities 6081h, 60FFh, 6099h:01/02 are user units/s (the table says "Inc/s").
- Accelerations 6083h, 6084h, 6085h, 609Ah are user units/s per ms, as the table's "Inc/s/ms"
  reads literally: 100000 means 1e8 units/s².
- 606Ch and the overspeed limit (2006h:08 on the MDi, 6080h elsewhere) are motor rpm for all
  three profiles; the MDi table gives rpm and CiA 402 leaves the unit to the device.
- Torques 6071h, 6072h, 6077h are 0.1 % of rated torque; 6087h is 0.1 %/ms.
- Polarity 607Eh: any non-zero value reverses the command direction (the MDi range is 0–1;
  CiA 402 bits 6 and 7 are taken together since a simulated axis has one direction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

from servodesk_sim.values import ValueStore

ENCODER_RESOLUTION = 131072  # 17-bit encoder, increments per revolution (MDi-S1-C manual §3.1)
DEFAULT_MAX_TORQUE = 3000  # 6072h default when absent: 300 % of rated torque

_INT32_SPAN = 1 << 32


def read_or(values: ValueStore, index: int, subindex: int, default: int) -> int:
    """An object's value, or `default` when this drive has no such entry."""
    try:
        return values.get(index, subindex)
    except KeyError:
        return default


def wrap_int32(value: float) -> int:
    """Round and wrap like a 32-bit position counter does when it overflows."""
    raw = round(value) % _INT32_SPAN
    return raw - _INT32_SPAN if raw >= 1 << 31 else raw


REST_SPEED = 1e-6  # rad/s: a coasting motor slower than this has stopped


@dataclass(frozen=True, slots=True)
class Scaling:
    """Factor group: gear ratio 6091h and polarity 607Eh (MDi-S1-C manual §3.1, §5.3)."""

    motor_increments: int = ENCODER_RESOLUTION  # 6091h:01
    user_units: int = 100000  # 6091h:02
    reversed: bool = False  # 607Eh
    encoder_resolution: int = ENCODER_RESOLUTION

    @classmethod
    def read(cls, values: ValueStore) -> Scaling:
        motor = read_or(values, 0x6091, 1, ENCODER_RESOLUTION)  # Gear ratio: motor increments
        user = read_or(values, 0x6091, 2, 100000)  # Gear ratio: user units
        # A zero in either half would divide by zero; the drive keeps the default instead.
        if motor <= 0 or user <= 0:
            motor, user = ENCODER_RESOLUTION, 100000
        return cls(motor, user, read_or(values, 0x607E, 0, 0) != 0)  # Polarity

    @property
    def _sign(self) -> float:
        return -1.0 if self.reversed else 1.0

    def to_user(self, increments: float) -> float:
        """Motor increments (signed, motor frame) to user units (signed, user frame)."""
        return self._sign * increments * self.user_units / self.motor_increments

    def to_increments(self, user: float) -> float:
        return self._sign * user * self.motor_increments / self.user_units

    def rpm_to_user(self, rpm: float) -> float:
        """Motor rpm (user direction) to user units/s."""
        return self.to_user(rpm * self.encoder_resolution / 60.0)

    def user_to_rpm(self, user_per_s: float) -> float:
        return self.to_increments(user_per_s) * 60.0 / self.encoder_resolution


@dataclass(frozen=True, slots=True)
class PlantParams:
    """A 400 W class servo with some load. Gains give a ~50 Hz velocity loop."""

    inertia: float = 1.0e-4  # kg·m², motor + load
    viscous_friction: float = 2.0e-4  # N·m per rad/s
    load_torque: float = 0.0  # N·m, constant (a hanging load), opposes positive torque
    rated_torque: float = 1.27  # N·m, what 1000 (= 100.0 %) in 6071h/6072h/6077h means
    position_gain: float = 60.0  # 1/s, position loop P
    velocity_gain: float = 0.0314  # N·m per rad/s, velocity loop P
    velocity_integral_gain: float = 2.5  # N·m per rad, velocity loop I
    encoder_resolution: int = ENCODER_RESOLUTION
    # Explicit integration needs h·Kv/J well below 1; 0.5 ms keeps it near 0.16 and the
    # simulator at two sub-steps per 1 ms control period.
    max_substep: float = 5.0e-4


class ControlKind(Enum):
    OFF = "off"  # power stage off: the axis coasts
    POSITION = "position"  # position P + velocity feed-forward -> velocity PI
    VELOCITY = "velocity"  # velocity PI
    TORQUE = "torque"  # torque reference, speed capped at a limit (MDi-S1-C manual §3.6)


@dataclass(frozen=True, slots=True)
class PlantCommand:
    """What the control cascade is asked for during one period (motor frame)."""

    kind: ControlKind
    position: float = 0.0  # increments (POSITION)
    velocity: float = 0.0  # increments/s: reference (VELOCITY), feed-forward (POSITION)
    torque: float = 0.0  # 0.1 % rated (TORQUE)
    velocity_limit: float = math.inf  # increments/s magnitude (TORQUE)
    torque_limit: float = DEFAULT_MAX_TORQUE  # 0.1 % rated, 6072h


class Plant:
    """Rigid motor + load with a position/velocity/torque cascade, integrated at fixed steps.

    Same inputs give bit-identical outputs: no randomness, no clock, fixed sub-steps.
    """

    def __init__(self, params: PlantParams | None = None, position: float = 0.0) -> None:
        self.params = params or PlantParams()
        self._rad_per_inc = 2.0 * math.pi / self.params.encoder_resolution
        self._angle = position * self._rad_per_inc  # rad
        self._speed = 0.0  # rad/s
        self._torque = 0.0  # N·m, last applied
        self._integral = 0.0  # N·m, velocity loop integrator
        # Last period's references (rad/s, rad), interpolated from in the next period.
        self._ref_speed: float | None = None
        self._ref_angle: float | None = None

    @property
    def position(self) -> float:
        """Motor position in encoder increments since power-up."""
        return self._angle / self._rad_per_inc

    @property
    def velocity(self) -> float:
        """Motor velocity in increments/s."""
        return self._speed / self._rad_per_inc

    @property
    def rpm(self) -> float:
        return self._speed * 60.0 / (2.0 * math.pi)

    @property
    def torque(self) -> float:
        """Applied motor torque in 0.1 % of rated torque."""
        return self._torque * 1000.0 / self.params.rated_torque

    def step(self, dt: float, command: PlantCommand) -> None:
        p = self.params
        substeps = max(1, math.ceil(dt / p.max_substep - 1e-9))
        h = dt / substeps
        limit = max(0.0, command.torque_limit) * p.rated_torque / 1000.0
        kind = command.kind
        if kind is ControlKind.POSITION or kind is ControlKind.VELOCITY:
            # The period's references are reached at its end: interpolate them over the
            # sub-steps and feed the acceleration and friction torque forward, as servo drives
            # do, so the PI only corrects the model error and a ramp ends without overshoot
            # (an overshoot at the speed limit would trip the overspeed alarm).
            speed_end = command.velocity * self._rad_per_inc
            angle_end = command.position * self._rad_per_inc
            speed_start = speed_end if self._ref_speed is None else self._ref_speed
            angle_start = angle_end
            if kind is ControlKind.POSITION and self._ref_angle is not None:
                angle_start = self._ref_angle
            accel_torque = p.inertia * (speed_end - speed_start) / dt
            for n in range(substeps):
                # Torque is computed from the state at the start of each sub-step, so it is
                # compared with the reference at that instant.
                fraction = n / substeps
                speed_ref = speed_start + (speed_end - speed_start) * fraction
                if kind is ControlKind.POSITION:
                    angle_ref = angle_start + (angle_end - angle_start) * fraction
                    speed_ref += p.position_gain * (angle_ref - self._angle)
                feed_forward = accel_torque + p.viscous_friction * speed_ref
                self._integrate(self._velocity_loop(speed_ref, feed_forward, limit, h), h)
            self._ref_speed = speed_end
            self._ref_angle = angle_end if kind is ControlKind.POSITION else None
            return
        self._ref_speed = self._ref_angle = None
        self._integral = 0.0
        for _ in range(substeps):
            torque = 0.0 if kind is ControlKind.OFF else self._torque_loop(command, limit)
            self._integrate(torque, h)
        if kind is ControlKind.OFF and p.load_torque == 0.0 and abs(self._speed) < REST_SPEED:
            # Friction alone never quite stops a coasting motor in floating point; below this
            # (10⁻⁵ rpm, far under 606Ch's 1 rpm) it has stopped, and a drive at rest can skip
            # its control period (MotionCore.step).
            self._speed = 0.0

    @property
    def at_rest(self) -> bool:
        """Stopped, unpowered and nothing pulling at it: an OFF step changes nothing."""
        return self._speed == 0.0 and self._torque == 0.0 and self.params.load_torque == 0.0

    def _integrate(self, torque: float, h: float) -> None:
        p = self.params
        self._torque = torque
        # Torque held over the sub-step: speed changes linearly, so the angle takes the mean
        # speed (trapezoidal), which is exact for the profiles the modes generate.
        accel = (torque - p.viscous_friction * self._speed - p.load_torque) / p.inertia
        previous = self._speed
        self._speed += h * accel
        self._angle += h * 0.5 * (previous + self._speed)

    def _velocity_loop(
        self, speed_ref: float, feed_forward: float, limit: float, h: float
    ) -> float:
        p = self.params
        speed_error = speed_ref - self._speed
        unsaturated = p.velocity_gain * speed_error + self._integral + feed_forward
        torque = _clamp(unsaturated, limit)
        # Anti-windup: integrate only while the output is not pushed further into the limit.
        if torque == unsaturated or (unsaturated > 0.0) != (speed_error > 0.0):
            self._integral = _clamp(
                self._integral + p.velocity_integral_gain * speed_error * h, limit
            )
        return torque

    def _torque_loop(self, command: PlantCommand, limit: float) -> float:
        p = self.params
        wanted = command.torque * p.rated_torque / 1000.0
        ceiling = command.velocity_limit * self._rad_per_inc
        # Above the speed limit the torque loop hands over to a speed regulator
        # ("当速度达到限幅值将进入调速阶段", MDi-S1-C manual §3.6).
        if wanted >= 0.0:
            wanted = min(wanted, p.velocity_gain * (ceiling - self._speed))
        else:
            wanted = max(wanted, p.velocity_gain * (-ceiling - self._speed))
        return _clamp(wanted, limit)


def _clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


def publish_feedback(
    values: ValueStore,
    plant: Plant,
    scaling: Scaling,
    origin: float,
    demand: float,
) -> None:
    """Publish 6063h, 6064h, 606Ch, 6077h and 60F4h.

    `origin` is the motor position (increments) that reads as user position 0 (moved by
    homing); `demand` is the position demand in user units (60F4h = demand − actual).
    """
    internal = plant.position - origin
    actual = scaling.to_user(internal)
    sign = -1.0 if scaling.reversed else 1.0
    values.set(0x6063, 0, wrap_int32(internal))  # Position actual internal value
    values.set(0x6064, 0, wrap_int32(actual))  # Position actual value
    values.set(0x606C, 0, wrap_int32(sign * plant.rpm))  # Velocity actual value (rpm)
    torque = round(sign * plant.torque)
    values.set(0x6077, 0, max(-32768, min(32767, torque)))  # Torque actual value
    values.set(0x60F4, 0, wrap_int32(demand - actual))  # Following error actual value
