"""Who a node is: 1000h Device type, 1018h Identity object, 1008h Device name, 1009h/100Ah hardware
and software (firmware) versions, 1017h heartbeat.

`read_identity` blocks (SDO): run it on the node's session thread. 1000h is mandatory in every
CANopen device, so a timeout on it means nobody is there and propagates; an abort on it still
proves a node answered. Every other entry is optional and reads as None when the node refuses
it; after one timeout the remaining reads are skipped (the node just went away).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import canopen
from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

from servodesk_protocol.nmt import PRODUCER_HEARTBEAT_TIME

DEVICE_TYPE = 0x1000  # Device type
DEVICE_NAME = 0x1008  # Manufacturer device name
HARDWARE_VERSION = 0x1009  # Manufacturer hardware version
SOFTWARE_VERSION = 0x100A  # Manufacturer software version
PRODUCER_HEARTBEAT = PRODUCER_HEARTBEAT_TIME  # Producer heartbeat time (ms)
IDENTITY = 0x1018  # Identity object: 1 vendor-ID, 2 product code, 3 revision, 4 serial number


@dataclass(frozen=True)
class Identity:
    device_type: int | None = None
    vendor_id: int | None = None
    product_code: int | None = None
    revision: int | None = None
    serial: int | None = None
    name: str | None = None
    heartbeat_ms: int | None = None
    hardware: str | None = None  # 1009h manufacturer hardware version
    software: str | None = None  # 100Ah manufacturer software (firmware) version

    def same_device(self, other: Identity) -> bool:
        """The same kind of device (vendor and product), e.g. after a reboot."""
        return (self.vendor_id, self.product_code) == (other.vendor_id, other.product_code)


class _OptionalReader:
    def __init__(self, remote: canopen.RemoteNode) -> None:
        self._remote = remote
        self._gone = False

    def raw(self, index: int, subindex: int) -> bytes | None:
        if self._gone:
            return None
        try:
            return bytes(self._remote.sdo.upload(index, subindex))
        except SdoAbortedError:
            return None  # the node does not have this entry
        except SdoCommunicationError:
            self._gone = True
            return None

    def uint(self, index: int, subindex: int) -> int | None:
        data = self.raw(index, subindex)
        return int.from_bytes(data, "little") if data else None

    def text(self, index: int, subindex: int) -> str | None:
        data = self.raw(index, subindex)
        if data is None:
            return None
        # VISIBLE_STRING is ASCII; latin-1 decodes any byte so a sloppy device still shows
        text = data.decode("latin-1").rstrip("\x00").strip()
        return text or None


def read_identity(remote: canopen.RemoteNode) -> Identity:
    """Blocking: identify the node behind `remote` (see the module docstring)."""
    try:
        device_type: int | None = int.from_bytes(remote.sdo.upload(DEVICE_TYPE, 0), "little")
    except SdoAbortedError:
        device_type = None  # it answered: a node is there, it only refuses 1000h
    read = _OptionalReader(remote)
    return Identity(
        device_type=device_type,
        vendor_id=read.uint(IDENTITY, 1),
        product_code=read.uint(IDENTITY, 2),
        revision=read.uint(IDENTITY, 3),
        serial=read.uint(IDENTITY, 4),
        name=read.text(DEVICE_NAME, 0),
        heartbeat_ms=read.uint(PRODUCER_HEARTBEAT, 0),
    )


def read_versions(remote: canopen.RemoteNode, identity: Identity) -> Identity:
    """Blocking: `identity` with 1009h/100Ah, for the ones the node's dictionary lists (asked
    after its profile is known: a read of an object the node lacks is an SDO abort, which the
    timeline would show at every scan)."""
    listed = remote.object_dictionary
    read = _OptionalReader(remote)
    hardware = read.text(HARDWARE_VERSION, 0) if HARDWARE_VERSION in listed else None
    software = read.text(SOFTWARE_VERSION, 0) if SOFTWARE_VERSION in listed else None
    return replace(identity, hardware=hardware, software=software)
