""" "tool-write" events: what the tool itself changed on a drive, for the timeline (and the audit
log that will build on it). Every one has `data.action` and, where there is one, the object
(`index`, `subindex`) and the value before (`old`, when the tool knew it) and after (`value`):

- `sdo`: a write through the SDO routes (events/sources.py)
- `param`: a named parameter (`name`, `old` read just before)
- `dcf-entry`: one entry a parameter set wrote; `dcf-load`: the load (`file`, `written`, …)
- `pdo-apply`: the PDOs an apply changed (`pdos`: "RPDO1" …)
- `store`, `restore-defaults`: 1010h / 1011h commands
- `clear-history`: 1003h cleared
- `jog-stop`: a jog ended (`jog_id`, `mode`, `reason`: "keep-alive missed for 300 ms",
  "heartbeat lost", "stopped by the user" …), whoever stopped it: once when the stop went out
  (`state` "stopping") and once when the axis is at rest (`state` "stopped")

NMT commands the tool sends keep their own kind, `nmt` (`data.command`, `data.tool` true).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from servodesk.events.bus import BusEvent, EventKind, event
from servodesk.motion.jog import REPLACED
from servodesk.motion.safety_models import JogInfo
from servodesk.pdo.model import PdoConfig

Publish = Callable[[BusEvent], None]


def where(index: int, subindex: int) -> str:
    return f"{index:04X}h:{subindex:02X}h"


def tool_write(node: int | None, message: str, action: str, **data: Any) -> BusEvent:
    return event(EventKind.TOOL_WRITE, node, message, {"action": action, **data})


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
        text = f"applied the PDOs of node {node}"
    elif changed:
        text = f"applied PDOs of node {node}: {', '.join(changed)} changed"
    else:
        text = f"applied PDOs of node {node}: nothing changed"
    publish(tool_write(node, text, "pdo-apply", pdos=changed, known_before=before is not None))


def jog_stopped(publish: Publish, jog: JogInfo) -> None:
    """A jog's end on the timeline with its reason, so "why did the axis stop?" has an answer
    there too (a jog a new one took over did not stop the axis: no event)."""
    if (jog.stop_reason or "").endswith(REPLACED):
        return
    # "stopping" when the stop went out, "at rest" once the axis stands: the timeline never
    # says a jog stopped while the axis still runs
    how = "stopping" if jog.state == "stopping" else "at rest"
    publish(
        tool_write(
            jog.node,
            f"node {jog.node}: {jog.mode.upper()} jog {how} ({jog.stop_reason})",
            "jog-stop",
            jog_id=jog.jog_id,
            mode=jog.mode,
            reason=jog.stop_reason,
            state=jog.state,
        )
    )
