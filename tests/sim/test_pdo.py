"""PDO engine: exact PDO frames for the manual examples, remap rules, timing and RTR (pdo.py)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import pytest

from servodesk_data.model import PdoRemapRule
from servodesk_protocol.nmt import NmtState
from servodesk_protocol.sdo_abort import (
    DEVICE_STATE,
    INVALID_VALUE,
    PDO_LENGTH_EXCEEDED,
    UNSUPPORTED_ACCESS,
    VALUE_TOO_HIGH,
)
from servodesk_sim.frames import Frame, frame
from servodesk_sim.od_store import ObjectStore, Value
from servodesk_sim.pdo import PdoEngine, PdoRules
from tests.sim.pdo_od import abort_of, make_store, write

INVALID = 0x80000000

MDI = PdoRules(
    rpdo_count=4,
    tpdo_count=4,
    byte_granular=True,
    remap_rule=PdoRemapRule.WHILE_INVALID,
    rtr_transmission=False,
    fixed_cob_ids=4,
)
# Kinco profile.toml: byte-granular mapping (§5.4.3), free CAN ids (§5.1 note 1)
KINCO = replace(MDI, remap_rule=PdoRemapRule.WHILE_UNMAPPED, fixed_cob_ids=0)
CIA402 = PdoRules(
    rpdo_count=8,
    tpdo_count=8,
    byte_granular=False,
    remap_rule=PdoRemapRule.OUTSIDE_OPERATIONAL,
    rtr_transmission=True,
    fixed_cob_ids=4,
    event_timer_restarts_on_send=False,
    cob_id_change_needs_reset=True,
)


@dataclass
class Rig:
    store: ObjectStore
    rules: PdoRules
    state: NmtState = NmtState.PRE_OPERATIONAL
    engine: PdoEngine = field(init=False)

    def __post_init__(self) -> None:
        self.engine = PdoEngine(self.store, self.rules, lambda: self.state)

    def nmt(self, state: NmtState, now: float = 0.0) -> list[Frame]:
        self.state = state
        return self.engine.on_nmt_state(state, now)

    def start(self, now: float = 0.0) -> list[Frame]:
        return self.nmt(NmtState.OPERATIONAL, now)


def make_rig(rules: PdoRules) -> Rig:
    return Rig(make_store(max(rules.rpdo_count, rules.tpdo_count)), rules)


def configure(
    store: ObjectStore,
    comm: int,
    entries: list[int],
    *,
    ttype: int,
    cob_id: int | None = None,
    inhibit: int = 0,
    timer: int = 0,
) -> None:
    """MDi-S1-C manual §2.5: invalidate, count 0, entries, count, parameters, validate."""
    mapping = comm + 0x200
    valid = (store.get(comm, 1) & ~INVALID) if cob_id is None else cob_id
    write(store, comm, 1, valid | INVALID)
    write(store, mapping, 0, 0)
    for sub, raw in enumerate(entries, start=1):
        write(store, mapping, sub, raw)
    write(store, mapping, 0, len(entries))
    write(store, comm, 2, ttype)
    if store.has(comm, 3):
        write(store, comm, 3, inhibit)
    write(store, comm, 5, timer)
    write(store, comm, 1, valid)


# ----------------------------------------------------------------------------- manual examples


def test_mdi_manual_mapping_procedure_then_operational() -> None:
    rig = make_rig(MDI)
    rig.store.set(0x6041, 0, 0x0237)
    rig.store.set(0x6064, 0, -2)
    configure(rig.store, 0x1800, [0x60410010, 0x60640020], ttype=255)
    assert rig.store.get(0x1800, 1) == 0x40000181  # bit 30 kept as written by the factory
    assert rig.start() == [frame(0x181, "37 02 FE FF FF FF")]
    assert rig.engine.poll(0.001) == []  # nothing changed
    rig.store.set(0x6064, 0, 1000)
    assert rig.engine.poll(0.002) == [frame(0x181, "37 02 E8 03 00 00")]


def test_kinco_tpdo1_example_count_3_exceeds_64_bits() -> None:
    """Kinco manual §5.4.4, as printed: the PDO stays valid (181h), type, inhibit time and
    entries go in, then the count. 6041h + 6063h + 60FDh = 10 bytes cannot be one PDO (the
    manual's own §5.4.3 limit of 8 bytes), so only the count 3 is refused."""
    rig = make_rig(KINCO)
    store = rig.store
    assert abort_of(store, 0x1800, 1, 0x181) is None
    assert abort_of(store, 0x1800, 2, 0xFE) is None
    assert abort_of(store, 0x1800, 3, 100) is None  # 100 × 100 µs = 10 ms
    for sub, raw in enumerate([0x60410010, 0x60630020, 0x60FD0020], start=1):
        assert abort_of(store, 0x1A00, sub, raw) is None
    assert abort_of(store, 0x1A00, 0, 3) == PDO_LENGTH_EXCEEDED
    assert store.get(0x1A00, 0) == 0  # the refused count was not stored
    assert abort_of(store, 0x1A00, 0, 2) is None
    assert abort_of(store, 0x1A00, 1, 0x60410010) == UNSUPPORTED_ACCESS  # count is not 0
    store.set(0x6041, 0, 0x4037)  # Kinco manual §5.2 statusword example
    store.set(0x6063, 0, 0x12345678)
    assert rig.start() == [frame(0x181, "37 40 78 56 34 12")]
    store.set(0x6041, 0, 0x4031)
    assert rig.engine.poll(0.005) == []  # inhibit time 10 ms
    assert rig.engine.poll(0.010) == [frame(0x181, "31 40 78 56 34 12")]


@pytest.mark.parametrize(
    ("rules", "code"),
    [(KINCO, None), (MDI, UNSUPPORTED_ACCESS)],  # MDi: only while the PDO is invalid
)
def test_type_of_a_valid_pdo_per_rule(rules: PdoRules, code: int | None) -> None:
    """The Kinco example's second write: type FEh while TPDO1 is valid."""
    rig = make_rig(rules)
    assert abort_of(rig.store, 0x1800, 2, 0xFE) == code
    assert abort_of(rig.store, 0x1800, 1, 0x80000181) is None
    assert abort_of(rig.store, 0x1800, 2, 0xFE) is None


def test_mdi_manual_sync_example() -> None:
    """MDi-S1-C manual §2.6.2: RPDO1 type 0, RPDO2 type 5, TPDO1 type 0, TPDO2 type 20."""
    rig = make_rig(MDI)
    store, engine = rig.store, rig.engine
    configure(store, 0x1400, [0x60400010], ttype=0)
    configure(store, 0x1401, [0x607A0020], ttype=5, cob_id=0x301)
    configure(store, 0x1800, [0x60410010], ttype=0)
    configure(store, 0x1801, [0x60640020], ttype=20, cob_id=0x40000281)
    store.set(0x6041, 0, 0x0237)
    store.set(0x6064, 0, 0x100)
    assert rig.start() == []  # no event-driven TPDO
    assert engine.on_frame(frame(0x201, "0F 00"), 0.0) == []
    assert engine.on_frame(frame(0x301, "E8 03 00 00"), 0.0) == []
    assert (store.get(0x6040), store.get(0x607A)) == (0, 0)  # buffered until SYNC

    sent: dict[int, list[Frame]] = {}
    for n in range(1, 41):
        if n == 10:
            store.set(0x6041, 0, 0x0637)
        frames = engine.on_sync(None, n * 0.001)
        if n == 1:
            assert (store.get(0x6040), store.get(0x607A)) == (0x0F, 1000)
        if frames:
            sent[n] = frames
    assert sent == {
        1: [frame(0x181, "37 02")],  # first SYNC after start: TPDO1 never sent yet
        10: [frame(0x181, "37 06")],  # only when its data changed
        20: [frame(0x281, "00 01 00 00")],  # every 20th SYNC, changed or not
        40: [frame(0x281, "00 01 00 00")],
    }


# ----------------------------------------------------------------------------- remap rules


@pytest.mark.parametrize(
    ("index", "sub", "value"),
    [
        (0x1A00, 0, 0),  # mapping count
        (0x1600, 0, 0),
        (0x1800, 2, 1),  # transmission type
        (0x1800, 3, 10),  # inhibit time
        (0x1800, 5, 100),  # event timer
        (0x1400, 2, 0),
    ],
)
def test_while_invalid_refuses_changes_of_a_valid_pdo(index: int, sub: int, value: int) -> None:
    rig = make_rig(MDI)
    before = rig.store.get(index, sub)
    assert abort_of(rig.store, index, sub, value) == UNSUPPORTED_ACCESS
    assert rig.store.get(index, sub) == before
    comm = 0x1400 if index in (0x1400, 0x1600) else 0x1800
    write(rig.store, comm, 1, rig.store.get(comm, 1) | INVALID)
    assert abort_of(rig.store, index, sub, value) is None


def test_entries_change_only_while_count_is_zero() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1801, [0x60410010], ttype=255, cob_id=0x80000281)  # stays invalid
    assert abort_of(rig.store, 0x1A01, 1, 0x60640020) == UNSUPPORTED_ACCESS
    assert abort_of(rig.store, 0x1A01, 0, 0) is None
    assert abort_of(rig.store, 0x1A01, 1, 0x60640020) is None


