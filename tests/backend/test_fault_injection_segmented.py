"""Segmented transfers under faults: a drive that falls silent mid-transfer, segment answers
with the wrong toggle bit or repeated, on uploads (1008h, through the API) and downloads
(6081h forced segmented, through the node's session as the services use it).

Each ends with the right value or a clear error naming the node and the object (the client's
abort reaching the drive where the protocol asks for one), and the node's next request works.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import can
import pytest

from servodesk.errors import CommTimeoutError
from servodesk_sim.frames import Frame
from tests.backend.fault_rig import (
    SDO_RX,
    SDO_TX,
    FaultyApp,
    faulty_app,
    segment_response,
    with_data,
)

BOUND = 2.0  # s: the longest any answer may take here (a hang shows as far more)
NAME = "DVS_CANOPEN"  # node 1's 1008h: 11 bytes, two segments
TOGGLE = 0x10
CLIENT_ABORT = 0x80
TOGGLE_NOT_ALTERNATED = 0x05030000
PROFILE_VELOCITY = 0x6081
DOWNLOAD_ANSWER = 0x20  # scs 1 (bits 7–5): a download segment response


@pytest.fixture(scope="module")
def shared(tmp_path_factory: pytest.TempPathFactory) -> Iterator[FaultyApp]:
    with faulty_app(tmp_path_factory.mktemp("data")) as running:
        yield running


@pytest.fixture
def app(shared: FaultyApp) -> Iterator[FaultyApp]:
    yield shared
    shared.rig.clear()
    time.sleep(0.3)


class AbortTap:
    """Client aborts (80h on 600h+node) that reached the simulated drives."""

    def __init__(self, app: FaultyApp, node: int) -> None:
        self.codes: list[int] = []
        self._node = node
        sim = app.services.bus.sim
        assert sim is not None
        self.remove = sim.add_tap(self._on_frame)

    def _on_frame(self, frame: Frame, origin: object | None) -> None:
        if frame.can_id == SDO_RX + self._node and frame.data[:1] == bytes([CLIENT_ABORT]):
            self.codes.append(int.from_bytes(frame.data[4:8], "little"))


def read_name(app: FaultyApp) -> tuple[int, dict[str, object]]:
    answer, took = app.timed("GET", "/api/nodes/1/sdo/1008/0")
    assert took < BOUND, f"took {took:.2f} s"
    body: dict[str, object] = answer.json()
    return answer.status_code, body


def assert_name_reads(app: FaultyApp) -> None:
    status, body = read_name(app)
    assert (status, body["value"]) == (200, NAME), body


def test_drive_silent_after_the_first_segment(app: FaultyApp) -> None:
    """Expected: node 1 answers the initiate of 1008h and then nothing: 504 `timeout` naming
    node 1 and 1008h:00h within the bound; once it answers again, 1008h reads right."""
    rule = app.rig.drop("rx", segment_response(1))
    status, body = read_name(app)
    assert rule.hits >= 1
    assert (status, body["error"], body["node"]) == (504, "timeout", 1), body
    assert "1008h:00h" in str(body["message"])
    app.rig.clear()
    assert_name_reads(app)


def test_bus_silent_mid_transfer(app: FaultyApp) -> None:
    """Expected: the whole bus goes quiet right after the first segment answer (a cut
    cable, no adapter error): 504 naming node 1 and 1008h:00h; when it speaks again, 1008h
    and the other drives read right."""
    app.rig.on("rx", segment_response(1), lambda msg: app.rig.go_silent(), times=1)
    status, body = read_name(app)
    assert (status, body["error"], body["node"]) == (504, "timeout", 1), body
    assert "1008h:00h" in str(body["message"])
    app.rig.speak()
    assert_name_reads(app)
    answer = app.client.get("/api/nodes/3/sdo/1008/0")
    assert (answer.status_code, answer.json()["value"]) == (200, "C5-E-SIM")


def test_a_segment_with_the_wrong_toggle_bit_aborts(app: FaultyApp) -> None:
    """Expected: the first segment answer arrives with its toggle bit flipped: the read fails
    with an error naming node 1, 1008h:00h and the toggle bit (not "no answer"), the drive
    receives the client's abort 05030000h, and the next read gives the right name."""
    taps = AbortTap(app, 1)
    try:

        def flip(msg: can.Message) -> can.Message:
            return with_data(msg, bytes([msg.data[0] ^ TOGGLE]) + bytes(msg.data[1:]))

        app.rig.replace("rx", segment_response(1), flip, times=1)
        status, body = read_name(app)
        assert (status, body["error"], body["node"]) == (502, "sdo_protocol", 1), body
        message = str(body["message"])
        assert "1008h:00h" in message
        assert "toggle" in message.lower(), message
        app.eventually(lambda: TOGGLE_NOT_ALTERNATED in taps.codes, what="the client's abort")
    finally:
        taps.remove()
    assert_name_reads(app)


