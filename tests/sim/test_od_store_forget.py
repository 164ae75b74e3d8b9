"""The simulator's "forget at next store" injection (5FF5h, docs/simulator.md): the next store
does not keep one chosen entry, so a reset brings back its default; the one after keeps it."""

from __future__ import annotations

import pytest

from servodesk_protocol.sdo_abort import INVALID_VALUE
from servodesk_sim.abort_codes import SdoAbort
from tests.sim.test_od_store import SAVE, make_store

HEARTBEAT = (0x1017, 0)  # Producer heartbeat time (rw, stored with the communication area)


def test_the_next_store_forgets_the_entry_once() -> None:
    store = make_store()
    store.set(*HEARTBEAT, 100)
    store.write_bytes(0x1010, 1, SAVE)
    store.set(*HEARTBEAT, 250)
    store.forget_at_next_store(*HEARTBEAT)
    store.write_bytes(0x1010, 1, SAVE)
    store.reset_node()
    assert store.get(*HEARTBEAT) == 0  # neither 250 nor the 100 stored before: the default
    store.set(*HEARTBEAT, 250)
    store.write_bytes(0x1010, 1, SAVE)  # the injection was used up
    store.reset_node()
    assert store.get(*HEARTBEAT) == 250


def test_an_entry_that_is_never_stored_is_refused() -> None:
    store = make_store()
    with pytest.raises(SdoAbort) as refused:
        store.forget_at_next_store(0x1000, 0)  # read-only
    assert refused.value.code == INVALID_VALUE
