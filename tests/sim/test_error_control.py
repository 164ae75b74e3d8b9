"""Heartbeat producer/consumer and node/life guarding with a fake clock."""

from __future__ import annotations

import pytest

from servodesk_protocol.nmt import NmtState, consumer_entry
from servodesk_protocol.sdo_abort import PARAMETER_INCOMPATIBLE as PARAM_INCOMPATIBLE
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.error_control import (
    HeartbeatConsumer,
    HeartbeatProducer,
    NodeGuarding,
)
from servodesk_sim.frames import Frame, frame

NODE = 4


def beats(
    producer: HeartbeatProducer, times: list[float], period_ms: int, state: NmtState
) -> list[tuple[float, Frame]]:
    out = []
    for now in times:
        beat = producer.poll(now, period_ms, state, NODE)
        if beat is not None:
            out.append((now, beat))
    return out


# ----------------------------------------------------------------------- heartbeat producer


@pytest.mark.parametrize(
    ("state", "data"),
    [
        (NmtState.PRE_OPERATIONAL, "7F"),
        (NmtState.OPERATIONAL, "05"),
        (NmtState.STOPPED, "04"),  # error control still runs in Stopped (MDi-S1-C manual table 2.8)
    ],
)
def test_heartbeat_carries_the_state(state: NmtState, data: str) -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    assert producer.poll(0.1, 100, state, NODE) == frame(0x704, data)


def test_heartbeat_every_period_on_a_fixed_grid() -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    times = [0.05, 0.099, 0.1, 0.15, 0.205, 0.25, 0.3, 0.35]
    sent = [now for now, _ in beats(producer, times, 100, NmtState.OPERATIONAL)]
    assert sent == [0.1, 0.205, 0.3]  # the late 0.205 does not push the next one back


def test_heartbeat_after_a_long_stall_sends_one_and_starts_a_new_grid() -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    times = [1.0, 1.01, 1.05, 1.1]
    sent = [now for now, _ in beats(producer, times, 100, NmtState.OPERATIONAL)]
    assert sent == [1.0, 1.1]


@pytest.mark.parametrize("period_ms", [0, -1])
def test_heartbeat_disabled_by_zero_period(period_ms: int) -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    assert beats(producer, [0.5, 1.0, 5.0], period_ms, NmtState.OPERATIONAL) == []


def test_heartbeat_not_sent_while_initialising() -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    assert beats(producer, [0.2, 0.4], 100, NmtState.INITIALISING) == []


def test_restart_moves_the_period() -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    assert producer.poll(0.08, 100, NmtState.OPERATIONAL, NODE) is None
    producer.restart(0.08)  # 1017h written
    assert producer.poll(0.1, 100, NmtState.OPERATIONAL, NODE) is None
    assert producer.poll(0.18, 100, NmtState.OPERATIONAL, NODE) == frame(0x704, "05")


def test_heartbeat_enabled_later_starts_a_full_period_then() -> None:
    producer = HeartbeatProducer()
    producer.restart(0.0)
    assert producer.poll(5.0, 0, NmtState.OPERATIONAL, NODE) is None
    assert producer.poll(6.0, 200, NmtState.OPERATIONAL, NODE) is None  # no burst for the past
    assert producer.poll(6.1, 200, NmtState.OPERATIONAL, NODE) is None
    assert producer.poll(6.2, 200, NmtState.OPERATIONAL, NODE) == frame(0x704, "05")


# ----------------------------------------------------------------------- heartbeat consumer


entry = consumer_entry  # its layout: tests/protocol/test_nmt.py


@pytest.mark.parametrize(
    ("entries", "refused"),
    [
        ([entry(1, 200), entry(1, 300)], True),  # MDi-S1-C manual 1016h: two times for one node
        ([entry(1, 200), entry(2, 200)], False),
        ([entry(1, 200), entry(1, 0)], False),  # time 0: entry unused
        ([entry(0, 200), entry(0, 300)], False),  # node 0: entry unused
        ([entry(5, 100), 0, entry(6, 100), entry(5, 100)], True),
        ([], False),
    ],
)
def test_validate_refuses_two_entries_for_one_node(entries: list[int], refused: bool) -> None:
    if refused:
        with pytest.raises(SdoAbort) as raised:
            HeartbeatConsumer.validate(entries)
        assert raised.value.code == PARAM_INCOMPATIBLE == 0x06040043
    else:
        HeartbeatConsumer.validate(entries)


def test_monitoring_starts_at_the_first_heartbeat() -> None:
    consumer = HeartbeatConsumer()
    consumer.configure([entry(1, 200)])
    assert consumer.poll(10.0) == []  # never heard: not monitored yet (MDi-S1-C manual §2.3.2)
    consumer.on_heartbeat(1, 10.0)
    assert consumer.poll(10.2) == []  # exactly the consumer time: still fine
    assert consumer.poll(10.21) == [1]


