"""Profile torque mode (6060h = 4): 6071h reached over the 6087h slope (MDi-S1-C manual §3.6).

"当速度达到限幅值将进入调速阶段": once the speed reaches the limit (the overspeed object,
2006h:08 or 6080h) the drive regulates speed instead of torque; the plant does that part.
Halt (bit 8) ramps the torque demand to zero over the same slope.
"""

from __future__ import annotations

from servodesk_protocol.cia402 import CW_HALT, SW_TARGET_REACHED
from servodesk_sim.modes.common import Axis, Setpoint
from servodesk_sim.plant import ControlKind, read_or
from servodesk_sim.values import ValueStore


class ProfileTorque:
    def __init__(self) -> None:
        self._torque = 0.0  # demand, 0.1 % rated
        self._target = 0.0
        self._halted = False

    def start(self, values: ValueStore, axis: Axis) -> None:
        self._torque = 0.0
        self._target = 0.0

    def on_controlword(self, values: ValueStore, controlword: int, previous: int) -> None:
        self._halted = bool(controlword & CW_HALT)

    def step(self, dt: float, values: ValueStore, axis: Axis) -> Setpoint:
        self._target = (
            0.0 if self._halted else float(read_or(values, 0x6071, 0, 0))
        )  # Target torque
        slope = read_or(values, 0x6087, 0, 1) * 1000.0  # Torque slope, 0.1 %/ms -> 0.1 %/s
        if slope <= 0.0:  # no slope: a step change
            self._torque = self._target
        elif self._torque < self._target:
            self._torque = min(self._target, self._torque + slope * dt)
        else:
            self._torque = max(self._target, self._torque - slope * dt)
        return Setpoint(
            ControlKind.TORQUE,
            position=axis.position,
            velocity=axis.velocity,
            torque=self._torque,
            velocity_limit=axis.max_speed,
        )

    def take_over(self, position: float) -> None:
        self._torque = 0.0  # 6071h slopes again from zero, checked anew each period

    def status_bits(self, axis: Axis) -> int:
        """Bit 10: the torque demand has reached the target (zero when halted)."""
        return SW_TARGET_REACHED if self._torque == self._target else 0
