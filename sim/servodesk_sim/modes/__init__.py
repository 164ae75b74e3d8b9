"""CiA 402 operating modes of the simulated drives (MDi-S1-C manual ch. 3), one module per mode."""

from __future__ import annotations

from servodesk_sim.modes.common import (
    Axis,
    Mode,
    Setpoint,
    StopRamp,
    Switches,
    read_switches,
)
from servodesk_sim.modes.homing import Homing
from servodesk_sim.modes.interpolated import Interpolated
from servodesk_sim.modes.profile_position import ProfilePosition
from servodesk_sim.modes.profile_torque import ProfileTorque
from servodesk_sim.modes.profile_velocity import ProfileVelocity

__all__ = [
    "Axis",
    "Homing",
    "Interpolated",
    "Mode",
    "ProfilePosition",
    "ProfileTorque",
    "ProfileVelocity",
    "Setpoint",
    "StopRamp",
    "Switches",
    "read_switches",
]
