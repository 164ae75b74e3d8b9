"""The tool's own SYNC producer (COB-ID 80h), through canopen's SyncProducer.

python-can sends it from a cyclic task bound to the bus, so it stops with the bus: the kernel's
broadcast manager on SocketCAN, elsewhere a thread that sends a late SYNC once and moves its
schedule instead of sending the missed ones back to back (bus/monitored.py, bus/cyclic.py).
After an automatic reconnect the producer is started again on the new connection at the same
period; an explicit disconnect stops it for good.
"""

from __future__ import annotations

import canopen

from servodesk.bus.connection import BusManager
from servodesk.errors import InvalidValueError
from servodesk.models.bus import BusState, BusStatus
from servodesk.models.network import SyncConfig

US = 1_000_000
# A sender thread cannot hold a shorter period steadily (its p99 error is a few hundred µs on a
# quiet PC); drives that need more (MDi: ≥ 500 µs, MDi-S1-C manual §2.6) are at that edge.
MIN_PERIOD_US = 500
MAX_PERIOD_US = 0xFFFFFFFF  # 1006h Communication cycle period is UNSIGNED32 µs


class SyncService:
    def __init__(self, bus: BusManager) -> None:
        self._bus = bus
        self._period_us: int | None = None  # what the user asked for
        self._network: canopen.Network | None = None  # where it is running now
        self._remove_listener = bus.add_listener(self._on_bus)

    def get(self) -> SyncConfig:
        producing = self._network is not None and self._period_us is not None
        return SyncConfig(producing=producing, period_us=self._period_us)

    async def set(self, period_us: int | None) -> SyncConfig:
        """Produce SYNC every `period_us` µs; None or 0 stops it."""
        if not period_us:
            self._stop()
            self._period_us = None
            return self.get()
        if not MIN_PERIOD_US <= period_us <= MAX_PERIOD_US:
            raise InvalidValueError(
                f"SYNC period {period_us} µs is outside {MIN_PERIOD_US}–{MAX_PERIOD_US} µs"
            )
        network = self._bus.network  # BusNotConnectedError when there is no bus
        self._stop()
        # starting a cyclic task only spawns python-can's sender thread: no I/O on the loop
        network.sync.start(period_us / US)
        self._network = network
        self._period_us = period_us
        return self.get()

    def close(self) -> None:
        self._stop()
        self._remove_listener()

    def _stop(self) -> None:
        network, self._network = self._network, None
        if network is not None:
            network.sync.stop()  # type: ignore[no-untyped-call]  # canopen: unannotated

    def _on_bus(self, status: BusStatus) -> None:
        if status.state is BusState.DISCONNECTED:
            self._stop()
            self._period_us = None
        elif status.state is BusState.ERROR:
            self._network = None  # the cyclic task died with the failed bus
        elif status.state is BusState.CONNECTED and self._period_us is not None:
            network = self._bus.network
            if network is not self._network:
                network.sync.start(self._period_us / US)
                self._network = network
