"""SQLite storage of the timeline and the fault history (store.py), schema in migrations.py."""

from __future__ import annotations

from servodesk.storage.migrations import LATEST, migrate
from servodesk.storage.store import Retention, Storage, StoredEvent

__all__ = ["LATEST", "Retention", "Storage", "StoredEvent", "migrate"]
