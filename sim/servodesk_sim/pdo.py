"""PDO engine: receive and transmit PDOs of one drive (MDi-S1-C manual §2.5, Kinco manual §5.4,
Nanotec article PDO).

Communication parameters live at 1400h+n (RPDO) / 1800h+n (TPDO), mappings at 1600h+n / 1A00h+n.
Values always go through the object store: TPDOs read with `read_bytes` (so whatever the drive
publishes with `store.set` is sent) and RPDOs write with `write_bytes` (so write hooks run, e.g.
the controlword drives the CiA 402 state machine).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from servodesk_data.model import PdoRemapRule
from servodesk_protocol.nmt import NmtState
from servodesk_protocol.pdo import (
    CAN_ID_MASK,
    COB_INVALID,
    COB_NO_RTR,
    EVENT_DRIVEN,
    EVENT_RTR,
    MAX_SYNC_START,
    RPDO_COMM,
    RPDO_MAP,
    SUB_COB_ID,
    SUB_EVENT_TIMER,
    SUB_INHIBIT,
    SUB_SYNC_START,
    SUB_TRANSMISSION,
    SYNC_CYCLIC_MAX,
    SYNC_RTR,
    TPDO_COMM,
    TPDO_MAP,
    Direction,
    MapEntry,
    default_can_id,
    frame_length,
    pack,
    restricted_can_id,
    unpack,
)
from servodesk_protocol.sdo_abort import (
    DEVICE_STATE,
    INVALID_VALUE,
    TYPE_MISMATCH,
    UNSUPPORTED_ACCESS,
)
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.frames import Frame
from servodesk_sim.od_store import ObjectStore, Value
from servodesk_sim.pdo_mapping import (
    check_cob_id,
    check_count,
    check_entry,
    check_transmission_type,
    read_fields,
    read_mapping,
)

# MDi-S1-C manual §5.2 1600h/1800h notes: these sub-indices change only while the PDO is invalid.
_WHILE_INVALID_SUBS = frozenset({SUB_TRANSMISSION, SUB_INHIBIT, SUB_EVENT_TIMER})
_EPSILON = 1e-9  # s: float clocks must not make a deadline miss by rounding


@dataclass(frozen=True)
class PdoRules:
    rpdo_count: int  # 4 (MDi, Kinco) or 8 (cia402)
    tpdo_count: int
    byte_granular: bool  # MDi: whole-byte mapping lengths only (MDi-S1-C manual §5.2 1600h note)
    remap_rule: PdoRemapRule
    rtr_transmission: bool  # cia402: TPDO types 252/253; MDi: COB-ID bit 30 is meaningless
    fixed_cob_ids: int  # PDOs 1..n whose CAN id is fixed to the node-id default
    # MDi-S1-C manual §2.5.3 4): a send for any reason restarts the event timer; Nanotec article
    # 180Nh:05:
    # the timer restarts only when it expires ("而不是基于另一个事件").
    event_timer_restarts_on_send: bool = True
    # Nanotec article 140Nh:01: a new CAN id takes effect only after a reset (communication); the
    # valid bit still acts at once so configuring in Pre-operational and starting works.
    cob_id_change_needs_reset: bool = False


def _as_int(value: Value) -> int:
    if not isinstance(value, int):
        raise SdoAbort(TYPE_MISMATCH, "PDO parameters are integers")
    return value


@dataclass
class _Channel:
    """One PDO and its run-time state."""

    direction: Direction
    number: int  # 1-based
    comm: int
    mapping: int
    can_id: int = 0  # the identifier in use (may lag 1xxxh:01, see cob_id_change_needs_reset)
    buffered: bytes | None = None  # RPDO data waiting for the next SYNC
    last_sent: bytes | None = None
    sync_count: int = 0
    sync_started: bool = False
    sampled: bytes | None = None  # type 252: data sampled at the last SYNC
    inhibit_until: float = float("-inf")
    event_deadline: float | None = None

    def clear_runtime(self) -> None:
        self.buffered = None
        self.last_sent = None
        self.sync_count = 0
        self.sync_started = False
        self.sampled = None
        self.inhibit_until = float("-inf")
        self.event_deadline = None


class PdoEngine:
    """Receive/transmit PDOs of one node over an ObjectStore; pure, time passed in."""

    def __init__(
        self, store: ObjectStore, rules: PdoRules, nmt_state: Callable[[], NmtState]
    ) -> None:
        self._store = store
        self._rules = rules
        self._nmt_state = nmt_state
        self.length_errors = 0  # RPDOs shorter than their mapping (CiA 301: EMCY 8210)
        self.write_errors = 0  # RPDO values the object dictionary refused
        self.last_write_error: SdoAbort | None = None
        self._was_operational = False
        self._rpdos = self._channels(Direction.RECEIVE, rules.rpdo_count, RPDO_COMM, RPDO_MAP)
        self._tpdos = self._channels(Direction.TRANSMIT, rules.tpdo_count, TPDO_COMM, TPDO_MAP)
        for channel in (*self._rpdos, *self._tpdos):
            self._install(channel)
        self.reset()

    def _channels(
        self, direction: Direction, count: int, comm: int, mapping: int
    ) -> list[_Channel]:
        return [
            _Channel(direction, n + 1, comm + n, mapping + n)
            for n in range(count)
            if self._store.has(comm + n) and self._store.has(mapping + n)
        ]

    def _install(self, channel: _Channel) -> None:
        store = self._store
        store.add_validator(channel.comm, lambda sub, value: self._check_comm(channel, sub, value))
        store.add_validator(
            channel.mapping, lambda sub, value: self._check_map(channel, sub, value)
        )
        store.add_write_hook(
            channel.comm, lambda sub, value: self._comm_written(channel, sub, value)
        )
        store.add_write_hook(channel.mapping, lambda _sub, _value: channel.clear_runtime())

    # ------------------------------------------------------------------ configuration checks

    def _check_comm(self, channel: _Channel, sub: int, value: Value) -> None:
        number = _as_int(value)
        self._check_change_allowed(channel, restricted=sub in _WHILE_INVALID_SUBS)
        if sub == SUB_COB_ID:
            self._check_cob_id(channel, number)
        elif sub == SUB_TRANSMISSION:
            check_transmission_type(number, channel.direction, rtr=self._rules.rtr_transmission)
        elif sub == SUB_SYNC_START and number > MAX_SYNC_START:
            raise SdoAbort(INVALID_VALUE, "SYNC start value above 240")  # CiA 301 §7.5.2.36

    def _check_map(self, channel: _Channel, sub: int, value: Value) -> None:
        raw = _as_int(value)
        self._check_change_allowed(channel, restricted=True)
        granular = self._rules.byte_granular
        if sub == 0:
            check_count(
                self._store, channel.mapping, raw, channel.direction, byte_granular=granular
            )
            return
        # CiA 301 mapping procedure (MDi-S1-C manual §2.5 steps 3–5): entries change only while
        # sub 0 is 0. Writing 0 clears an unused entry and needs no target.
        if self._store.get(channel.mapping, 0) != 0:
            raise SdoAbort(UNSUPPORTED_ACCESS, "set sub 0 to 0 before changing entries")
        if raw != 0:
            entry = MapEntry.from_raw(raw)
            check_entry(self._store, entry, channel.direction, byte_granular=granular)

    def _check_change_allowed(self, channel: _Channel, *, restricted: bool) -> None:
        rule = self._rules.remap_rule
        if rule is PdoRemapRule.OUTSIDE_OPERATIONAL:
            # Nanotec article SDO abort table, 08000022: no writes to these objects in Operational.
            if self._nmt_state() is NmtState.OPERATIONAL:
                raise SdoAbort(DEVICE_STATE, "PDO parameters change outside Operational only")
        elif rule is PdoRemapRule.WHILE_INVALID and restricted and not self._invalid(channel):
            # MDi-S1-C manual §5.2 says "only while the PDO is invalid" without a code; 06010000 is
            # what CiA 301 devices commonly answer (Copley, CCT PDO 23 accepts it).
            raise SdoAbort(UNSUPPORTED_ACCESS, "PDO must be invalid (COB-ID bit 31) to change")
        # WHILE_UNMAPPED asks nothing more: the sub-0 rule of _check_map and the COB-ID checks
        # are all the Kinco manual's §5.4.4/§5.4.5 sequences meet (the PDO stays valid).

    def _check_cob_id(self, channel: _Channel, value: int) -> None:
        fixed = channel.number <= self._rules.fixed_cob_ids
        base = default_can_id(channel.direction, channel.number)
        check_cob_id(
            value,
            self._cob_id(channel),
            fixed_id=base + self._store.node_id if fixed and base is not None else None,
        )

    def _comm_written(self, channel: _Channel, sub: int, value: Value) -> None:
        if sub == SUB_COB_ID and not self._rules.cob_id_change_needs_reset:
            channel.can_id = _as_int(value) & CAN_ID_MASK
        channel.clear_runtime()

    # ------------------------------------------------------------------ helpers

    def _cob_id(self, channel: _Channel) -> int:
        return self._store.get(channel.comm, SUB_COB_ID)

    def _invalid(self, channel: _Channel) -> bool:
        return bool(self._cob_id(channel) & COB_INVALID)

    def _param(self, channel: _Channel, sub: int) -> int:
        return self._store.get(channel.comm, sub) if self._store.has(channel.comm, sub) else 0

    def _usable(self, channel: _Channel) -> bool:
        """Valid (bit 31 clear) with an identifier the node may use."""
        return not self._invalid(channel) and not restricted_can_id(channel.can_id)

    def _operational(self) -> bool:
        return self._nmt_state() is NmtState.OPERATIONAL

    def _find(self, channels: list[_Channel], can_id: int) -> _Channel | None:
        for channel in channels:
            if channel.can_id == can_id and self._usable(channel):
                return channel
        return None

    def _apply(self, channel: _Channel, data: bytes) -> None:
        for entry, value in unpack(data, read_mapping(self._store, channel.mapping)):
            try:
                self._store.write_bytes(entry.index, entry.subindex, value)
            except SdoAbort as abort:
                # A PDO has no answer path: the value is dropped, the drive can inspect why.
                self.write_errors += 1
                self.last_write_error = abort

    def _send(self, channel: _Channel, data: bytes, now: float) -> Frame:
        channel.last_sent = data
        channel.inhibit_until = now + self._param(channel, SUB_INHIBIT) * 1e-4
        timer = self._param(channel, SUB_EVENT_TIMER) * 1e-3
        if timer > 0 and (
            self._rules.event_timer_restarts_on_send or channel.event_deadline is None
        ):
            channel.event_deadline = now + timer
        return Frame(channel.can_id, data)

    def _tpdo_data(self, channel: _Channel) -> bytes | None:
        """Current TPDO payload, or None when nothing is mapped (nothing to publish)."""
        entries = read_mapping(self._store, channel.mapping)
        return pack(read_fields(self._store, entries)) if entries else None

    # ------------------------------------------------------------------ bus side

    def on_frame(self, frame: Frame, now: float) -> list[Frame] | None:
        """Handle an RPDO or a TPDO remote request; None when the frame is not one of ours."""
        if frame.rtr:
            tpdo = self._find(self._tpdos, frame.can_id)
            return None if tpdo is None else self._answer_rtr(tpdo, now)
        rpdo = self._find(self._rpdos, frame.can_id)
        if rpdo is None:
            return None
        if not self._operational():
            return []
        entries = read_mapping(self._store, rpdo.mapping)
        needed = frame_length(entries)
        if len(frame.data) < needed:
            # CiA 301 §7.2.2.2: too short → not processed (EMCY 8210 is the drive's call).
            self.length_errors += 1
            return []
        data = frame.data[:needed]  # longer than mapped: the extra bytes are ignored
        if self._param(rpdo, SUB_TRANSMISSION) <= SYNC_CYCLIC_MAX:
            rpdo.buffered = data  # MDi-S1-C manual §2.5.3 2): synchronous data applies at next SYNC
        else:
            self._apply(rpdo, data)
        return []

    def _answer_rtr(self, channel: _Channel, now: float) -> list[Frame]:
        if not (self._operational() and self._rules.rtr_transmission):
            return []  # MDi: RTR-triggered PDOs are not supported (MDi-S1-C manual §5.2 1800h:01)
        if self._cob_id(channel) & COB_NO_RTR:
            return []
        ttype = self._param(channel, SUB_TRANSMISSION)
        if ttype == SYNC_RTR and channel.sampled is not None:
            return [self._send(channel, channel.sampled, now)]
        if ttype == EVENT_RTR:
            data = self._tpdo_data(channel)
            return [] if data is None else [self._send(channel, data, now)]
        return []

    def on_sync(self, counter: int | None, now: float) -> list[Frame]:
        """SYNC received: apply buffered RPDOs, then send the synchronous TPDOs that are due."""
        if not self._operational():
            return []
        for rpdo in self._rpdos:
            if rpdo.buffered is not None and self._usable(rpdo):
                self._apply(rpdo, rpdo.buffered)
            rpdo.buffered = None
        out: list[Frame] = []
        for tpdo in self._tpdos:
            if not self._usable(tpdo):
                continue
            ttype = self._param(tpdo, SUB_TRANSMISSION)
            if ttype == 0:
                # MDi-S1-C manual §2.5.3 2): acyclic, sent at a SYNC only if the data changed
                data = self._tpdo_data(tpdo)
                if data is not None and data != tpdo.last_sent:
                    out.append(self._send(tpdo, data, now))
            elif ttype <= SYNC_CYCLIC_MAX:
                if self._cyclic_due(tpdo, ttype, counter):
                    data = self._tpdo_data(tpdo)
                    if data is not None:
                        out.append(self._send(tpdo, data, now))
            elif ttype == SYNC_RTR:
                tpdo.sampled = self._tpdo_data(tpdo)
        return out

    def _cyclic_due(self, channel: _Channel, every: int, counter: int | None) -> bool:
        if not channel.sync_started:
            start = self._param(channel, SUB_SYNC_START)
            if counter is not None and start > 0:
                # CiA 301 §7.5.2.36: the SYNC whose counter equals the start value counts as the
                # first one; before it the PDO stays silent (Nanotec article 180Nh:06).
                if counter != start:
                    return False
                channel.sync_started = True
                channel.sync_count = 0
                return True
            channel.sync_started = True
        channel.sync_count += 1
        if channel.sync_count >= every:
            channel.sync_count = 0
            return True
        return False

    def poll(self, now: float) -> list[Frame]:
        """Event-driven TPDOs (254/255): on change (after the inhibit time) and on the timer."""
        if not self._operational():
            return []
        out: list[Frame] = []
        for tpdo in self._tpdos:
            if not self._usable(tpdo) or self._param(tpdo, SUB_TRANSMISSION) not in EVENT_DRIVEN:
                continue
            data = self._tpdo_data(tpdo)
            if data is None:
                continue
            timer = self._param(tpdo, SUB_EVENT_TIMER) * 1e-3
            if timer > 0 and tpdo.event_deadline is None:
                tpdo.event_deadline = now + timer
            expired = tpdo.event_deadline is not None and now + _EPSILON >= tpdo.event_deadline
            if timer <= 0:
                tpdo.event_deadline = None
                expired = False
            if not (expired or data != tpdo.last_sent):
                continue
            if now + _EPSILON < tpdo.inhibit_until:
                # MDi-S1-C manual §2.5.3 3): the change goes out when the inhibit time ends
                continue
            if expired and tpdo.event_deadline is not None:
                # Next period counts from the expiry, not from this poll: no drift.
                following = tpdo.event_deadline + timer
                tpdo.event_deadline = following if following > now else now + timer
            out.append(self._send(tpdo, data, now))
        return out

    def on_nmt_state(self, state: NmtState, now: float) -> list[Frame]:
        """NMT state changed: entering Operational sends event-driven TPDOs once (Nanotec
        article)."""
        entering = state is NmtState.OPERATIONAL and not self._was_operational
        leaving = state is not NmtState.OPERATIONAL and self._was_operational
        self._was_operational = state is NmtState.OPERATIONAL
        if leaving or entering:
            for channel in (*self._rpdos, *self._tpdos):
                channel.clear_runtime()  # leaving: buffered RPDO data is dropped
        if not entering:
            return []
        out: list[Frame] = []
        for tpdo in self._tpdos:
            if self._usable(tpdo) and self._param(tpdo, SUB_TRANSMISSION) in EVENT_DRIVEN:
                data = self._tpdo_data(tpdo)
                if data is not None:
                    out.append(self._send(tpdo, data, now))
        return out

    def reset(self) -> None:
        """After reset communication: take the (restored) identifiers, forget all run-time state."""
        self._was_operational = False  # a reset always ends in Pre-operational
        for channel in (*self._rpdos, *self._tpdos):
            channel.can_id = self._cob_id(channel) & CAN_ID_MASK
            channel.clear_runtime()
