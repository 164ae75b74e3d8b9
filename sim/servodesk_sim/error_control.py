"""NMT error control of a simulated drive: heartbeat producer and consumer, node/life guarding.

CiA 301 §7.2.8.3.2; MDi-S1-C manual §2.3.2; Nanotec article "心跳和节点保护". Pure classes with
explicit time (seconds); the drive feeds them 1016h/1017h/100Ch/100Dh values and raises the
faults they report.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from servodesk_protocol import cob_id
from servodesk_protocol.nmt import NmtState, make_heartbeat, parse_consumer_entry
from servodesk_protocol.sdo_abort import PARAMETER_INCOMPATIBLE as PARAM_INCOMPATIBLE
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.frames import Frame

US_PER_MS = 1000


def _elapsed_us(now: float, since: float) -> int:
    """Whole microseconds between two clock readings: CANopen times are whole ms, and rounding
    keeps 0.3 - 0.2 from counting as less than 100 ms."""
    return round((now - since) * 1_000_000)


def _active(node: int, time_ms: int) -> bool:
    return node != 0 and time_ms != 0  # node 0 or time 0: entry not used (CiA 301)


class HeartbeatProducer:
    """Sends the NMT state on 700h+id every 1017h ms (MDi-S1-C manual §2.3.2, table 2.12)."""

    def __init__(self) -> None:
        self._last: float | None = None  # time the current period started

    def restart(self, now: float) -> None:
        """Start the period again at `now` (after boot-up or a 1017h write)."""
        self._last = now

    def poll(self, now: float, period_ms: int, state: NmtState, node_id: int) -> Frame | None:
        if period_ms <= 0 or state is NmtState.INITIALISING:
            self._last = None  # disabled: when enabled again the period starts afresh
            return None
        if self._last is None:
            self._last = now
            return None
        elapsed = _elapsed_us(now, self._last)
        if elapsed < period_ms * US_PER_MS:
            return None
        # Keep the beat on its grid; after a long stall start a new grid rather than bursting.
        on_grid = elapsed < 2 * period_ms * US_PER_MS
        self._last = self._last + period_ms / 1000 if on_grid else now
        return Frame(cob_id.HEARTBEAT + node_id, make_heartbeat(state))


@dataclass
class _Watch:
    time_ms: int
    last: float | None = None  # first heartbeat starts monitoring (MDi-S1-C manual §2.3.2)
    lost: bool = False


class HeartbeatConsumer:
    """Watches other nodes' heartbeats per 1016h and reports each loss once."""

    def __init__(self) -> None:
        self._watches: dict[int, _Watch] = {}

    @staticmethod
    def validate(entries: Sequence[int]) -> None:
        """Refuse two active 1016h entries for the same node with 06040043.

        The MDi-S1-C manual 1016h: "不可以对同一个节点设置两个消费者时间" (CiA 301 1016h likewise).
        """
        seen: set[int] = set()
        for raw in entries:
            node, time_ms = parse_consumer_entry(raw)
            if not _active(node, time_ms):
                continue
            if node in seen:
                raise SdoAbort(PARAM_INCOMPATIBLE, f"two consumer times for node {node}")
            seen.add(node)

    def configure(self, entries: Sequence[int]) -> None:
        """Take the raw 1016h sub-values; an unchanged entry keeps its monitoring state."""
        watches: dict[int, _Watch] = {}
        for raw in entries:
            node, time_ms = parse_consumer_entry(raw)
            if not _active(node, time_ms) or node in watches:
                continue
            old = self._watches.get(node)
            watches[node] = old if old is not None and old.time_ms == time_ms else _Watch(time_ms)
        self._watches = watches

    def on_heartbeat(self, node_id: int, now: float) -> None:
        watch = self._watches.get(node_id)
        if watch is not None:
            watch.last = now
            watch.lost = False  # back again: a later silence is a new loss

    def poll(self, now: float) -> list[int]:
        """Node ids whose heartbeat just stayed away longer than their consumer time."""
        lost: list[int] = []
        for node, watch in self._watches.items():
            if watch.last is None or watch.lost:
                continue
            if _elapsed_us(now, watch.last) > watch.time_ms * US_PER_MS:
                watch.lost = True
                lost.append(node)
        return lost


class NodeGuarding:
    """Answers guarding RTRs and watches the master's life time (MDi-S1-C manual §2.3.2 1))."""

    def __init__(self) -> None:
        self._toggle = False
        self._last_rtr: float | None = None
        self._lost = False

    def on_rtr(self, state: NmtState, node_id: int, now: float) -> Frame:
        """Answer 700h+id: bit 7 toggles on every answer, starting at 0; bits 6–0 the state."""
        answer = Frame(cob_id.HEARTBEAT + node_id, make_heartbeat(state, toggle=self._toggle))
        self._toggle = not self._toggle
        self._last_rtr = now
        self._lost = False
        return answer

    def poll(
        self, now: float, guard_time_ms: int, life_factor: int, heartbeat_active: bool
    ) -> bool:
        """True once when the master's RTRs stayed away for 100Ch × 100Dh ms.

        Life guarding runs once 100Ch and 100Dh are non-zero and the first RTR arrived; never
        together with a heartbeat (MDi-S1-C manual §2.3.2 note 1), so 1017h ≠ 0 switches it off.
        """
        if heartbeat_active or guard_time_ms <= 0 or life_factor <= 0:
            return False
        if self._last_rtr is None or self._lost:
            return False
        if _elapsed_us(now, self._last_rtr) > guard_time_ms * life_factor * US_PER_MS:
            self._lost = True
            return True
        return False

    def reset(self) -> None:
        """Reset communication: toggle back to 0, life guarding inactive until the next RTR."""
        self._toggle = False
        self._last_rtr = None
        self._lost = False
