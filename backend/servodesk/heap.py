"""Garbage collection off the hot path (DESIGN: the loop never stalls).

CPython's full (generation 2) collection walks every tracked object and stops every thread
while it does: at start-up that is the imports, the profiles and the first scan (over 100 ms
on a quiet host, 400 ms under load), and later every large dictionary the user uploaded. Those
objects live as long as the app or the dictionary and are freed by reference counting (they
hold no cycles), so they are moved out of the collector's sight (`gc.freeze`): a full
collection then only walks what was made since. The young generations keep CPython's
thresholds: each of their collections walks a few thousand objects, well under a millisecond.
"""

from __future__ import annotations

import gc
import sys

# A thread waiting for the interpreter lock (the event loop, a node's worker sending a stop)
# gets it after at most this while a busy thread holds it (CPython's default is 5 ms).
SWITCH_INTERVAL = 0.001


def quiet_start() -> None:
    """Before start-up: no automatic full collections while it allocates (each would walk the
    growing heap from whichever thread allocated, the scan's or the loop's)."""
    gc.disable()


def settle_after_start() -> None:
    """Once, after start-up (before serving): keep start-up's objects out of later passes,
    collect automatically again. Start-up's garbage is frozen with them rather than collected:
    with collections off every start-up object is still young, so any collection would walk all
    of them (100 ms quiet, 400–800 ms under load, the loop and every thread stopped); the
    garbage is a few thousand objects, kept once."""
    sys.setswitchinterval(SWITCH_INTERVAL)
    gc.freeze()
    gc.enable()


def keep_long_lived() -> None:
    """After a large long-lived structure was built (an uploaded dictionary): out of the
    collector's sight, after a young-generation pass so the garbage of building it goes first."""
    gc.collect(1)
    gc.freeze()
