"""The CAN interfaces the connect dialog offers: the common ones with real labels first, then
every other interface python-can knows, with a generic label."""

from __future__ import annotations

from can.interfaces import VALID_INTERFACES

from servodesk.models import InterfaceInfo

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

# udp_multicast sends to the LAN (DESIGN rule 6): offer it, but say so.
_LABELS = {"udp_multicast": "UDP multicast (sends to the local network)"}


def _others() -> tuple[InterfaceInfo, ...]:
    listed = {info.name for info in _KNOWN}
    return tuple(
        InterfaceInfo(
            name=name,
            label=_LABELS.get(name, f"{name} (python-can interface)"),
            needs_channel=True,
            example_channel="",
        )
        for name in sorted(VALID_INTERFACES)
        if name not in listed
    )


INTERFACES: list[InterfaceInfo] = [*_KNOWN, *_others()]