@pytest.mark.parametrize(
    ("index", "sub", "value"),
    [(0x1800, 2, 1), (0x1800, 1, 0x80000181), (0x1A00, 0, 0), (0x1407, 2, 1), (0x1A07, 0, 0)],
)
def test_outside_operational_refuses_any_write_in_operational(
    index: int, sub: int, value: int
) -> None:
    rig = make_rig(CIA402)
    rig.start()
    assert abort_of(rig.store, index, sub, value) == DEVICE_STATE
    rig.nmt(NmtState.PRE_OPERATIONAL)
    assert abort_of(rig.store, index, sub, value) is None  # even though PDO 1 is valid


@pytest.mark.parametrize(
    ("rules", "index", "sub", "value", "code"),
    [
        (MDI, 0x1800, 1, 0x80000185, INVALID_VALUE),  # fixed CAN id
        (MDI, 0x1801, 2, 252, INVALID_VALUE),  # no RTR transmission on MDi (PDO 2 invalid)
        (MDI, 0x1A01, 1, 0x21000001, 0x06040041),  # bit mapping on MDi
        (CIA402, 0x1A01, 1, 0x21000001, None),
        (CIA402, 0x1800, 2, 252, None),
        (CIA402, 0x1400, 2, 252, INVALID_VALUE),  # RTR types are TPDO-only
        (CIA402, 0x1800, 2, 241, INVALID_VALUE),
        (CIA402, 0x1804, 1, 0x800001A5, None),  # PDO 5: free CAN id
        (CIA402, 0x1803, 1, 0x800001A5, INVALID_VALUE),  # PDO 4: fixed
        (CIA402, 0x1800, 6, 241, INVALID_VALUE),  # SYNC start value 0–240
    ],
)
def test_parameter_checks_per_profile(
    rules: PdoRules, index: int, sub: int, value: int, code: int | None
) -> None:
    rig = make_rig(rules)
    assert abort_of(rig.store, index, sub, value) == code


