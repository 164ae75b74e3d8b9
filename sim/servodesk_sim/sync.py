"""SYNC producer and consumer bookkeeping (MDi-S1-C manual §2.6, Nanotec article SYNC, CiA 301
§7.2.5).

1005h holds the SYNC COB-ID (bits 0–10) and, in bit 30, whether this node produces SYNC;
1006h is the communication cycle period in µs; 1019h > 1 adds a 1-byte counter to the frame.
Only one producer may be active on a bus; that is the integrator's business, not the drive's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from servodesk_protocol.cob_id import CAN_ID_MASK, EXTENDED_BIT
from servodesk_protocol.cob_id import SYNC as DEFAULT_COB_ID
from servodesk_protocol.sdo_abort import DEVICE_STATE, INVALID_VALUE, VALUE_TOO_LOW
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.frames import Frame
from servodesk_sim.od_store import ObjectStore, Value

SYNC_COB_ID = 0x1005  # COB-ID SYNC message
CYCLE_PERIOD = 0x1006  # Communication cycle period (µs)
COUNTER_OVERFLOW = 0x1019  # Synchronous counter overflow value

PRODUCER_BIT = 1 << 30
ID_BITS = 0x1FFFFFFF
COUNTER_MAX = 240  # CiA 301 §7.5.2.22: 2–240 valid, 1 and 241–255 reserved
# A consumer declares SYNC lost after 1.5 periods without one (same margin as CANopenNode).
_EPSILON = 1e-9  # s: float clocks must not make a deadline miss by rounding


@dataclass(frozen=True)
class SyncRules:
    min_period_us: int  # MDi 500 (MDi-S1-C manual §2.6 note), others 0 (no limit beyond 1)
    require_period_before_enable: bool  # MDi: enabling 1005h bit 30 while 1006h = 0 is refused


def _as_int(value: Value) -> int:
    if not isinstance(value, int):
        raise SdoAbort(INVALID_VALUE, "SYNC parameters are integers")
    return value


def sync_counter(frame: Frame) -> int | None:
    """The counter a SYNC frame carries, or None for the plain 0-byte SYNC."""
    return frame.data[0] if frame.data else None


class SyncProducer:
    """Produces SYNC when 1005h bit 30 is set, every 1006h µs on absolute deadlines."""

    def __init__(self, store: ObjectStore, rules: SyncRules, *, lead: float = 0.0) -> None:
        """`lead`: a SYNC due within this many seconds after `now` is sent at this poll. A caller
        polling on a jittery periodic clock passes half its period, so SYNC lands on the poll
        nearest its deadline instead of flapping between two polls."""
        self._store = store
        self._rules = rules
        self._lead = lead
        self._next: float | None = None  # deadline of the next SYNC; None: not scheduled
        self._counter = 0
        if store.has(SYNC_COB_ID):
            store.add_validator(SYNC_COB_ID, self._check_cob_id)
            store.add_write_hook(SYNC_COB_ID, self._restart)
        if store.has(CYCLE_PERIOD):
            store.add_validator(CYCLE_PERIOD, self._check_period)
            store.add_write_hook(CYCLE_PERIOD, self._restart)
        if store.has(COUNTER_OVERFLOW):
            store.add_validator(COUNTER_OVERFLOW, self._check_overflow)
            store.add_write_hook(COUNTER_OVERFLOW, self._restart)

    def _get(self, index: int, default: int) -> int:
        return self._store.get(index) if self._store.has(index) else default

    def _check_cob_id(self, _sub: int, value: Value) -> None:
        cob = _as_int(value)
        if cob & EXTENDED_BIT or (cob & ID_BITS) > CAN_ID_MASK:
            raise SdoAbort(INVALID_VALUE, "29-bit SYNC identifiers are not supported")
        if not cob & PRODUCER_BIT:
            return
        if self._rules.require_period_before_enable and self._get(CYCLE_PERIOD, 0) == 0:
            # MDi-S1-C manual §2.6 step 3: 1006h "不可为0，否则下一步无法执行" — the manual names no
            # code; 08000022 says "not in the present device state", which is what it is.
            raise SdoAbort(DEVICE_STATE, "set 1006h before enabling the SYNC producer")
        current = self._get(SYNC_COB_ID, DEFAULT_COB_ID)
        if current & PRODUCER_BIT and (cob ^ current) & CAN_ID_MASK:
            # CiA 301 §7.5.2.5: the identifier must not change while this node produces SYNC.
            raise SdoAbort(INVALID_VALUE, "stop the SYNC producer before changing its CAN id")

    def _check_period(self, _sub: int, value: Value) -> None:
        period = _as_int(value)
        if 0 < period < self._rules.min_period_us:
            # MDi-S1-C manual §2.6 note: no SYNC producer below 500 µs.
            raise SdoAbort(VALUE_TOO_LOW, f"SYNC period below {self._rules.min_period_us} µs")

    def _check_overflow(self, _sub: int, value: Value) -> None:
        overflow = _as_int(value)
        if overflow == 1 or overflow > COUNTER_MAX:
            raise SdoAbort(INVALID_VALUE, f"counter overflow value {overflow} is reserved")
        if self._get(CYCLE_PERIOD, 0) != 0:
            # CiA 301 §7.5.2.22: 1019h may change only while 1006h is 0.
            raise SdoAbort(DEVICE_STATE, "set 1006h to 0 before changing 1019h")

    def _restart(self, _sub: int, _value: Value) -> None:
        self.reset()

    def cob_id(self) -> int:
        """CAN id of the SYNC the drive consumes (and produces): 1005h bits 0–10."""
        return self._get(SYNC_COB_ID, DEFAULT_COB_ID) & CAN_ID_MASK

    def producing(self) -> bool:
        return bool(self._get(SYNC_COB_ID, DEFAULT_COB_ID) & PRODUCER_BIT)

    def poll(self, now: float) -> Frame | None:
        """The SYNC frame due at `now`, if any. The first one comes one period after start."""
        period_us = self._get(CYCLE_PERIOD, 0)
        if not self.producing() or period_us == 0:
            self._next = None
            return None
        period = period_us * 1e-6
        if self._next is None:
            self._next = now + period
            return None
        due = now + self._lead + _EPSILON
        if due < self._next:
            return None
        # Absolute deadlines: no drift. After a stall the missed SYNCs are skipped, not burst.
        behind = math.floor((due - self._next) / period)
        self._next += (behind + 1) * period
        overflow = self._get(COUNTER_OVERFLOW, 0)
        if overflow < 2:
            return Frame(self.cob_id())
        self._counter = self._counter % overflow + 1  # 1, 2, …, overflow, 1, …
        return Frame(self.cob_id(), bytes([self._counter]))

    def reset(self) -> None:
        """Forget the schedule and the counter (reset communication, parameter change)."""
        self._next = None
        self._counter = 0
