"""Reading entries for evidence: only what the node's dictionary lists, an SDO abort kept as
the entry's answer (a drive refusing one optional object does not sink the step)."""

from __future__ import annotations

from typing import Any

from servodesk.errors import SdoAbortError
from servodesk.nodes.access import NodeAccess
from servodesk.sdo.service import SdoService


def where(index: int, subindex: int) -> str:
    return f"{index:04X}:{subindex:02X}"


def label(access: NodeAccess, node: int, index: int, subindex: int) -> str | None:
    """The catalogue's name (PA-14) where it has one, else the dictionary's."""
    data = access.profile_data(node)
    if data is not None:
        for parameter in data.parameters:
            if parameter.object == (index, subindex):
                return parameter.name
    sub = access.od(node).get(index, subindex)
    return None if sub is None else sub.name


async def read_listed(
    access: NodeAccess, sdo: SdoService, node: int, objects: list[tuple[int, int]]
) -> list[dict[str, Any]]:
    """Each listed object the dictionary has: {object, index, subindex, name, value, text}
    (or `abort_code` and `error` where the drive refused it)."""
    model = access.od(node)
    found: list[dict[str, Any]] = []
    for index, subindex in objects:
        sub = model.get(index, subindex)
        if sub is None or sub.access == "wo":
            continue
        item: dict[str, Any] = {
            "object": where(index, subindex),
            "index": index,
            "subindex": subindex,
            "name": label(access, node, index, subindex),
        }
        try:
            read = await sdo.read(node, index, subindex)
        except SdoAbortError as error:
            item.update(value=None, abort_code=error.code_hex, error=error.meaning)
        else:
            item.update(value=read.value, text=read.text)
        found.append(item)
    return found
