""" "tool-write" events: what the tool itself changed on a drive, for the timeline (and the audit
log that will build on it). Every one has `data.action` and, where there is one, the object
(`index`, `subindex`) and the value before (`old`, when the tool knew it) and after (`value`):

- `sdo`: a write through the SDO routes (sdo/publish.py)
- `param`: a named parameter (`name`, `old` read just before)
- `dcf-entry`: one entry a parameter set wrote; `dcf-load`: the load (`file`, `written`, …)
- `pdo-apply`: the PDOs an apply changed (`pdos`: "RPDO1" …; pdo/publish.py)
- `store`, `restore-defaults`: 1010h / 1011h commands
- `clear-history`: 1003h cleared
- `jog-stop`: a jog ended (`jog_id`, `mode`, `reason`: "keep-alive missed for 300 ms",
  "heartbeat lost", "stopped by the user" …), whoever stopped it: once when the stop went out
  (`state` "stopping") and once when the axis is at rest (`state` "stopped"; motion/publish.py)

NMT commands the tool sends keep their own kind, `nmt` (`data.command`, `data.tool` true,
`data.broadcast`; published typed by the node registry).

This module builds the events and imports nothing but the event bus: the publishers that know
a service's types live beside that service (`servodesk.sdo.publish`, `servodesk.pdo.publish`,
`servodesk.motion.publish`), so `servodesk.events` stays a bottom
layer every package may import (docs/architecture.md, "Layers").
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from servodesk.events.bus import BusEvent, EventKind, event
from servodesk.events.texts import Said

Publish = Callable[[BusEvent], None]


def where(index: int, subindex: int) -> str:
    return f"{index:04X}h:{subindex:02X}h"


def tool_write(node: int | None, message: str | Said, action: str, **data: Any) -> BusEvent:
    return event(EventKind.TOOL_WRITE, node, message, {"action": action, **data})
