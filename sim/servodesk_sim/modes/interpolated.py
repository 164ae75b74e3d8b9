"""Interpolated position mode (6060h = 7), linear interpolation on SYNC (MDi-S1-C manual §3.8).

Controlword bit 4 enables interpolation while it is 1 (statusword bit 12 "插补有效" shows it).
Each SYNC takes the absolute point in 60C1h:01. Following figure 3.6 notes 1–3 the drive plans
one point ahead: the point received at one SYNC is travelled to during the next period, as a
straight line whose increment is spread evenly over the interpolation period 60C2h (value
60C2h:01 × 10^60C2h:02 s, clamped to 1–20 ms on the MDi, note 5). With no SYNC for more than
three periods while interpolation is enabled, the drive reports SYNC loss (MDi alarm 62).
Halt (bit 8) brakes with 6084h and drops the planned segment.
"""

from __future__ import annotations

from servodesk_protocol.cia402 import CW_HALT, CW_NEW_SETPOINT, SW_MODE_BIT12, SW_TARGET_REACHED
from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.modes.common import Axis, Setpoint, acceleration, ramp_velocity
from servodesk_sim.plant import ControlKind, read_or
from servodesk_sim.values import ValueStore

SYNC_LOSS_PERIODS = 3


def interpolation_period(values: ValueStore, clamp_ms: tuple[int, int]) -> float:
    """60C2h in seconds, clamped to the drive's supported range (MDi-S1-C manual §3.8 note 5)."""
    value = read_or(values, 0x60C2, 1, 1)  # Interpolation time period value
    index = read_or(values, 0x60C2, 2, -3)  # Interpolation time index (-3 = ms)
    milliseconds = value * 10.0 ** (index + 3)
    low, high = clamp_ms
    return min(max(milliseconds, low), high) / 1000.0


class Interpolated:
    def __init__(self, period_clamp_ms: tuple[int, int]) -> None:
        self._clamp = period_clamp_ms
        self._active = False
        self._halted = False
        self._position = 0.0
        self._velocity = 0.0
        self._start = 0.0  # segment start, user units
        self._end = 0.0  # segment end
        self._elapsed = 0.0  # time into the segment, s
        self._period = 0.001
        self._buffered: float | None = None  # point received, travelled to after next SYNC
        self._since_sync = 0.0
        self._sync_lost = False

    @property
    def active(self) -> bool:
        return self._active

    def start(self, values: ValueStore, axis: Axis) -> None:
        self._active = False
        self._position = self._start = self._end = axis.position
        self._velocity = 0.0
        self._period = interpolation_period(values, self._clamp)
        self._elapsed = self._period

    def on_controlword(self, values: ValueStore, controlword: int, previous: int) -> None:
        self._halted = bool(controlword & CW_HALT)
        enable = bool(controlword & CW_NEW_SETPOINT)
        if enable and not self._active:
            self._active = True
            self._buffered = None
            self._since_sync = 0.0
            self._sync_lost = False
            self._start = self._end = self._position
            self._elapsed = self._period
        elif not enable and self._active:
            # Interpolation switched off: stay where the demand is.
            self._active = False
            self._start = self._end = self._position
            self._velocity = 0.0

    def on_sync(self, values: ValueStore) -> None:
        if not self._active:
            return
        self._since_sync = 0.0
        self._period = interpolation_period(values, self._clamp)
        if self._buffered is not None and not self._halted:
            self._start, self._end, self._elapsed = self._position, self._buffered, 0.0
        self._buffered = float(read_or(values, 0x60C1, 1, 0))  # Interpolation data record

    def step(self, dt: float, values: ValueStore, axis: Axis) -> Setpoint:
        fault = None
        if self._active:
            self._since_sync += dt
            # A small margin keeps float sums of 1 ms steps from tripping one period early.
            late = self._since_sync > SYNC_LOSS_PERIODS * self._period + 1e-9
            if late and not self._sync_lost:
                self._sync_lost = True
                fault = FaultKind.SYNC_LOST
        if self._halted:
            dec = acceleration(read_or(values, 0x6084, 0, 100000))  # Profile deceleration
            new_velocity = ramp_velocity(self._velocity, 0.0, dec, dec, dt)
            self._position += 0.5 * (self._velocity + new_velocity) * dt
            self._velocity = new_velocity
            self._start = self._end = self._position
            self._elapsed = self._period
        elif self._elapsed < self._period:
            self._elapsed = min(self._period, self._elapsed + dt)
            span = self._end - self._start
            self._position = self._start + span * self._elapsed / self._period
            self._velocity = span / self._period
        else:
            self._velocity = 0.0
        return Setpoint(
            ControlKind.POSITION, position=self._position, velocity=self._velocity, fault=fault
        )

    def take_over(self, position: float) -> None:
        # Interpolation stays enabled; the next SYNC plans from here to the buffered point.
        self._position = self._start = self._end = position
        self._velocity = 0.0
        self._elapsed = self._period

    def status_bits(self, axis: Axis) -> int:
        """Bit 12 interpolation active; bit 10 the demand stands at the last point."""
        bits = SW_MODE_BIT12 if self._active else 0
        if self._velocity == 0.0 and self._elapsed >= self._period:
            bits |= SW_TARGET_REACHED
        return bits
