"""A python-can bus wrapper that counts what is sent and notices when the adapter fails.

canopen talks to `network.bus`; giving it this wrapper instead of the raw bus lets the tool count
every transmitted frame (including python-can's cyclic SYNC task, which calls `send`) and learn
about a failing adapter from any thread, without patching canopen.

Periodic frames (`send_periodic`: canopen's SYNC producer) go to the adapter's own scheduler
where it has one (SocketCAN: the kernel's broadcast manager), elsewhere to a thread that keeps
time without catch-up bursts (bus/cyclic.py).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence

import can
from can.interfaces.socketcan import SocketcanBus

from servodesk.bus.counters import BusCounters
from servodesk.bus.cyclic import SteadyCyclicSendTask

log = logging.getLogger(__name__)


class MonitoredBus(can.BusABC):
    """Delegates to `inner`; after the first receive error it goes quiet instead of raising
    again, so the notifier thread neither dies nor spins on a dead adapter."""

    def __init__(
        self,
        inner: can.BusABC,
        counters: BusCounters,
        on_failure: Callable[[str], None],
        sent_listeners: Sequence[can.Listener] = (),
    ) -> None:
        self.inner = inner
        # Frames the tool sends never come back through recv (no local echo on most adapters):
        # listeners that must see the whole bus (a recording) get them here, on the sending
        # thread, so they must not block either.
        self.sent_listeners = sent_listeners
        self.channel_info = inner.channel_info
        self._counters = counters
        self._on_failure = on_failure
        self._failed = threading.Event()
        self._closed = threading.Event()
        self._periodic_lock = threading.Lock()  # python-can: one periodic sender at a time
        super().__init__(channel=inner.channel_info)

    @property
    def failed(self) -> bool:
        return self._failed.is_set()

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        if self._failed.is_set():
            # Wait like an idle bus until the manager shuts this link down.
            self._closed.wait(timeout)
            return None, True
        try:
            msg = self.inner.recv(timeout)
        except can.CanError:
            self._failed.set()
            self._counters.bus_error()
            raise  # the notifier hands it to CountingListener.on_error
        return msg, True  # the inner bus applied its own filters

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        sent_at = time.time()  # before: the answer it provokes may be stamped while send returns
        try:
            self.inner.send(msg, timeout)
        except can.CanError as exc:
            self._failed.set()
            self._counters.bus_error()
            self._on_failure(f"sending failed: {exc}")
            raise
        self._counters.sent()
        for listener in self.sent_listeners:
            listener.on_message_received(_as_sent(msg, sent_at))

    def _send_periodic_internal(
        self,
        msgs: Sequence[can.Message] | can.Message,
        period: float,
        duration: float | None = None,
        autostart: bool = True,
        modifier_callback: Callable[[can.Message], None] | None = None,
    ) -> can.broadcastmanager.CyclicSendTaskABC:
        """python-can's hook behind `send_periodic` (which keeps the task, so `shutdown` stops
        it). The kernel's broadcast manager sends without this process (its frames reach the
        notifier through the socket's loopback: counted as received, not as sent)."""
        if isinstance(self.inner, SocketcanBus) and modifier_callback is None:
            return self.inner._send_periodic_internal(msgs, period, duration, autostart)
        # A failing send already reported the adapter through `send`: the task ends quietly.
        return SteadyCyclicSendTask(
            self,
            self._periodic_lock,
            msgs,
            period,
            duration,
            on_error=lambda _: False,
            autostart=autostart,
            modifier_callback=modifier_callback,
        )

    def shutdown(self) -> None:
        self._closed.set()
        super().shutdown()  # stops the cyclic tasks started through this wrapper
        try:
            self.inner.shutdown()
        except (can.CanError, OSError):
            # A lost adapter often fails to close too; the link is gone either way.
            log.warning("closing the CAN adapter failed", exc_info=True)


def _as_sent(msg: can.Message, sent_at: float) -> can.Message:
    """A copy stamped with the time it left, marked as transmitted (python-can's writers keep
    the direction where the format has one)."""
    return can.Message(
        timestamp=sent_at,
        arbitration_id=msg.arbitration_id,
        is_extended_id=msg.is_extended_id,
        is_remote_frame=msg.is_remote_frame,
        is_error_frame=msg.is_error_frame,
        dlc=msg.dlc,
        data=msg.data,
        channel=msg.channel,
        is_rx=False,
    )
