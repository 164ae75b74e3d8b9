"""Device profiles: which drive family a node is, chosen by its identity (1000h, 1018h)."""

from __future__ import annotations

from servodesk.profiles.dictionaries import ProfileDictionaries
from servodesk.profiles.match import (
    GENERIC_CIA301,
    GENERIC_CIA402,
    ProfileMatch,
    load_known,
    match,
)

__all__ = [
    "GENERIC_CIA301",
    "GENERIC_CIA402",
    "ProfileDictionaries",
    "ProfileMatch",
    "load_known",
    "match",
]
