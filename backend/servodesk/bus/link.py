"""One open connection: the monitored bus, the canopen Network on it, and the notifier.

A link is never repaired: after a failure the connection manager closes it and opens a new one
with the same configuration (python-can buses do not recover from a lost adapter by themselves).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import can
import canopen

from servodesk.bus.counters import BusCounters, CountingListener
from servodesk.bus.monitored import MonitoredBus

log = logging.getLogger(__name__)

# Seconds the notifier thread blocks in recv: closing a link waits for at most one cycle, so a
# short cycle keeps disconnect quick (canopen's default of 1 s would make every disconnect slow).
NOTIFIER_CYCLE = 0.1
NOTIFIER_STOP_TIMEOUT = 2.0


@dataclass
class Link:
    bus: MonitoredBus
    network: canopen.Network
    notifier: can.Notifier
    # Held for the whole close, so a second closer returns only once the bus really is closed.
    _close_lock: threading.Lock = field(default_factory=threading.Lock)
    _closed: bool = False


def open_link(
    raw: can.BusABC,
    counters: BusCounters,
    listeners: Sequence[can.Listener],
    on_failure: Callable[[str], None],
    sent_listeners: Sequence[can.Listener] = (),
) -> Link:
    """Attach a canopen Network to an already open bus (takes ownership of `raw`).
    `sent_listeners` also get every frame the tool sends (live: the sequence is read per send)."""
    bus = MonitoredBus(raw, counters, on_failure, sent_listeners)

    def receive_failed(exc: Exception) -> None:
        on_failure(f"receiving failed: {exc}")

    # canopen 2.4's Network.connect() with `bus` already set only builds the notifier over
    # `network.listeners`; building it here lets us pick the cycle and add our own listeners.
    network = canopen.Network(bus)
    counting = CountingListener(counters, receive_failed)
    try:
        notifier = can.Notifier(bus, [*network.listeners, counting, *listeners], NOTIFIER_CYCLE)
    except BaseException:
        bus.shutdown()
        raise
    network.notifier = notifier
    return Link(bus=bus, network=network, notifier=notifier)


def close_link(link: Link) -> None:
    """Stop the notifier, then close the bus (blocking: joins the notifier thread).

    Safe to call more than once and from several threads."""
    with link._close_lock:
        if link._closed:
            return
        link._closed = True
        try:
            link.notifier.stop(NOTIFIER_STOP_TIMEOUT)
        finally:
            link.bus.shutdown()
            # canopen's send_message refuses to send without a bus: stale users get a clear
            # error instead of writing to a closed adapter.
            link.network.bus = None
