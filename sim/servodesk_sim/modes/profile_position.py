"""Profile position mode (6060h = 1): set-point handshake and trapezoidal moves (MDi-S1-C manual
§3.4).

Handshake: a 0 -> 1 edge of controlword bit 4 offers 607Ah (absolute, or relative with bit 6)
with 6081h/6083h/6084h; it is taken only while statusword bit 12 is 0, and bit 12 then shows 1.

- Non-immediate on the MDi ("驱动器只支持非立即更新功能", MDi-S1-C manual §3.4.2 first timing): bit
12
  means "position running / cannot take a new target"; it stays 1 until the move has ended and
  bit 4 is back to 0, so the master waits for the current move before offering the next.
- Drives that honour bit 5 (CiA 402): with bit 5 = 1 the new set-point replaces the running one
  at once and bit 12 follows bit 4 back to 0 (MDi-S1-C manual §3.4.2 second timing); with bit 5 = 0
  it
  is buffered and started when the running move reaches its target, bit 12 staying 1 while the
  buffer is full.

Halt (bit 8) brakes with 6084h and keeps the set-point: releasing halt resumes the move.
Relative targets add to the last accepted target (the end of the running move when buffered).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from servodesk_protocol.cia402 import (
    CW_CHANGE_IMMEDIATELY,
    CW_HALT,
    CW_NEW_SETPOINT,
    CW_RELATIVE,
    SW_MODE_BIT12,
    SW_TARGET_REACHED,
)
from servodesk_sim.modes.common import (
    Axis,
    Setpoint,
    acceleration,
    ramp_velocity,
    trapezoid_step,
)
from servodesk_sim.plant import ControlKind, read_or
from servodesk_sim.values import ValueStore

DEFAULT_POSITION_WINDOW_REV = 0.001  # 6067h when absent: 1/1000 revolution


@dataclass(frozen=True, slots=True)
class _Move:
    target: float  # user units
    velocity: float  # 6081h, user units/s
    acc: float  # 6083h, user units/s²
    dec: float  # 6084h, user units/s²


class ProfilePosition:
    def __init__(self, immediate_setpoint: bool) -> None:
        self._honours_bit5 = immediate_setpoint
        self._position = 0.0
        self._velocity = 0.0
        self._active: _Move | None = None
        self._pending: _Move | None = None
        self._last_target = 0.0
        self._ack = False
        self._halted = False
        self._bit4 = False
        self._window = 0.0

    def start(self, values: ValueStore, axis: Axis) -> None:
        """Enter the mode (enable or mode change): stand still, forget set-points."""
        self._window = _position_window(values, axis)
        self._position = axis.position
        self._velocity = 0.0
        self._active = self._pending = None
        self._last_target = axis.position
        self._ack = False
        self._halted = False

    def on_controlword(self, values: ValueStore, controlword: int, previous: int) -> None:
        self._halted = bool(controlword & CW_HALT)
        self._bit4 = bool(controlword & CW_NEW_SETPOINT)
        if self._bit4 and not previous & CW_NEW_SETPOINT and not self._ack:
            self._accept(values, controlword)
        self._update_ack()

    def _accept(self, values: ValueStore, controlword: int) -> None:
        raw_target = read_or(values, 0x607A, 0, 0)  # Target position
        target = raw_target + self._last_target if controlword & CW_RELATIVE else raw_target
        move = _Move(
            target=float(target),
            velocity=float(read_or(values, 0x6081, 0, 100000)),  # Profile velocity
            acc=acceleration(read_or(values, 0x6083, 0, 100000)),  # Profile acceleration
            dec=acceleration(read_or(values, 0x6084, 0, 100000)),  # Profile deceleration
        )
        self._last_target = move.target
        immediate = self._honours_bit5 and bool(controlword & CW_CHANGE_IMMEDIATELY)
        if immediate or self._active is None:
            self._active, self._pending = move, None
        else:
            self._pending = move
        self._ack = True

    def _update_ack(self) -> None:
        if self._bit4 or not self._ack:
            return
        # Bit 4 is low: the drive can take the next set-point once it has room for it.
        busy = self._pending is not None if self._honours_bit5 else self._active is not None
        self._ack = busy

    def step(self, dt: float, values: ValueStore, axis: Axis) -> Setpoint:
        self._window = _position_window(values, axis)
        if self._halted:
            dec = acceleration(read_or(values, 0x6084, 0, 100000))  # Profile deceleration
            new_velocity = ramp_velocity(self._velocity, 0.0, dec, dec, dt)
            self._position += 0.5 * (self._velocity + new_velocity) * dt
            self._velocity = new_velocity
        elif self._active is not None:
            move = self._active
            self._position, self._velocity, arrived = trapezoid_step(
                self._position, self._velocity, move.target, move.velocity, move.acc, move.dec, dt
            )
            if arrived:
                self._active, self._pending = self._pending, None
                self._update_ack()
        return Setpoint(ControlKind.POSITION, position=self._position, velocity=self._velocity)

    def take_over(self, position: float) -> None:
        # The move that ran into the inhibit is dropped (its target lies beyond it); the
        # handshake stays as it is, so the master can offer a set-point the other way.
        self._position = self._last_target = position
        self._velocity = 0.0
        self._active = self._pending = None
        self._update_ack()

    def status_bits(self, axis: Axis) -> int:
        """Bit 10 target reached (or halted at standstill), bit 12 set-point acknowledge."""
        bits = SW_MODE_BIT12 if self._ack else 0
        if self._halted:
            if self._velocity == 0.0:
                bits |= SW_TARGET_REACHED
        elif self._active is None and abs(axis.position - self._position) <= self._window:
            bits |= SW_TARGET_REACHED
        return bits


def _position_window(values: ValueStore, axis: Axis) -> float:
    window = read_or(values, 0x6067, 0, -1)  # Position window
    if window == 0xFFFFFFFF:  # CiA 402: window switched off
        return math.inf
    if window >= 0:
        return window + 0.5  # the published positions are whole units
    revolution = abs(axis.scaling.to_user(axis.scaling.encoder_resolution))
    return revolution * DEFAULT_POSITION_WINDOW_REV