def test_a_repeated_segment_answer_instead_of_the_next_is_refused(app: FaultyApp) -> None:
    """Expected: the drive repeats its first segment instead of sending the second (same
    toggle bit twice): the read fails naming the toggle bit, no mixed-up name is returned;
    the next read gives the right name."""
    first: list[bytes] = []

    def repeat_first(msg: can.Message) -> can.Message:
        if not first:
            first.append(bytes(msg.data))
            return msg
        return with_data(msg, first[0])

    app.rig.replace("rx", segment_response(1), repeat_first, times=2)
    status, body = read_name(app)
    assert (status, body["error"]) == (502, "sdo_protocol"), body
    assert "toggle" in str(body["message"]).lower(), body
    assert_name_reads(app)


def test_segment_answers_arriving_twice_never_mix_up_the_value(app: FaultyApp) -> None:
    """Expected: every segment answer arrives twice (the copy 0–20 ms later): each of ten
    reads gives exactly the name or a clear error naming node 1; afterwards it reads right."""
    for delay in (0.0, 0.005, 0.01, 0.02, 0.0, 0.005, 0.01, 0.02, 0.0, 0.01):
        rule = app.rig.duplicate("rx", segment_response(1), delay=delay)
        status, body = read_name(app)
        if status == 200:
            assert body["value"] == NAME, body
        else:  # a copy taken for the next answer: refused by its toggle bit, or lost in time
            assert (status, body["error"], body["node"]) in {
                (502, "sdo_protocol", 1),
                (504, "timeout", 1),
            }, body
            assert "1008h:00h" in str(body["message"])
        app.rig.remove(rule)
    time.sleep(0.3)
    assert_name_reads(app)


def segmented_write(app: FaultyApp, node: int, value: int) -> None:
    """6081h written with a segmented download (as a long DOMAIN would be), on the node's
    session: the path every service takes."""
    session = app.services.registry.session(node)
    data = value.to_bytes(4, "little")
    started = time.monotonic()
    try:
        app.call(
            lambda: session.run(
                lambda remote: remote.sdo.download(PROFILE_VELOCITY, 0, data, force_segment=True),
                what="write 6081h:00h",
                index=PROFILE_VELOCITY,
            )
        )
    finally:
        assert time.monotonic() - started < BOUND


def read_velocity(app: FaultyApp, node: int) -> int:
    answer = app.client.get(f"/api/nodes/{node}/sdo/6081/0")
    assert answer.status_code == 200, answer.json()
    value: int = answer.json()["value"]
    return value


def test_drive_silent_during_a_segmented_download(app: FaultyApp) -> None:
    """Expected: node 2 acknowledges the initiate and then answers nothing: CommTimeoutError
    naming node 2 and 6081h:00h within the bound; the value is the old or the new one (the
    segment reached the drive, only its answer was lost), and the next write works."""
    before = read_velocity(app, 2)

    def download_answer(msg: can.Message) -> bool:
        return msg.arbitration_id == SDO_TX + 2 and msg.data[0] & 0xE0 == DOWNLOAD_ANSWER

    app.rig.drop("rx", download_answer)
    with pytest.raises(CommTimeoutError) as caught:
        segmented_write(app, 2, 4242)
    assert caught.value.node_id == 2
    assert "6081h:00h" in str(caught.value)
    app.rig.clear()
    assert read_velocity(app, 2) in {before, 4242}
    segmented_write(app, 2, 4343)
    assert read_velocity(app, 2) == 4343


def test_a_lost_segment_request_times_out_and_leaves_the_value(app: FaultyApp) -> None:
    """Expected: the segment of a segmented download to node 3 is lost on its way: timeout
    naming node 3 and 6081h:00h; the drive never got the data, so 6081h keeps its value; the
    next segmented write works."""
    before = read_velocity(app, 3)

    def segment(msg: can.Message) -> bool:
        return msg.arbitration_id == SDO_RX + 3 and msg.data[0] & 0xE0 == 0x00

    app.rig.drop("tx", segment, times=1)
    with pytest.raises(CommTimeoutError) as caught:
        segmented_write(app, 3, before + 1)
    assert caught.value.node_id == 3
    assert read_velocity(app, 3) == before
    segmented_write(app, 3, before + 2)
    assert read_velocity(app, 3) == before + 2
