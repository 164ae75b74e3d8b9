"""Which listed node is a device that now answers at another id (its node id was changed
outside the wizard, or it was re-addressed by its switches): the same vendor, product and
serial number, offline here and online there. Pure, table-tested."""

from __future__ import annotations

from collections.abc import Sequence

from servodesk.models.nodes import NodeInfo


def _device(info: NodeInfo) -> tuple[int, int, int] | None:
    """vendor, product, serial, when all are known and the serial is one (0 is no serial)."""
    if info.vendor_id is None or info.product_code is None or not info.serial:
        return None
    return info.vendor_id, info.product_code, info.serial


def moved(nodes: Sequence[NodeInfo]) -> dict[int, int]:
    """Offline node id -> the online node id the same device answers at now."""
    online = {_device(n): n.node for n in nodes if n.online and _device(n) is not None}
    found: dict[int, int] = {}
    for info in nodes:
        device = _device(info)
        if not info.online and device is not None and device in online:
            found[info.node] = online[device]
    return found
