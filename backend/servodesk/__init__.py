"""ServoDesk: browser-based commissioning and field diagnostics for CANopen servo drives."""

__version__ = "0.1.0"
