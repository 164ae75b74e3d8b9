"""An IP stream's worker-thread side (ip.py streams it): the plan, the SYNC clock, the
set-point writes pipelined between the SYNCs, and what is measured on the way."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import canopen

from servodesk.bus.cyclic import precise_wakeups
from servodesk.motion import drive_io as io
from servodesk.motion.ip_timing import SyncClock
from servodesk.pdo.commands import IP_DATA, RpdoRoute
from servodesk_protocol.cia402 import CONTROLWORD, STATUSWORD, SW_FAULT, SW_MODE_BIT12
from servodesk_protocol.sdo import expedited_download

# SDO initiate download, expedited, 4 bytes, 60C1h:01 Interpolation data record (CiA 301)
EXPEDITED_4 = expedited_download(0x60C1, 1, 4)


@dataclass
class Stream:
    """What the worker-thread chunks share: the plan, the clock, the measurements."""

    points: list[int]
    period: float
    clock: SyncClock = field(default_factory=lambda: SyncClock(0.0, 0.0))  # set by begin()
    sent: int = 0
    syncs: list[float] = field(default_factory=list)
    lags: list[int] = field(default_factory=list)  # |planned − actual| in user units
    cancelled: bool = False
    stalled: bool = False  # more than 3 periods without SYNC: the drive has dropped out
    stall_gap: float = 0.0  # the interval that stalled it (no SYNC was sent at its end)
    unconfirmed: int = 0  # set-point writes sent whose confirmation was not read yet
    active: bool = False  # the drive shows interpolation active (statusword bit 12)
    not_started: bool = False  # … and did not within the transition timeout
    started_at: float = 0.0
    _timeout: float = 0.0
    # the RPDO 60C1h:01 goes in (None: expedited SDO), the values of its other objects, and
    # how many SYNCs ahead a set-point is sent (2 where the drive takes the RPDO at a SYNC)
    rpdo: RpdoRoute | None = None
    rpdo_values: dict[int, int] = field(default_factory=dict)
    lead: int = 1

    def begin(self, remote: canopen.RemoteNode, controlword: int, timeout: float) -> None:
        """Switch interpolation on and start the SYNC clock in one step on the worker: the drive
        counts SYNC lost from here, so the first SYNC must follow within a period, whatever
        the event loop or the host is doing meanwhile (bit 12 is checked while streaming)."""
        precise_wakeups()  # this worker thread now keeps the stream's SYNC deadlines
        io.write_controlword(remote, controlword)
        io.write(remote, io.IP_DATA, 1, self.points[0], io.I32)
        self.rpdo_values[CONTROLWORD] = controlword
        for k in range(1, self.lead):  # taken at a SYNC: the next point is sent before SYNC 0
            if k < len(self.points):
                self._send_point(remote, self.points[k])
        self.started_at = time.perf_counter()
        self._timeout = timeout
        self.clock = SyncClock(self.started_at + self.period, self.period)

    def chunk(self, remote: canopen.RemoteNode, count: int, sample_every: int) -> None:
        """Send the next `count` SYNCs, each at its absolute deadline, and after each the
        set-point for the next one. Blocking; on the node's worker thread, the only user of
        its SDO client, so the set-point writes can be pipelined: sent without waiting, their
        confirmations collected before any other transfer (and at the chunk's end)."""
        network = remote.network
        end = min(self.sent + count, len(self.points))
        try:
            while self.sent < end and not self.cancelled:
                k = self.sent
                now = self.clock.wait(k)
                if self.syncs and now - self.syncs[-1] > 3 * self.period:
                    self.stalled = True  # the drives count SYNC lost after 3 periods
                    self.stall_gap = now - self.syncs[-1]
                    return
                network.sync.transmit()  # the drive takes point k, written after SYNC k - 1
                self.syncs.append(now)
                self.sent += 1
                if k + self.lead < len(self.points):
                    self._send_point(remote, self.points[k + self.lead])
                if k % sample_every == 0 and k > 0:
                    self._confirm(remote)
                    if not self.active and not self._check_active(remote, now):
                        return
                    actual = io.read(remote, io.POSITION_ACTUAL, signed=True)
                    if actual is not None:  # at SYNC k the axis should be at point k - 1
                        self.lags.append(abs(actual - self.points[k - 1]))
        finally:
            self._confirm(remote)

    def _check_active(self, remote: canopen.RemoteNode, now: float) -> bool:
        """Whether to go on: bit 12 seen, or still within the transition timeout."""
        word = io.read(remote, STATUSWORD, signed=False)
        self.active = word is not None and bool(word & SW_MODE_BIT12)
        faulted = word is not None and bool(word & SW_FAULT)
        if not self.active and (faulted or now - self.started_at > self._timeout):
            self.not_started = self.cancelled = True  # the drive's objects will say why
        return not self.not_started

    def _send_point(self, remote: canopen.RemoteNode, value: int) -> None:
        """60C1h:01 in the RPDO, else by an expedited SDO download, not waiting for the
        confirmation."""
        if self.rpdo is not None:
            self.rpdo_values[IP_DATA] = value
            self.send_rpdo(remote)
            return
        remote.sdo.send_request(EXPEDITED_4 + value.to_bytes(4, "little", signed=True))
        self.unconfirmed += 1

    def send_rpdo(self, remote: canopen.RemoteNode) -> None:
        data = self.rpdo.payload(self.rpdo_values) if self.rpdo is not None else None
        if self.rpdo is not None and data is not None:
            remote.network.send_message(self.rpdo.cob_id, data)

    def _confirm(self, remote: canopen.RemoteNode) -> None:
        """Collect the confirmations of the pipelined writes (an abort raises)."""
        while self.unconfirmed:
            self.unconfirmed -= 1
            remote.sdo.read_response()  # SdoAbortedError / SdoCommunicationError
