"""FaultKind lives with the drive data (the tool reads it too); the simulator re-exports it."""

from servodesk_data.fault_kind import FaultKind

__all__ = ["FaultKind"]
