"""The event bus (`EventBus`, bus.py) and the "tool-write" events (tool_writes.py): a bottom
layer that imports nothing else of servodesk. The publishers that know a service's types live
beside that service (`sdo/publish.py`, `pdo/publish.py`, `motion/publish.py`); the node
registry publishes its own (boot-up, node lost/back, NMT, bus) on the bus it is given."""

from __future__ import annotations

from servodesk.events.bus import BusEvent, EventBus, EventKind, Subscriber, event

__all__ = ["BusEvent", "EventBus", "EventKind", "Subscriber", "event"]