# ----------------------------------------------------------------------------- RPDO


def test_rpdo_writes_run_the_write_hooks() -> None:
    rig = make_rig(MDI)
    seen: list[tuple[int, Value]] = []
    rig.store.add_write_hook(0x6040, lambda sub, value: seen.append((sub, value)))
    configure(rig.store, 0x1400, [0x60400010, 0x60600008], ttype=255)
    rig.start()
    assert rig.engine.on_frame(frame(0x201, "0F 00 01"), 0.0) == []
    assert seen == [(0, 0x000F)]
    assert rig.store.get(0x6060) == 1


def test_short_rpdo_is_ignored_long_one_is_cut() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1400, [0x60400010, 0x607A0020], ttype=255)
    rig.start()
    assert rig.engine.on_frame(frame(0x201, "0F 00 E8 03 00"), 0.0) == []
    assert (rig.store.get(0x6040), rig.engine.length_errors) == (0, 1)
    assert rig.engine.on_frame(frame(0x201, "0F 00 E8 03 00 00 FF FF"), 0.0) == []
    assert (rig.store.get(0x6040), rig.store.get(0x607A)) == (0x0F, 1000)


def test_refused_rpdo_value_is_counted_others_applied() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1400, [0x60710010, 0x60400010], ttype=255)
    rig.start()
    rig.engine.on_frame(frame(0x201, "D0 07 06 00"), 0.0)  # 2000 > 1000 (0.1 % units)
    assert rig.store.get(0x6071) == 0
    assert rig.store.get(0x6040) == 6
    assert rig.engine.write_errors == 1
    error = rig.engine.last_write_error
    assert error is not None
    assert error.code == VALUE_TOO_HIGH


