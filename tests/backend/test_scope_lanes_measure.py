"""Pure cores of the statusword lanes and the cursors' readout, table-tested: what the lanes
say at each change of a statusword or controlword, and what the readout shows between two
cursors (values at A and B, Δ, min, max, mean, count), with the errors a user gets."""

from __future__ import annotations

import math

import numpy as np
import pytest

from servodesk.models.scope import CaptureSignal, LanesRequest
from servodesk.scope.lanes import LaneTracker, lanes_for
from servodesk.scope.measure import Batch, CursorError, measure, time_span, trace

DISABLED, READY, ON, ENABLED, FAULT = 0x0250, 0x0231, 0x0233, 0x0237, 0x0218
REACHED = 0x0400  # bit 10 target reached


def words(*values: int) -> np.ndarray:
    return np.asarray(values, dtype=np.float64)


def lane_story(index: int, batches: list[list[int]], bits: list[int]) -> dict[str, list[str]]:
    """Each lane's values in words at its changes, over batches fed one after the other."""
    tracker = LaneTracker(lanes_for(index, 0, bits, bits))
    story: dict[str, list[str]] = {lane.key: [] for lane in tracker.lanes}
    for batch in batches:
        for change in tracker.feed(words(*batch)):
            story[change.lane.key] += change.texts
    return story


def test_an_enable_reads_as_states_and_bits_even_across_batches() -> None:
    batches = [[DISABLED, DISABLED, READY], [READY, ON, ENABLED], [ENABLED | REACHED, FAULT]]
    story = lane_story(0x6041, batches, [3, 10])
    assert story["state"] == [
        "Switch on disabled",
        "Ready to switch on",
        "Switched on",
        "Operation enabled",
        "Fault",
    ]
    assert story["bit_10 target reached"] == ["0", "1", "0"]
    assert story["bit_03 fault"] == ["0", "1"]


def test_a_statusword_without_a_state_says_so() -> None:
    assert lane_story(0x6041, [[0x0001]], [])["state"] == ["no CiA 402 state"]


@pytest.mark.parametrize(
    ("controlwords", "commands"),
    [
        (
            [0x00, 0x06, 0x07, 0x0F],
            ["Disable voltage", "Shutdown", "Switch on", "Switch on enable"],
        ),
        ([0x0F, 0x02], ["Switch on enable", "Quick stop"]),
        ([0x00, 0x80, 0x00], ["Disable voltage", "Fault reset", "Disable voltage"]),
    ],
)
def test_the_controlword_lane_names_the_command(
    controlwords: list[int], commands: list[str]
) -> None:
    assert lane_story(0x6040, [controlwords], [7])["command"] == commands


def test_only_words_get_lanes_and_the_default_bits_are_the_useful_ones() -> None:
    assert lanes_for(0x6064, 0, [10], [0]) == []
    assert lanes_for(0x6041, 1, [10], [0]) == []
    chosen = LanesRequest()
    keys = [lane.key for lane in lanes_for(0x6041, 0, chosen.statusword_bits, [])]
    assert keys == [
        "state",
        "bit_03 fault",
        "bit_07 warning",
        "bit_10 target reached",
        "bit_11 internal limit active",
        "bit_12 set-point ack or homing attained",
        "bit_13 following error or homing error",
    ]
    assert LanesRequest(statusword_bits=[13, 10, 10]).statusword_bits == [10, 13]


def signal(name: str, unit: str) -> CaptureSignal:
    return CaptureSignal(
        node=1,
        index=0x6064,
        subindex=0,
        name=name,
        key=name,
        source="pdo",
        quantity="other",
        unit=unit,
        raw_unit=unit,
        scale=1.0,
        bits=32,
    )


SIGNALS = [signal("position", "rev"), signal("velocity", "rpm")]


def batch(position: int, times: list[float], values: list[float]) -> Batch:
    return (
        np.full(len(times), position, dtype=np.int32),
        np.asarray(times, dtype=np.float64),
        np.asarray(values, dtype=np.float64),
    )


# position: 0.0 … 0.5 s, one sample per 0.1 s; velocity only from 0.25 s, split in two batches
BATCHES = [
    batch(0, [0.0, 0.1, 0.2], [1.0, 2.0, 4.0]),
    batch(1, [0.25, 0.35], [100.0, 300.0]),
    batch(0, [0.3, 0.4, 0.5], [8.0, 3.0, 5.0]),
    batch(1, [0.45], [200.0]),
]


@pytest.mark.parametrize(
    ("t0", "t1", "position", "velocity"),
    [
        # cursors on samples: A and B are those samples; stats include both ends
        (
            0.1,
            0.4,
            (2.0, 3.0, 1.0, 2.0, 8.0, 17 / 4, 4),
            (None, 300.0, None, 100.0, 300.0, 200.0, 2),
        ),
        # between samples: the sample at or before each cursor
        (
            0.15,
            0.47,
            (2.0, 3.0, 1.0, 3.0, 8.0, 5.0, 3),
            (None, 200.0, None, 100.0, 300.0, 200.0, 3),
        ),
        # B before A: Δt and Δvalue negative, the same samples between them
        (
            0.4,
            0.1,
            (3.0, 2.0, -1.0, 2.0, 8.0, 17 / 4, 4),
            (300.0, None, None, 100.0, 300.0, 200.0, 2),
        ),
        # both cursors on one time: one sample between them
        (0.3, 0.3, (8.0, 8.0, 0.0, 8.0, 8.0, 8.0, 1), (100.0, 100.0, 0.0, None, None, None, 0)),
    ],
)
def test_the_readout_between_two_cursors(
    t0: float, t1: float, position: tuple[object, ...], velocity: tuple[object, ...]
) -> None:
    span = time_span(BATCHES)
    assert span == (0.0, 0.5)
    result = measure(BATCHES, SIGNALS, t0, t1, span=span)
    assert result.dt == pytest.approx(t1 - t0)
    for row, expected in zip(result.signals, (position, velocity), strict=True):
        got = (row.at_a, row.at_b, row.delta, row.min, row.max, row.mean, row.count)
        assert got == pytest.approx(expected), row.name
    assert [row.unit for row in result.signals] == ["rev", "rpm"]


@pytest.mark.parametrize(
    ("t0", "t1", "says"),
    [
        (-1.0, 0.2, "t0 = -1 s lies outside the capture: pick a time from 0 s to 0.5 s"),
        (0.1, 7.0, "t1 = 7 s lies outside the capture"),
        (math.nan, 0.2, "t0 must be a number of seconds from the trigger"),
        (0.1, math.inf, "t1 must be a number"),
    ],
)
def test_a_cursor_off_the_capture_says_where_it_may_go(t0: float, t1: float, says: str) -> None:
    with pytest.raises(CursorError, match=None) as error:
        measure(BATCHES, SIGNALS, t0, t1, span=(0.0, 0.5))
    assert says in str(error.value)


def test_the_overview_keeps_a_spike_between_bins() -> None:
    times = [i / 100 for i in range(101)]
    values = [0.0] * 101
    values[37] = 9.0  # one sample's spike
    result = trace([batch(0, times, values), batch(1, [0.5], [1.0])], 0, "rev", (0.0, 1.0), 10)
    assert len(result.times) == 10
    assert max(result.high) == 9.0
    assert result.high.index(9.0) == 3  # the bin 0.3 … 0.4 s
    assert min(result.low) == 0.0
    assert result.times[0] == 0.0
