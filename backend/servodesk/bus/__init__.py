"""The CAN bus connection: python-can bus + canopen.Network lifecycle, reconnect, statistics."""

from __future__ import annotations

from servodesk.bus.connection import (
    BusFactory,
    BusManager,
    config_from_settings,
    default_bus_factory,
)
from servodesk.bus.interfaces import INTERFACES

__all__ = [
    "INTERFACES",
    "BusFactory",
    "BusManager",
    "config_from_settings",
    "default_bus_factory",
]
