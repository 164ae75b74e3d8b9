"""The capture window of CaptureCore, fed frames the way the flush hands them over: uneven
batches of (CAN id, arrival time, payload), built the way the service builds the core
(wanted → plan_node → capture_signals → build_core), with a recording sink as the Output."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import pytest

from servodesk.events.bus import BusEvent, EventKind
from servodesk.models.scope import (
    CaptureRequest,
    CaptureSignal,
    ScopeSignalRequest,
    TriggerRequest,
)
from servodesk.motion.units import DriveUnits
from servodesk.od import DataType, OdSub
from servodesk.pdo.model import PdoConfig
from servodesk.scope.batch import Floats
from servodesk.scope.capture import CaptureCore
from servodesk.scope.frames import Frame
from servodesk.scope.plan import plan_node
from servodesk.scope.setup import SDO_STREAM_BASE, build_core, capture_signals, wanted
from servodesk.scope.signals import signal_info
from servodesk_protocol.pdo import MapEntry, pack

NODE, OTHER = 2, 9
T0 = 1_700_000_000.0  # arrival times are epoch seconds
PERIOD = 0.001  # the SYNC period (1000 µs)
STATUS, POSITION, VELOCITY, TORQUE, VOLTAGE = 0x6041, 0x6064, 0x606C, 0x6077, 0x2000
DICTIONARY = {
    STATUS: OdSub(STATUS, 0, "Statusword", DataType.UNSIGNED16, "ro", True),
    POSITION: OdSub(POSITION, 0, "Position actual value", DataType.INTEGER32, "ro", True),
    VELOCITY: OdSub(VELOCITY, 0, "Velocity actual value", DataType.INTEGER32, "ro", True),
    TORQUE: OdSub(TORQUE, 0, "Torque actual value", DataType.INTEGER16, "ro", True),
    VOLTAGE: OdSub(VOLTAGE, 0, "DC bus voltage", DataType.UNSIGNED16, "ro", False),  # SDO
}
FREE = [PdoConfig("tpdo", n, 0x80 + 0x100 * n + NODE, False, 255) for n in (1, 2, 3, 4)]
DISABLED, READY, ON, ENABLED = 0x0250, 0x0231, 0x0233, 0x0237


def t(k: float) -> float:
    """Arrival time of SYNC cycle k."""
    return T0 + k * PERIOD


@dataclass
class Recorder:
    """The Output: what the window writes, per signal, and the text lanes."""

    times: dict[int, list[float]] = field(default_factory=dict)
    rel: dict[int, list[float]] = field(default_factory=dict)
    raw: dict[int, list[float]] = field(default_factory=dict)
    lanes: list[tuple[int, str, float, float, str]] = field(default_factory=list)

    def samples(self, signal: int, times: Floats, rel: Floats, raw: Floats) -> None:
        self.times.setdefault(signal, []).extend(times.tolist())
        self.rel.setdefault(signal, []).extend(rel.tolist())
        self.raw.setdefault(signal, []).extend(raw.tolist())

    def texts(
        self, node: int, lane: str, times: Sequence[float], rel: Sequence[float], texts: list[str]
    ) -> None:
        self.lanes.extend((node, lane, a, r, x) for a, r, x in zip(times, rel, texts, strict=True))

    def lane(self, name: str) -> list[tuple[float, str]]:
        return [(round(r, 6), x) for _, lane, _, r, x in self.lanes if lane == name]


@dataclass
class Rig:
    core: CaptureCore
    out: Recorder
    signals: list[CaptureSignal]

    def number(self, index: int) -> int:
        return next(i for i, s in enumerate(self.signals) if s.index == index)

    def count(self, index: int) -> int:
        return len(self.out.raw.get(self.number(index), []))

    def frames(
        self,
        ks: Sequence[float],
        values: Callable[[float], dict[int, int]],
        times: Callable[[float], float] = t,
    ) -> list[Frame]:
        """Every scope TPDO's frame for each SYNC cycle k."""
        out: list[Frame] = []
        for k in ks:
            got = values(k)
            for pdo in self.core.streams.values():
                if pdo.decoder is None:
                    continue
                spec = [self.signals[n] for n in pdo.signals]
                cob_id = spec[0].cob_id
                assert cob_id is not None
                fields = [(s, got.get(s.index, 0) & ((1 << s.bits) - 1)) for s in spec]
                payload = pack([(_entry(s), v.to_bytes(s.bits // 8, "little")) for s, v in fields])
                out.append((cob_id, times(k), payload))
        return out

    def sdo(self, index: int, when: float, value: int) -> Frame:
        return (SDO_STREAM_BASE + self.number(index), when, value.to_bytes(2, "little"))

    def feed(self, *batches: Sequence[Frame], events: Sequence[BusEvent] = ()) -> None:
        for frames in batches:
            self.core.process(sorted(frames, key=lambda f: f[1]), events)


def _entry(signal: CaptureSignal) -> MapEntry:
    return MapEntry(signal.index, signal.subindex, signal.bits)


def rig(
    indices: Sequence[int],
    duration_s: float,
    trigger: TriggerRequest | None = None,
    *,
    lane: bool = False,
) -> Rig:
    request = CaptureRequest(
        signals=[ScopeSignalRequest(node=NODE, index=i) for i in indices],
        sync_period_us=round(PERIOD * 1e6),
        duration_s=duration_s,
        trigger=trigger or TriggerRequest(),
    )
    need = wanted(request, {NODE: lane})
    infos = {key: signal_info(NODE, DICTIONARY[key[1]], DriveUnits()) for key in need.keys}
    plan = plan_node(
        NODE, list(infos.values()), FREE, byte_granular=True, fixed_cob_ids=0, taken_ids={}
    )
    signals = capture_signals(need.keys, {NODE: plan}, need.added)
    out = Recorder()
    return Rig(build_core(signals, infos, {NODE: plan.scope_pdos}, request, out), out, signals)


def ramp(k: float) -> dict[int, int]:
    return {POSITION: round(100 * k), VELOCITY: -round(k), TORQUE: 7, STATUS: ENABLED}


def chunks(frames: list[Frame], sizes: Sequence[int]) -> list[list[Frame]]:
    """`frames` cut into batches of `sizes` (the rest in a last batch)."""
    out, start = [], 0
    for size in sizes:
        out.append(frames[start : start + size])
        start += size
    return [*out, frames[start:]]


def level(pre_s: float) -> TriggerRequest:
    return TriggerRequest(kind="level", node=NODE, index=POSITION, level=5000, pre_s=pre_s)


def emcy(node: int, when: float) -> BusEvent:
    return BusEvent(when, EventKind.EMCY, node, f"EMCY 7500h from node {node}")


# ---------------------------------------------------------------------------------- tests


def test_free_running_window_has_exact_counts_over_uneven_batches() -> None:
    scope = rig([STATUS, POSITION, VELOCITY, TORQUE], duration_s=0.05)  # 50 samples each
    assert len({s.tpdo for s in scope.signals}) == 2  # two frame streams
    frames = sorted(scope.frames(range(120), ramp), key=lambda f: f[1])
    done = []
    for batch in chunks(frames, [1, 8, 0, 41, 43, 6, 1, 140]):
        scope.feed(batch)
        done.append(scope.core.done())
    assert done == [False] * 6 + [True] * 3  # the 100th frame: k=49 of the second TPDO
    assert scope.core.trigger_time == t(0)
    for signal in scope.signals:
        n = scope.signals.index(signal)
        assert len(scope.out.raw[n]) == 50
        assert scope.out.rel[n][0] == 0.0
        assert scope.out.rel[n][-1] == pytest.approx(0.049)
    assert scope.out.raw[scope.number(POSITION)] == [100.0 * k for k in range(50)]
    assert scope.out.raw[scope.number(VELOCITY)] == [-1.0 * k for k in range(50)]
    assert scope.out.lane("events") == [(0.0, "trigger: free-running: the first sample")]


def stalled_before(k: float) -> float:
    """SYNCs from k=38 held up by a 3 ms stall, then made up half a period apart until back on
    schedule at k=44 (bus/cyclic.py): k=38 and 39 arrive after the trigger time − pre_s."""
    return t(41 + (k - 38) / 2) if 38 <= k < 44 else t(k)


@pytest.mark.parametrize(
    ("pre_times", "post_times"),
    [
        (t, t),  # on time
        (t, lambda k: t(50) + (k - 50) * 0.01),  # late, 10 ms apart after the trigger
        (stalled_before, t),  # a stall that moved SYNCs into the window: still 10
    ],
)
def test_pre_trigger_and_trigger_sample_at_zero(
    pre_times: Callable[[float], float], post_times: Callable[[float], float]
) -> None:
    scope = rig([POSITION], duration_s=0.0305, trigger=level(pre_s=0.0105))  # 20 after
    history = scope.frames(range(50), ramp, times=pre_times)
    after = scope.frames(range(50, 200), ramp, times=post_times)
    scope.feed(*chunks(history, [7] * 7))  # k=49, the predecessor, alone in its batch
    assert scope.core.armed
    assert scope.count(POSITION) == 0
    done = []
    for batch in chunks(after, [1, 5, 13, 1, 30]):  # the crossing (k=50) opens a batch
        scope.feed(batch)
        done.append(scope.core.done())
    assert scope.core.trigger_time == t(50)
    assert done == [False, False, False, True, True, True]  # 1 + 5 + 13 + 1 = 20 after
    rel, raw = scope.out.rel[0], scope.out.raw[0]
    assert len(raw) == 30
    assert raw == [100.0 * k for k in range(40, 70)]
    assert rel[10] == 0.0
    assert raw[10] == 5000
    assert rel[0] == pytest.approx(pre_times(40) - t(50))
    assert scope.out.lane("events") == [
        (0.0, "trigger: node 2 6064h:00 Position actual value rose to 5000 (5000)")
    ]


def test_sdo_window_by_time_and_done_only_when_every_signal_is_complete() -> None:
    scope = rig([POSITION, VOLTAGE], duration_s=0.05)
    assert [s.source for s in scope.signals] == ["pdo", "sdo"]
    pdo = scope.frames(range(60), ramp)
    polls = [scope.sdo(VOLTAGE, t(0.3 + 7 * j), 230 + j) for j in range(10)]  # every 7 ms
    scope.feed(pdo[:30] + polls[:9])
    assert not scope.core.done()  # the SDO window ended (j=8 at 56.3 ms), the TPDO's did not
    scope.feed(pdo[30:49])
    assert not scope.core.done()
    scope.feed(pdo[49:50])
    assert scope.core.done()
    voltage = scope.number(VOLTAGE)
    assert scope.out.raw[voltage] == [230.0 + j for j in range(8)]  # up to 49.3 ms
    assert scope.out.rel[voltage] == pytest.approx([0.0003 + 0.007 * j for j in range(8)], abs=1e-6)

    scope = rig([POSITION, VOLTAGE], duration_s=0.05)
    scope.feed(pdo + polls[:8])
    assert not scope.core.done()  # all TPDO samples; the last poll (49.3 ms) is short of 50 ms
    scope.feed(polls[8:9])
    assert scope.core.done()


@pytest.mark.parametrize(
    ("trigger", "lane"),
    [
        (
            None,  # free-running: every change from the first sample on
            [
                (0.0, "Switch on disabled"),
                (0.005, "Ready to switch on"),
                (0.008, "Switched on"),
                (0.009, "Operation enabled"),
                (0.016, "Fault"),
            ],
        ),
        (
            TriggerRequest(kind="state", node=NODE, state="operation enabled", pre_s=0.0035),
            [
                (-0.003, "Ready to switch on"),
                (-0.001, "Switched on"),
                (0.0, "Operation enabled"),
                (0.007, "Fault"),
            ],
        ),
    ],
)
def test_state_lane_texts_on_statusword_changes(
    trigger: TriggerRequest | None, lane: list[tuple[float, str]]
) -> None:
    scope = rig([POSITION], duration_s=0.02, trigger=trigger, lane=True)
    why = "the state trigger watches it" if trigger else "the CiA 402 state lane"
    assert scope.signals[scope.number(STATUS)].note == f"added: {why}"

    def words(k: float) -> dict[int, int]:
        word = DISABLED if k < 5 else READY if k < 8 else ON if k < 9 else ENABLED
        return {STATUS: 0x0218 if k >= 16 else word}

    scope.feed(*chunks(scope.frames(range(40), words), [6, 7, 0, 1, 4]))
    assert scope.out.lane("state") == lane
    assert {node for node, *_ in scope.out.lanes} == {NODE}


def test_a_frame_from_before_the_trigger_that_arrives_after_it_is_not_counted() -> None:
    """The EMCY is handed over before a TPDO frame of an earlier SYNC (the frame's batch comes
    later): the window still holds exactly 5 SYNCs before and 10 after."""
    scope = rig(
        [POSITION], duration_s=0.0155, trigger=TriggerRequest(kind="emcy", node=NODE, pre_s=0.0055)
    )
    frames = scope.frames(range(40), ramp)
    scope.feed(frames[:20], events=[emcy(NODE, t(20.2))])  # fires on k = 0 … 19
    scope.feed(frames[20:])  # k = 20, from before the EMCY, comes only now
    assert scope.core.done()
    assert scope.out.raw[0] == [100.0 * k for k in (*range(15, 20), *range(21, 31))]


def test_emcy_trigger_from_an_event() -> None:
    scope = rig(
        [POSITION], duration_s=0.0155, trigger=TriggerRequest(kind="emcy", node=NODE, pre_s=0.0055)
    )
    frames = scope.frames(range(40), ramp)
    scope.feed(frames[:15], events=[emcy(OTHER, t(5))])  # another node's EMCY: no trigger
    assert scope.core.armed
    scope.feed(frames[15:25], events=[emcy(NODE, t(20.2))])
    scope.feed(frames[25:])
    assert scope.core.trigger_time == t(20.2)
    assert scope.core.done()
    rel, raw = scope.out.rel[0], scope.out.raw[0]
    # 5.5 ms before at 1 ms SYNCs: the 5 SYNCs ahead of the EMCY, then 10 after it
    assert raw == [100.0 * k for k in range(16, 31)]
    assert rel[4:6] == pytest.approx([-0.0002, 0.0008], abs=1e-6)
    assert scope.out.lane("events") == [
        (0.0, "trigger: EMCY from node 2: EMCY 7500h from node 2"),
        (0.0, "EMCY 7500h from node 2"),
    ]

    anyone = rig([POSITION], duration_s=0.01, trigger=TriggerRequest(kind="emcy"))
    anyone.feed(frames[:10], events=[emcy(OTHER, t(5))])
    assert anyone.core.trigger_time == t(5)


def test_events_before_the_window_are_not_annotated() -> None:
    scope = rig([POSITION], duration_s=0.0305, trigger=level(pre_s=0.0105))
    frames = scope.frames(range(100), ramp)

    def event(kind: EventKind, k: float, node: int = NODE) -> BusEvent:
        return BusEvent(t(k), kind, node, f"{kind.value} at {k}")

    scope.feed(frames[:20], events=[event(EventKind.NMT, 10)])  # before trigger − pre_s
    scope.feed(
        frames[20:50],
        events=[
            event(EventKind.NODE_BACK, 45),
            event(EventKind.SDO_ABORT, 46),  # not a kind the scope shows
            event(EventKind.NMT, 47, node=OTHER),  # not a captured node
        ],
    )
    scope.feed(frames[50:60], events=[event(EventKind.BOOT_UP, 39)])  # late, still too early
    scope.feed(frames[60:], events=[event(EventKind.FAULT_RESET, 60)])
    assert scope.out.lane("events") == [
        (0.0, "trigger: node 2 6064h:00 Position actual value rose to 5000 (5000)"),
        (-0.005, "node-back at 45"),
        (0.01, "fault-reset at 60"),
    ]


def test_short_frames_are_skipped_and_counted() -> None:
    scope = rig([STATUS, POSITION], duration_s=0.05)
    frames = scope.frames(range(30), ramp)
    assert {len(payload) for *_, payload in frames} == {6}
    cut = [
        (c, when, p[:2]) if k % 3 == 1 else (c, when, p) for k, (c, when, p) in enumerate(frames)
    ]
    scope.feed(cut[:3], [f for f in cut[3:] if len(f[2]) == 2], cut[3:])
    assert scope.core.short_frames == 1 + 9 + 9
    assert scope.out.raw[scope.number(POSITION)] == [100.0 * k for k in range(30) if k % 3 != 1]
    assert scope.count(STATUS) == 20


def test_pre_trigger_history_stays_bounded() -> None:
    scope = rig([POSITION, VELOCITY, TORQUE], duration_s=0.1005, trigger=level(pre_s=0.0505))
    flat = scope.frames(range(3000), lambda k: {POSITION: 0})  # 3 s of waiting
    position = scope.core.tracks[scope.number(POSITION)]
    torque = scope.core.tracks[scope.number(TORQUE)]
    torque_id = scope.signals[scope.number(TORQUE)].cob_id
    assert torque_id != scope.signals[scope.number(POSITION)].cob_id
    most = 0
    for batch in chunks(flat, [66] * 90):
        # the torque's TPDO comes with another mapping (1 byte): every frame skipped
        scope.feed([(c, w, p[:1]) if c == torque_id else (c, w, p) for c, w, p in batch])
        held = sum(times.size for times, _ in position.ring)
        most = max(most, held)
        assert len(torque.ring) <= 2
    assert most <= (0.0505 + 0.1) / PERIOD + 2 * 33  # ~pre_s, a margin and one batch
    assert scope.core.armed
    assert scope.core.short_frames == 3000
    rise = scope.frames(range(3000, 3100), lambda k: {POSITION: 10_000})
    scope.feed(rise)
    assert scope.core.trigger_time == t(3000)
    rel = scope.out.rel[scope.number(POSITION)]
    assert len(rel) == 50 + 50
    assert rel[50] == 0.0


def test_samples_reaching_the_core_after_the_trigger_but_before_its_window_are_left_out() -> None:
    # the EMCY event is stamped on the event loop: frames from just before it can still be in
    # the queue when the flush that fires takes it (pre_s 0: nothing before the trigger)
    scope = rig([POSITION, VOLTAGE], duration_s=0.01, trigger=TriggerRequest(kind="emcy"))
    frames = scope.frames(range(40), ramp)
    scope.feed(frames[:10], events=[emcy(NODE, t(20.2))])
    scope.feed(frames[10:] + [scope.sdo(VOLTAGE, t(k), 230) for k in (19.5, 20.5, 29.5, 30.5)])
    assert scope.out.raw[scope.number(POSITION)] == [100.0 * k for k in range(21, 31)]
    assert min(scope.out.rel[scope.number(VOLTAGE)]) > 0
    assert scope.count(VOLTAGE) == 2
    assert scope.core.done()
