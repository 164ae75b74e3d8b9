"""Refuse a bus configuration that cannot work before anything is touched.

python-can fills unset arguments from its config file and environment when the bus is opened;
an interface found nowhere only fails there, as a traceback ("Unknown interface type None").
So the same resolution runs first, and an incomplete or unknown configuration is refused in one
sentence that says what to do.
"""

from __future__ import annotations

import can
from can.interfaces import VALID_INTERFACES

from servodesk.bus.interfaces import REFUSED
from servodesk.errors import InvalidValueError
from servodesk.models.bus import BusConfig

NO_INTERFACE = (
    "no CAN interface given: pass -i/--interface and -c/--channel (e.g. -i socketcan -c can0), "
    "or --sim for the simulated drives, or set one in python-can's config file"
)


def check_bus_config(config: BusConfig) -> BusConfig:
    """`config` unchanged if python-can can open it; InvalidValueError otherwise."""
    if config.simulated:
        return config
    interface = config.interface
    if interface is None:
        try:
            interface = can.util.load_config().get("interface")
        except can.CanInterfaceNotImplementedError:
            interface = None  # python-can's way of saying "none configured"
        if interface is None:
            raise InvalidValueError(NO_INTERFACE)
    if interface in REFUSED:
        raise InvalidValueError(
            f"the {interface} interface sends every frame onto the local network; "
            "use a CAN adapter, socketcand or the simulated drives"
        )
    if interface not in VALID_INTERFACES:
        known = ", ".join(sorted(VALID_INTERFACES - REFUSED))
        raise InvalidValueError(f"unknown CAN interface {interface!r}; python-can knows: {known}")
    return config