def test_frames_that_are_not_our_pdos() -> None:
    rig = make_rig(MDI)
    rig.start()
    assert rig.engine.on_frame(frame(0x202, "01"), 0.0) is None  # another node's RPDO1
    assert rig.engine.on_frame(frame(0x301, "01 00"), 0.0) is None  # RPDO2 invalid (factory)
    assert rig.engine.on_frame(Frame(0x185, rtr=True, dlc=2), 0.0) is None


def test_pdos_only_in_operational() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1400, [0x60400010], ttype=255)
    configure(rig.store, 0x1800, [0x60410010], ttype=1)
    assert rig.engine.on_frame(frame(0x201, "0F 00"), 0.0) == []
    assert rig.store.get(0x6040) == 0
    assert rig.engine.on_sync(None, 0.0) == []
    rig.nmt(NmtState.STOPPED)
    assert rig.engine.on_frame(frame(0x201, "0F 00"), 0.0) == []
    assert rig.store.get(0x6040) == 0


def test_leaving_operational_drops_buffered_rpdo_data() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1400, [0x60400010], ttype=0)
    rig.start()
    rig.engine.on_frame(frame(0x201, "0F 00"), 0.0)
    rig.nmt(NmtState.PRE_OPERATIONAL)
    rig.start()
    rig.engine.on_sync(None, 0.01)
    assert rig.store.get(0x6040) == 0


# ----------------------------------------------------------------------------- TPDO timing


def test_entering_operational_sends_event_driven_tpdos_once() -> None:
    rig = make_rig(MDI)
    rig.store.set(0x6041, 0, 0x0250)
    configure(rig.store, 0x1800, [0x60410010], ttype=255)
    configure(rig.store, 0x1801, [0x60600008], ttype=254, cob_id=0x281)
    configure(rig.store, 0x1802, [0x60640020], ttype=1, cob_id=0x381)  # synchronous
    configure(rig.store, 0x1803, [0x60410010], ttype=255, cob_id=0x80000481)  # invalid
    assert rig.start() == [frame(0x181, "50 02"), frame(0x281, "00")]
    assert rig.engine.poll(0.001) == []


def test_empty_mapping_sends_nothing() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1800, [], ttype=255)
    assert rig.start() == []


def test_inhibit_time_delays_a_change_until_it_expires() -> None:
    rig = make_rig(MDI)
    configure(rig.store, 0x1800, [0x60410010], ttype=255, inhibit=1000)  # 100 ms
    assert rig.start(0.0) == [frame(0x181, "00 00")]
    rig.store.set(0x6041, 0, 1)
    assert rig.engine.poll(0.01) == []
    assert rig.engine.poll(0.0999) == []
    assert rig.engine.poll(0.1) == [frame(0x181, "01 00")]
    rig.store.set(0x6041, 0, 2)
    assert rig.engine.poll(0.15) == []
    rig.store.set(0x6041, 0, 3)
    assert rig.engine.poll(0.2) == [frame(0x181, "03 00")]  # the latest value


