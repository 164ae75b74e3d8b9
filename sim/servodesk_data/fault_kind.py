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
    # Both limit inputs active while enabled: the fault of drives whose limit inputs are drive
    # inhibits (MDi alarm 7 "CCW/CW 驱动禁止输入都 OFF"); one input alone only stops the motion.
    BOTH_LIMITS = "both_limits"
    SYNC_LOST = "sync_lost"
    HEARTBEAT_LOST = "heartbeat_lost"
    LIFE_GUARD = "life_guard"
    HOMING_ERROR = "homing_error"
