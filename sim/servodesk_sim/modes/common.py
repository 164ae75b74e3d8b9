"""What every operating mode shares: the axis snapshot, the set-point it returns, the
limit/home switches of the simulated axis, and the ramp arithmetic.

Units are those of plant.py: user units, user units/s, and user units/s² after converting the
"per ms" acceleration objects with `acceleration()`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntFlag
from typing import Protocol

from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.plant import ControlKind, Scaling, read_or
from servodesk_sim.values import ValueStore

# A position or velocity this close to its target counts as exactly there (float rounding).
_EPSILON = 1e-6


class Switches(IntFlag):
    """Digital inputs 60FDh as CiA 402 numbers them."""

    NEGATIVE_LIMIT = 0x1  # N-OT
    POSITIVE_LIMIT = 0x2  # P-OT
    HOME = 0x4  # HW


def read_switches(values: ValueStore, motor_position: float) -> Switches:
    """Switch states at a motor position (increments since power-up).

    The switch positions are simulator-only objects in motor increments, so a gear change does
    not move them: 5FF1h N-OT (active at or below), 5FF2h P-OT (active at or above), 5FF3h/5FF4h
    home switch (active inside [start, end]). An absent object means the switch is never active.
    """
    state = Switches(0)
    n_ot = read_or(values, 0x5FF1, 0, -(1 << 31))  # Simulated N-OT position
    p_ot = read_or(values, 0x5FF2, 0, (1 << 31) - 1)  # Simulated P-OT position
    hw_start = read_or(values, 0x5FF3, 0, 1)  # Simulated home switch start
    hw_end = read_or(values, 0x5FF4, 0, 0)  # Simulated home switch end
    if motor_position <= n_ot and n_ot > -(1 << 31):
        state |= Switches.NEGATIVE_LIMIT
    if motor_position >= p_ot and p_ot < (1 << 31) - 1:
        state |= Switches.POSITIVE_LIMIT
    if hw_start <= motor_position <= hw_end:
        state |= Switches.HOME
    return state


@dataclass(frozen=True, slots=True)
class Axis:
    """The axis as a mode sees it at the start of a control period (user frame)."""

    position: float  # actual position, user units
    velocity: float  # actual velocity, user units/s
    torque: float  # actual torque, 0.1 % rated, user direction
    switches: Switches
    motor_velocity: float  # increments/s in the motor frame (switches live in that frame)
    max_speed: float  # overspeed limit as a magnitude in user units/s
    scaling: Scaling


@dataclass(frozen=True, slots=True)
class Setpoint:
    """A mode's output for one period, in user units."""

    kind: ControlKind
    position: float = 0.0  # position demand (POSITION); for other kinds the actual position
    velocity: float = 0.0  # velocity demand or feed-forward
    torque: float = 0.0  # torque demand, 0.1 % rated (TORQUE)
    velocity_limit: float = math.inf  # magnitude (TORQUE)
    # Homing finished: every user position moves by this much (the demand now reads 607Ch).
    position_shift: float | None = None
    fault: FaultKind | None = None


def hold(axis: Axis) -> Setpoint:
    """Stand still where the axis is."""
    return Setpoint(ControlKind.POSITION, position=axis.position)


def acceleration(raw: int) -> float:
    """An "Inc/s/ms" object (6083h, 6084h, 6085h, 609Ah) in user units/s².

    Zero would never stop a ramp, so it counts as the slowest non-zero value.
    """
    return max(raw, 1) * 1000.0


def ramp_velocity(velocity: float, target: float, acc: float, dec: float, dt: float) -> float:
    """One step of a velocity ramp: `acc` while the speed grows, `dec` while it shrinks.

    A ramp through zero stops at zero for the rest of that step (at most one period late).
    """
    if velocity == target:
        return velocity
    growing = (velocity >= 0.0 and target > velocity) or (velocity <= 0.0 and target < velocity)
    if growing:
        step = acc * dt
        return min(target, velocity + step) if target > velocity else max(target, velocity - step)
    step = dec * dt
    if target > velocity:  # velocity < 0, braking upwards
        return min(target, 0.0, velocity + step) if target > 0.0 else min(target, velocity + step)
    return max(target, 0.0, velocity - step) if target < 0.0 else max(target, velocity - step)


def trapezoid_step(
    position: float,
    velocity: float,
    target: float,
    max_velocity: float,
    acc: float,
    dec: float,
    dt: float,
) -> tuple[float, float, bool]:
    """One period of an on-line trapezoidal profile; returns (position, velocity, arrived).

    The allowed speed is the one from which braking at `dec` lands exactly on the target with
    the trapezoidal position update used here, so the profile ends without overshoot. It also
    handles a target that changes in flight (immediate set-points): it brakes, reverses, goes.
    """
    distance = target - position
    brake = dec * dt
    if abs(distance) <= _EPSILON and abs(velocity) <= brake:
        return target, 0.0, True
    direction = 1.0 if distance > 0.0 else -1.0
    toward = direction * velocity
    discriminant = brake * brake + 8.0 * dec * abs(distance) - 4.0 * brake * toward
    allowed = (math.sqrt(discriminant) - brake) / 2.0 if discriminant > 0.0 else 0.0
    wanted = direction * min(max_velocity, max(allowed, 0.0))
    new_velocity = ramp_velocity(velocity, wanted, acc, dec, dt)
    new_position = position + 0.5 * (velocity + new_velocity) * dt
    remaining = direction * (target - new_position)
    if remaining <= _EPSILON and abs(new_velocity) <= brake * (1.0 + 1e-9):
        return target, 0.0, True
    return new_position, new_velocity, False


@dataclass(slots=True)
class StopRamp:
    """Brake a position demand to standstill (halt, quick stop, fault reaction)."""

    position: float = 0.0
    velocity: float = 0.0

    def start(self, position: float, velocity: float) -> None:
        self.position = position
        self.velocity = velocity

    @property
    def stopped(self) -> bool:
        return self.velocity == 0.0

    def step(self, dt: float, dec: float) -> Setpoint:
        new_velocity = ramp_velocity(self.velocity, 0.0, dec, dec, dt)
        self.position += 0.5 * (self.velocity + new_velocity) * dt
        self.velocity = new_velocity
        return Setpoint(ControlKind.POSITION, position=self.position, velocity=new_velocity)


class Mode(Protocol):
    """One operating mode; MotionCore runs the one 6061h shows while Operation enabled."""

    def start(self, values: ValueStore, axis: Axis) -> None:
        """Entering Operation enabled or this mode: take over the axis where it stands."""
        ...

    def on_controlword(self, values: ValueStore, controlword: int, previous: int) -> None:
        """Every controlword write while Operation enabled (edges against `previous`)."""
        ...

    def step(self, dt: float, values: ValueStore, axis: Axis) -> Setpoint: ...

    def take_over(self, position: float) -> None:
        """The drive holds the axis at `position` itself (a drive-inhibit input is active):
        drop the demand that pushed into it, so the mode goes on from standstill there instead
        of winding up behind the hold."""
        ...

    def status_bits(self, axis: Axis) -> int:
        """Statusword bits 10, 12 and 13 for this mode."""
        ...