@pytest.mark.parametrize(
    ("restarts_on_send", "sends_at"),
    [
        (True, [0.0, 0.010, 0.013, 0.023]),  # MDi-S1-C manual §2.5.3 4): every send restarts it
        (False, [0.0, 0.010, 0.013, 0.020]),  # Nanotec article 180Nh:05: only expiry restarts it
    ],
)
def test_event_timer(restarts_on_send: bool, sends_at: list[float]) -> None:
    rig = make_rig(replace(MDI, event_timer_restarts_on_send=restarts_on_send))
    configure(rig.store, 0x1800, [0x60410010], ttype=255, timer=10)
    times: list[float] = [0.0] if rig.start(0.0) else []
    for tick in range(1, 26):
        now = tick * 0.001
        if tick == 13:
            rig.store.set(0x6041, 0, 7)
        if rig.engine.poll(now):
            times.append(now)
    assert times == pytest.approx(sends_at)


@pytest.mark.parametrize(
    ("counters", "start_value", "sends_at"),
    [
        (False, 0, [2, 4, 6, 8]),  # type 2: every 2nd SYNC
        (True, 3, [3, 5, 7]),  # 1019h > 1: the SYNC with counter 3 is the first one
        (True, 0, [2, 4, 6, 8]),  # start value 0: not used
    ],
)
def test_cyclic_tpdo_and_sync_start_value(
    counters: bool, start_value: int, sends_at: list[int]
) -> None:
    rig = make_rig(CIA402)
    configure(rig.store, 0x1800, [0x60410010], ttype=2)
    write(rig.store, 0x1800, 6, start_value)
    rig.start()
    sent = [n for n in range(1, 9) if rig.engine.on_sync(n if counters else None, n * 0.001)]
    assert sent == sends_at


# ----------------------------------------------------------------------------- RTR (cia402)


def test_rtr_type_253_samples_and_sends_on_request() -> None:
    rig = make_rig(CIA402)
    configure(rig.store, 0x1800, [0x60410010], ttype=253, cob_id=0x181)
    assert rig.start() == []
    assert rig.engine.poll(0.001) == []  # never on its own
    rig.store.set(0x6041, 0, 0x0237)
    assert rig.engine.on_frame(Frame(0x181, rtr=True, dlc=2), 0.002) == [frame(0x181, "37 02")]


def test_rtr_type_252_sends_what_the_last_sync_sampled() -> None:
    rig = make_rig(CIA402)
    configure(rig.store, 0x1800, [0x60410010], ttype=252, cob_id=0x181)
    rig.start()
    request = Frame(0x181, rtr=True, dlc=2)
    assert rig.engine.on_frame(request, 0.0) == []  # nothing sampled yet
    rig.store.set(0x6041, 0, 0x0233)
    assert rig.engine.on_sync(None, 0.001) == []
    rig.store.set(0x6041, 0, 0x0237)
    assert rig.engine.on_frame(request, 0.002) == [frame(0x181, "33 02")]


@pytest.mark.parametrize(
    ("rules", "cob_id"),
    [
        (CIA402, 0x40000181),  # bit 30: no RTR allowed on this PDO
        (replace(CIA402, rtr_transmission=False), 0x181),  # the drive has no RTR transmission
    ],
)
def test_rtr_refused(rules: PdoRules, cob_id: int) -> None:
    rig = make_rig(rules)
    configure(rig.store, 0x1800, [0x60410010], ttype=1, cob_id=cob_id)
    if rules.rtr_transmission:
        write(rig.store, 0x1800, 1, cob_id | INVALID)
        write(rig.store, 0x1800, 2, 253)
        write(rig.store, 0x1800, 1, cob_id)
    rig.start()
    assert rig.engine.on_frame(Frame(0x181, rtr=True, dlc=2), 0.0) == []


# ----------------------------------------------------------------------------- COB-ID changes


@pytest.mark.parametrize("needs_reset", [True, False])
def test_free_cob_id_takes_effect_per_rule(needs_reset: bool) -> None:
    rig = make_rig(replace(CIA402, cob_id_change_needs_reset=needs_reset))
    rig.store.set(0x6041, 0, 0x0250)
    configure(rig.store, 0x1804, [0x60410010], ttype=255, cob_id=0x1A5)
    expected = [frame(0x1A5, "50 02")]
    assert rig.start() == ([] if needs_reset else expected)  # Nanotec article: after a restart
    rig.nmt(NmtState.PRE_OPERATIONAL)
    rig.engine.reset()  # reset communication (the store keeps the written value here)
    assert rig.start() == expected
