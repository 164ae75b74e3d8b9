"""The "tool-write" event of a PDO apply (`pdo-apply`, events/tool_writes.py): which PDOs it
changed. The app hands it to PdoService as `on_applied`."""

from __future__ import annotations

from collections.abc import Sequence

from servodesk.events.texts import say
from servodesk.events.tool_writes import Publish, tool_write
from servodesk.pdo.model import PdoConfig


def pdo_name(pdo: PdoConfig) -> str:
    return f"{pdo.kind.upper()}{pdo.number}"


def pdo_applied(
    publish: Publish, node: int, before: Sequence[PdoConfig] | None, after: Sequence[PdoConfig]
) -> None:
    """One event naming the PDOs an apply changed (compared with the PDOs read before, when the
    service had them; else every PDO read back)."""
    old = {pdo_name(p): p for p in before or ()}
    changed = [pdo_name(p) for p in after if old.get(pdo_name(p)) != p]
    if before is None:
        said = say("event.pdos_applied", node=node)
    elif changed:
        said = say("event.pdos_changed", node=node, pdos=", ".join(changed))
    else:
        said = say("event.pdos_unchanged", node=node)
    publish(tool_write(node, said, "pdo-apply", pdos=changed, known_before=before is not None))
