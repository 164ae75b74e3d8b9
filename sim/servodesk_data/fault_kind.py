"""Causes of a drive fault, independent of how each drive family numbers them.

Each profile maps a kind to its own code (MDi alarm number, Kinco 603Fh code, CiA 402 EMCY code).
"""

from __future__ import annotations

from enum import Enum


class FaultKind(Enum):
    OVERSPEED = "overspeed"
    FOLLOWING_ERROR = "following_error"
    POSITIVE_LIMIT = "positive_limit"
    NEGATIVE_LIMIT = "negative_limit"
    SYNC_LOST = "sync_lost"
    HEARTBEAT_LOST = "heartbeat_lost"
    LIFE_GUARD = "life_guard"
    HOMING_ERROR = "homing_error"
