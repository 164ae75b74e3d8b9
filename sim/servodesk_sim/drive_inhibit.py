"""Limit switches as drive-inhibit inputs (profile quirk `limit_switch_reaction = "inhibit"`).

The MDi-S1-C CANopen manual §4.1 raises alarm 7 "驱动禁止异常" only when "CCW/CW 驱动禁止输入都
OFF": both inhibit inputs at once. One active input is no fault, so the drive refuses the motion
toward it and still moves the other way. How it stops is not in the manual: the simulator brakes
the demand with the quick stop deceleration 6085h and holds the axis where that ramp ends, until
the mode's demand points away from the switch. Homing is left alone (it uses the switches).
"""

from __future__ import annotations

from servodesk_sim.modes.common import Axis, Setpoint, StopRamp, Switches
from servodesk_sim.plant import ControlKind


def pushes_into_limit(setpoint: Setpoint, axis: Axis) -> bool:
    """Whether the demand drives the motor toward a limit switch that is active.

    The switches live in the motor frame, so the demand's direction is taken there too.
    """
    scaling = axis.scaling
    if setpoint.kind is ControlKind.TORQUE:
        motor = -setpoint.torque if scaling.reversed else setpoint.torque
    elif setpoint.kind in (ControlKind.POSITION, ControlKind.VELOCITY):
        motor = scaling.to_increments(setpoint.velocity)
    else:
        return False
    if motor > 0.0:
        return bool(axis.switches & Switches.POSITIVE_LIMIT)
    if motor < 0.0:
        return bool(axis.switches & Switches.NEGATIVE_LIMIT)
    return False


class DriveInhibit:
    """Holds the axis while the demand pushes into an active limit switch."""

    def __init__(self) -> None:
        self._ramp = StopRamp()
        self.holding = False

    def reset(self) -> None:
        self.holding = False

    def apply(
        self, dt: float, demand: Setpoint, last: Setpoint, axis: Axis, dec: float
    ) -> Setpoint | None:
        """The set-point to run instead of `demand` (None: run `demand`). `last` is what the
        previous period ran; `dec` the braking deceleration in user units/s²."""
        if not pushes_into_limit(demand, axis) and (not self.holding or self._ramp.stopped):
            self.holding = False  # released only at standstill: the stop is never cut short
            return None
        if not self.holding:
            self.holding = True
            if last.kind is ControlKind.POSITION:
                self._ramp.start(last.position, last.velocity)
            else:
                self._ramp.start(axis.position, axis.velocity)
        return self._ramp.step(dt, dec)
