"""Commissioning records: a guided flow per axis whose record proves what the drive holds
(docs/api.md, "Commissioning"). models: the record; plan: which steps a drive can do (pure);
store: SQLite; evidence / store_verify: the automated steps; service: what the API calls."""

from servodesk.commissioning.service import CommissioningService

__all__ = ["CommissioningService"]