@pytest.mark.parametrize(
    ("events", "lost_at"),
    [
        # (kind, time): "hb" heartbeat from node 1, "poll" returns what it reports
        ([("hb", 0.0), ("hb", 0.15), ("poll", 0.3), ("poll", 0.36)], [0.36]),
        ([("hb", 0.0), ("poll", 0.25), ("poll", 0.5), ("poll", 1.0)], [0.25]),  # once per loss
        ([("hb", 0.0), ("poll", 0.25), ("hb", 0.3), ("poll", 0.4), ("poll", 0.6)], [0.25, 0.6]),
    ],
)
def test_loss_is_reported_once_and_again_after_recovery(
    events: list[tuple[str, float]], lost_at: list[float]
) -> None:
    consumer = HeartbeatConsumer()
    consumer.configure([entry(1, 200)])
    reported = []
    for kind, now in events:
        if kind == "hb":
            consumer.on_heartbeat(1, now)
        elif consumer.poll(now) == [1]:
            reported.append(now)
    assert reported == lost_at


def test_several_nodes_and_foreign_heartbeats() -> None:
    consumer = HeartbeatConsumer()
    consumer.configure([entry(1, 100), entry(2, 300), 0])
    consumer.on_heartbeat(1, 0.0)
    consumer.on_heartbeat(2, 0.0)
    consumer.on_heartbeat(3, 0.0)  # not watched
    assert consumer.poll(0.2) == [1]
    assert consumer.poll(0.4) == [2]


def test_reconfigure_keeps_unchanged_entries_and_restarts_changed_ones() -> None:
    consumer = HeartbeatConsumer()
    consumer.configure([entry(1, 100), entry(2, 100)])
    consumer.on_heartbeat(1, 0.0)
    consumer.on_heartbeat(2, 0.0)
    consumer.configure([entry(1, 100), entry(2, 500)])
    assert consumer.poll(0.2) == [1]  # node 2 waits for its next heartbeat now
    consumer.configure([entry(2, 500)])
    consumer.on_heartbeat(1, 0.3)
    assert consumer.poll(5.0) == []  # node 1 no longer watched


# ------------------------------------------------------------------------------- guarding


def test_guarding_answer_toggles_starting_at_zero() -> None:
    guarding = NodeGuarding()
    answers = [
        guarding.on_rtr(NmtState.PRE_OPERATIONAL, NODE, 0.0),
        guarding.on_rtr(NmtState.PRE_OPERATIONAL, NODE, 0.1),
        guarding.on_rtr(NmtState.OPERATIONAL, NODE, 0.2),
        guarding.on_rtr(NmtState.STOPPED, NODE, 0.3),
    ]
    # MDi-S1-C manual table 2.11: bit 7 alternates, bits 6-0 the state
    assert answers == [
        frame(0x704, "7F"),
        frame(0x704, "FF"),
        frame(0x704, "05"),
        frame(0x704, "84"),
    ]


def test_reset_communication_restarts_the_toggle() -> None:
    guarding = NodeGuarding()
    guarding.on_rtr(NmtState.PRE_OPERATIONAL, NODE, 0.0)
    guarding.reset()
    assert guarding.on_rtr(NmtState.PRE_OPERATIONAL, NODE, 1.0) == frame(0x704, "7F")


@pytest.mark.parametrize(
    ("guard_ms", "factor", "heartbeat", "rtr_at", "polls", "lost_at"),
    [
        # life time 100 ms x 3 = 0.3 s after the last RTR
        (100, 3, False, [0.0], [0.2, 0.3, 0.31, 0.5], [0.31]),
        (100, 3, False, [0.0, 0.25], [0.31, 0.55, 0.56, 0.9], [0.56]),
        (100, 3, False, [], [1.0, 10.0], []),  # no RTR yet: life guarding not active
        (0, 3, False, [0.0], [1.0, 10.0], []),  # 100Ch = 0: off
        (100, 0, False, [0.0], [1.0, 10.0], []),  # 100Dh = 0: off
        (100, 3, True, [0.0], [1.0, 10.0], []),  # heartbeat on: guarding not monitored
    ],
)
def test_life_guarding(
    guard_ms: int,
    factor: int,
    heartbeat: bool,
    rtr_at: list[float],
    polls: list[float],
    lost_at: list[float],
) -> None:
    guarding = NodeGuarding()
    events = sorted([(t, "rtr") for t in rtr_at] + [(t, "poll") for t in polls])
    reported = []
    for now, kind in events:
        if kind == "rtr":
            guarding.on_rtr(NmtState.OPERATIONAL, NODE, now)
        elif guarding.poll(now, guard_ms, factor, heartbeat):
            reported.append(now)
    assert reported == lost_at


def test_life_guarding_reports_again_after_rtrs_resume() -> None:
    guarding = NodeGuarding()
    guarding.on_rtr(NmtState.OPERATIONAL, NODE, 0.0)
    assert guarding.poll(0.5, 100, 2, False)
    guarding.on_rtr(NmtState.OPERATIONAL, NODE, 1.0)
    assert not guarding.poll(1.1, 100, 2, False)
    assert guarding.poll(1.3, 100, 2, False)


def test_reset_deactivates_life_guarding_until_the_next_rtr() -> None:
    guarding = NodeGuarding()
    guarding.on_rtr(NmtState.OPERATIONAL, NODE, 0.0)
    guarding.reset()
    assert not guarding.poll(5.0, 100, 2, False)
