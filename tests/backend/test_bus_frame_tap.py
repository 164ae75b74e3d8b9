"""The bus's one EMCY / SDO-abort listener (bus/frame_tap.py), fed frames directly: no bus, no
notifier thread."""

from __future__ import annotations

import logging

import can
import pytest

from servodesk.bus.frame_tap import FrameTap
from servodesk_protocol.sdo import abort_frame

Heard = list[tuple[int, bytes]]

EMCY_5 = bytes.fromhex("1082 11 0000000000")  # CiA 301: 8210h, error register 11h
ABORT_7 = abort_frame(0x6060, 0, 0x06090030)  # node 7 refused a 6060h write


def frame(can_id: int, data: bytes = EMCY_5, **flags: bool) -> can.Message:
    return can.Message(arbitration_id=can_id, data=data, **{"is_extended_id": False, **flags})


@pytest.fixture
def tap() -> FrameTap:
    return FrameTap()


def test_an_emcy_reaches_every_emcy_subscriber_once(tap: FrameTap) -> None:
    first: Heard = []
    second: Heard = []
    aborts: Heard = []
    tap.on_emcy(lambda node, data: first.append((node, data)))
    tap.on_emcy(lambda node, data: second.append((node, data)))
    tap.on_sdo_abort(lambda node, data: aborts.append((node, data)))
    tap.on_message_received(frame(0x085))
    assert first == second == [(5, EMCY_5)]
    assert aborts == []


def test_a_remover_stops_only_its_subscriber(tap: FrameTap) -> None:
    kept: Heard = []
    removed: Heard = []
    tap.on_emcy(lambda node, data: kept.append((node, data)))
    remove = tap.on_emcy(lambda node, data: removed.append((node, data)))
    remove()
    remove()  # twice is harmless
    tap.on_message_received(frame(0x085))
    assert kept == [(5, EMCY_5)]
    assert removed == []


def test_an_sdo_abort_reaches_the_abort_subscribers(tap: FrameTap) -> None:
    emcys: Heard = []
    aborts: Heard = []
    tap.on_emcy(lambda node, data: emcys.append((node, data)))
    tap.on_sdo_abort(lambda node, data: aborts.append((node, data)))
    tap.on_message_received(frame(0x587, ABORT_7))
    tap.on_message_received(frame(0x587, bytes.fromhex("60 4060 00 00000000")))  # an answer
    tap.on_message_received(frame(0x587, b""))  # no command byte at all
    assert aborts == [(7, ABORT_7)]
    assert emcys == []


def test_first_puts_a_subscriber_ahead(tap: FrameTap) -> None:
    order: list[str] = []
    tap.on_emcy(lambda node, data: order.append("fault service"))
    tap.on_emcy(lambda node, data: order.append("jog stop"), first=True)
    tap.on_message_received(frame(0x081))
    assert order == ["jog stop", "fault service"]


@pytest.mark.parametrize(
    "msg",
    [
        frame(0x085, is_extended_id=True),  # 29-bit id 85h is not an EMCY
        frame(0x085, data=b"", is_remote_frame=True),
        frame(0x085, is_error_frame=True),
        frame(0x080),  # SYNC, not node 0's EMCY
        frame(0x100),  # past 80h + 127
        frame(0x7F),
        frame(0x185),  # TPDO1 of node 5
        frame(0x580, ABORT_7),  # SDO response base: no node 0
        frame(0x600 + 7, ABORT_7),  # an abort the tool sends (client -> server)
        frame(0x587, ABORT_7, is_extended_id=True),
    ],
    ids=[
        "extended",
        "remote",
        "error",
        "080h",
        "100h",
        "07Fh",
        "TPDO",
        "580h",
        "tool's abort",
        "extended abort",
    ],
)
def test_other_frames_are_ignored(tap: FrameTap, msg: can.Message) -> None:
    heard: Heard = []
    tap.on_emcy(lambda node, data: heard.append((node, data)))
    tap.on_sdo_abort(lambda node, data: heard.append((node, data)))
    tap.on_message_received(msg)
    assert heard == []


def test_the_whole_node_range(tap: FrameTap) -> None:
    heard: Heard = []
    tap.on_emcy(lambda node, data: heard.append((node, data)))
    tap.on_message_received(frame(0x081))
    tap.on_message_received(frame(0x0FF))
    assert [node for node, _ in heard] == [1, 127]


def test_a_failing_subscriber_is_logged_once_and_does_not_stop_the_others(
    tap: FrameTap, caplog: pytest.LogCaptureFixture
) -> None:
    heard: Heard = []

    def broken(node: int, data: bytes) -> None:
        raise RuntimeError("bug")

    tap.on_emcy(broken)
    tap.on_emcy(lambda node, data: heard.append((node, data)))
    with caplog.at_level(logging.ERROR, logger="servodesk.bus.frame_tap"):
        for _ in range(3):
            tap.on_message_received(frame(0x085))
    assert len(heard) == 3
    assert tap.failures == 3
    assert len(caplog.records) == 1


def test_clear_forgets_every_subscriber(tap: FrameTap) -> None:
    heard: Heard = []
    tap.on_emcy(lambda node, data: heard.append((node, data)))
    tap.on_sdo_abort(lambda node, data: heard.append((node, data)))
    tap.clear()
    tap.on_message_received(frame(0x085))
    tap.on_message_received(frame(0x587, ABORT_7))
    assert heard == []
