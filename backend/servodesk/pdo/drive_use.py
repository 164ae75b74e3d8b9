"""What the Drive page does with a node's RPDOs, in one sentence for the live check.

Pure, from the same route choice the motion service makes (commands.py): the controlword and
set-points go in the first valid RPDO the drive applies on receipt (254/255) that maps them,
while the node is Operational and ServoDesk knows every object that RPDO carries; otherwise by
SDO. A synchronous RPDO (applied at the next SYNC) carries no commands — one that acts after a
stop sent meanwhile would undo it — except an interpolation stream's set-points (60C1h:01).
"""

from __future__ import annotations

from collections.abc import Sequence

from servodesk.pdo.commands import COMMAND_OBJECTS, IP_DATA, ip_route_in, route_in
from servodesk.pdo.model import PdoConfig
from servodesk_protocol.pdo import is_synchronous

_NAMES = {
    0x6040: "controlword",
    0x607A: "target position",
    0x60FF: "target velocity",
    0x6071: "target torque",
}


def drive_page_use(pdos: Sequence[PdoConfig]) -> str | None:
    """None when the node has no valid RPDO."""
    rpdos = [p for p in pdos if p.kind == "rpdo" and p.valid]
    if not rpdos:
        return None
    routes: dict[str, list[str]] = {}
    for index in sorted(COMMAND_OBJECTS):
        route = route_in(pdos, index)
        if route is not None:
            routes.setdefault(route.label, []).append(f"{index:04X}h {_NAMES[index]}")
    parts: list[str] = []
    if routes:
        sent = "; ".join(f"{', '.join(objs)} in {label}" for label, objs in routes.items())
        parts.append(
            f"The Drive page sends its commands by RPDO: {sent} (while the node is Operational"
            " and ServoDesk knows every object that RPDO maps; else by SDO)."
        )
    else:
        parts.append("The Drive page does not send its commands in these RPDOs: it uses SDO.")
    timed = [
        f"RPDO{p.number}"
        for p in rpdos
        if is_synchronous(p.transmission_type)
        and any(o.index in COMMAND_OBJECTS and o.subindex == 0 for o in p.mapping)
    ]
    if timed:
        parts.append(
            f"{', '.join(timed)} {'is' if len(timed) == 1 else 'are'} synchronous (applied at"
            " the next SYNC): no command goes there, where it could act after a stop sent"
            " meanwhile."
        )
    ip = ip_route_in(pdos)
    if ip is not None:
        route, at_sync = ip
        when = "taken at SYNC" if at_sync else "taken on receipt"
        parts.append(
            f"An interpolation stream sends its set-points ({IP_DATA:04X}h:01) in {route.label},"
            f" {when}."
        )
    return " ".join(parts)
