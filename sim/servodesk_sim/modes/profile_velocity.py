"""Profile velocity mode (6060h = 3): 60FFh reached over a 6083h ramp (MDi-S1-C manual §3.5).

"轮廓加速度应用于速度模式的加减速": 6083h is used for speeding up and for slowing down.
The target is not clamped to the overspeed limit: asking for more shows statusword bit 13
("速度超限", MDi-S1-C manual §3.2.3) and then trips the overspeed alarm, as the real drive would.
"""

from __future__ import annotations

from servodesk_protocol.cia402 import CW_HALT, SW_MODE_BIT13, SW_TARGET_REACHED
from servodesk_sim.modes.common import Axis, Setpoint, acceleration, ramp_velocity
from servodesk_sim.plant import ControlKind, read_or
from servodesk_sim.values import ValueStore

VELOCITY_WINDOW_RPM = 10.0  # 606Dh is not in the MDi dictionary; a fixed window stands in


class ProfileVelocity:
    def __init__(self) -> None:
        self._velocity = 0.0
        self._target = 0.0
        self._halted = False
        self._over_limit = False

    def start(self, values: ValueStore, axis: Axis) -> None:
        # Take over the running speed so a mode change does not jerk the axis.
        self._velocity = axis.velocity
        self._target = axis.velocity

    def on_controlword(self, values: ValueStore, controlword: int, previous: int) -> None:
        self._halted = bool(controlword & CW_HALT)

    def step(self, dt: float, values: ValueStore, axis: Axis) -> Setpoint:
        requested = float(read_or(values, 0x60FF, 0, 0))  # Target velocity
        self._over_limit = abs(requested) > axis.max_speed
        self._target = 0.0 if self._halted else requested
        acc = acceleration(read_or(values, 0x6083, 0, 100000))  # Profile acceleration
        self._velocity = ramp_velocity(self._velocity, self._target, acc, acc, dt)
        return Setpoint(ControlKind.VELOCITY, position=axis.position, velocity=self._velocity)

    def take_over(self, position: float) -> None:
        self._velocity = 0.0  # 60FFh ramps again from standstill, checked anew each period

    def status_bits(self, axis: Axis) -> int:
        """Bit 10 target velocity reached (or halted at standstill), bit 13 speed over limit."""
        bits = SW_MODE_BIT13 if self._over_limit else 0
        window = abs(axis.scaling.rpm_to_user(VELOCITY_WINDOW_RPM))
        if self._velocity == self._target and abs(axis.velocity - self._target) <= window:
            bits |= SW_TARGET_REACHED
        return bits
