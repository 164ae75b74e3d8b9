"""The event bus (`EventBus`) and its publishers; see bus.py and sources.py."""

from __future__ import annotations

from servodesk.events.bus import BusEvent, EventBus, EventKind, Subscriber, event

__all__ = ["BusEvent", "EventBus", "EventKind", "Subscriber", "event"]
