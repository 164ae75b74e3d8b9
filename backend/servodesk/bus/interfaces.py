"""The CAN interfaces the connect dialog offers: the common ones with real labels first, then
every other interface python-can knows, with a generic label."""

from __future__ import annotations

from can.interfaces import VALID_INTERFACES

from servodesk.models.bus import InterfaceInfo

_KNOWN: tuple[InterfaceInfo, ...] = (
    InterfaceInfo(
        name="socketcan", label="SocketCAN (Linux)", needs_channel=True, example_channel="can0"
    ),
    InterfaceInfo(
        name="pcan", label="PEAK PCAN-USB", needs_channel=True, example_channel="PCAN_USBBUS1"
    ),
    InterfaceInfo(name="kvaser", label="Kvaser", needs_channel=True, example_channel="0"),
    InterfaceInfo(
        name="slcan",
        label="Serial line CAN (slcan, CANable, USBtin)",
        needs_channel=True,
        example_channel="/dev/ttyACM0",
    ),
    InterfaceInfo(
        name="socketcand",
        label="socketcand (CAN over TCP)",
        needs_channel=True,
        example_channel="can0",
    ),
    InterfaceInfo(
        name="virtual",
        label="Virtual (in this process, for testing)",
        needs_channel=True,
        example_channel="servodesk",
    ),
)

# python-can's udp_multicast puts every frame on the local network (DESIGN rule 6): a
# commissioning tool must not send CANopen commands that way, so it is neither offered nor
# accepted (connection.py refuses it).
REFUSED = frozenset({"udp_multicast"})


def _others() -> tuple[InterfaceInfo, ...]:
    listed = {info.name for info in _KNOWN} | REFUSED
    return tuple(
        InterfaceInfo(
            name=name,
            label=f"{name} (python-can interface)",
            needs_channel=True,
            example_channel="",
        )
        for name in sorted(VALID_INTERFACES)
        if name not in listed
    )


INTERFACES: list[InterfaceInfo] = [*_KNOWN, *_others()]
