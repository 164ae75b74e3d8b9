"""Motion commands in the drive's own RPDOs: where an RPDO maps the controlword or a set-point
(60FFh, 6071h, 607Ah), the command goes in that RPDO's frame instead of an SDO download — one
frame, no answer to wait for, no place in the node's SDO queue. An interpolation stream sends its
60C1h:01 set-points in the RPDO the manuals map for it (`ip_route_in`), taken at SYNC.

An RPDO carries every object it maps at once, so a frame is built only when the value of each
of them is known: what ServoDesk itself last wrote (the motion service keeps that and forgets
it on every stop and on any other write). An object with no known value sends nothing by RPDO:
the command falls back to SDO. Only RPDOs the drive applies on receipt (transmission types
254/255) are used: one applied at the next SYNC would act after a stop sent meanwhile by SDO.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

import canopen

from servodesk.errors import ServodeskError
from servodesk.pdo.model import PdoConfig
from servodesk_protocol.cia402 import CONTROLWORD, MODES_OF_OPERATION
from servodesk_protocol.pdo import DUMMY_BITS

TARGET_TORQUE, TARGET_POSITION, TARGET_VELOCITY = 0x6071, 0x607A, 0x60FF
COMMAND_OBJECTS = frozenset({CONTROLWORD, TARGET_VELOCITY, TARGET_TORQUE, TARGET_POSITION})
ON_RECEIPT = (254, 255)  # event-driven RPDOs: the drive takes them as they arrive


class PdoCache(Protocol):
    """What the routes read of the PDO service (pdo/service.py, which imports this module
    through its live check: named here by what it does, no import cycle even for types)."""

    def known(self, node: int) -> Sequence[PdoConfig] | None: ...

    def network(self) -> canopen.Network: ...


@dataclass(frozen=True, slots=True)
class RpdoRoute:
    """One RPDO a command can travel in."""

    label: str  # "RPDO1"
    cob_id: int
    fields: tuple[tuple[int, int], ...]  # (index, bits) in frame order; index 0: a dummy

    def payload(self, values: Mapping[int, int]) -> bytes | None:
        """The frame for these object values; None when one mapped object has none."""
        packed = 0
        offset = 0
        for index, bits in self.fields:
            if index:
                value = values.get(index)
                if value is None:
                    return None
                packed |= (value & ((1 << bits) - 1)) << offset
            offset += bits
        return packed.to_bytes((offset + 7) // 8, "little")


def route_in(pdos: Sequence[PdoConfig], index: int) -> RpdoRoute | None:
    """The first valid, event-driven RPDO mapping `index`:00 (whole objects only)."""
    if index not in COMMAND_OBJECTS:
        return None
    for pdo in pdos:
        if pdo.kind != "rpdo" or not pdo.valid or pdo.transmission_type not in ON_RECEIPT:
            continue
        if not any(obj.index == index and obj.subindex == 0 for obj in pdo.mapping):
            continue
        if any(obj.subindex != 0 and obj.index not in DUMMY_BITS for obj in pdo.mapping):
            continue  # a record's sub-entry: not an object the motion service writes
        fields = tuple((0 if o.index in DUMMY_BITS else o.index, o.bits) for o in pdo.mapping)
        return RpdoRoute(f"RPDO{pdo.number}", pdo.cob_id, fields)
    return None


IP_DATA = 0x60C1  # Interpolation data record (:01 the position set-point)
# what an IP RPDO may carry beside 60C1h:01
IP_COMPANIONS = frozenset({CONTROLWORD, MODES_OF_OPERATION})


def ip_route_in(pdos: Sequence[PdoConfig]) -> tuple[RpdoRoute, bool] | None:
    """The RPDO an interpolation stream sends 60C1h:01 in, and whether the drive takes it at
    the next SYNC (types 1–240) rather than on receipt: the first valid RPDO mapping 60C1h:01
    with nothing else than the controlword and 6060h (the manuals' IP mapping)."""
    for pdo in pdos:
        if pdo.kind != "rpdo" or not pdo.valid:
            continue
        synchronous = 1 <= pdo.transmission_type <= 240
        if not synchronous and pdo.transmission_type not in ON_RECEIPT:
            continue
        keys = {(o.index, o.subindex) for o in pdo.mapping if o.index not in DUMMY_BITS}
        if (IP_DATA, 1) not in keys:
            continue
        if any(k != (IP_DATA, 1) and (k[1] != 0 or k[0] not in IP_COMPANIONS) for k in keys):
            continue
        fields = tuple((0 if o.index in DUMMY_BITS else o.index, o.bits) for o in pdo.mapping)
        return RpdoRoute(f"RPDO{pdo.number}", pdo.cob_id, fields), synchronous
    return None


class RpdoRoutes:
    """The command routes of every node, from the PDO service's cache (never read for them:
    a node whose PDOs were not read yet takes SDO)."""

    def __init__(self, pdos: PdoCache, *, operational: Callable[[int], bool]) -> None:
        self._pdos = pdos
        self._operational = operational

    def ip_route(self, node: int) -> tuple[RpdoRoute, bool] | None:
        known = self._pdos.known(node)
        if known is None or not self._operational(node):
            return None
        return ip_route_in(known)

    def route(self, node: int, index: int) -> RpdoRoute | None:
        known = self._pdos.known(node)
        if known is None or index not in COMMAND_OBJECTS or not self._operational(node):
            return None
        return route_in(known, index)

    def network(self) -> canopen.Network | None:
        try:
            return self._pdos.network()
        except ServodeskError:  # no bus
            return None
