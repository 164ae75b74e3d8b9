"""The pure rules of the heartbeat monitor (network/health.py) and the frame recorder, with
explicit times: no clock, no bus."""

from __future__ import annotations

import can
import pytest

from servodesk.models.nodes import NmtStateName
from servodesk.network.health import Evidence, Health, assess
from servodesk.network.monitor import FrameWatch

FACTOR = 1.5
DEFAULT = 3.0
NOW = 100.0


def _assess(ev: Evidence, now: float = NOW) -> Health:
    return assess(ev, now, lost_factor=FACTOR, default_timeout=DEFAULT)


@pytest.mark.parametrize(
    ("evidence", "online", "state", "age_ms"),
    [
        # heartbeat 100 ms: lost after 150 ms without one
        (
            Evidence(beat=(99.9, 0x05), heartbeat_ms=100, expect_since=90.0),
            True,
            "operational",
            100,
        ),
        (
            Evidence(beat=(99.86, 0x7F), heartbeat_ms=100, expect_since=90.0),
            True,
            "pre-operational",
            140,
        ),
        (Evidence(beat=(99.8, 0x05), heartbeat_ms=100, expect_since=90.0), False, "unknown", 200),
        # just configured: no heartbeat yet, but within one lost time of the write
        (Evidence(heartbeat_ms=100, expect_since=99.9), True, "unknown", None),
        (Evidence(heartbeat_ms=100, expect_since=99.0), False, "unknown", None),
        # beats arrive but 1017h unknown: the default timeout applies
        (Evidence(beat=(98.0, 0x04)), True, "stopped", 2000),
        (Evidence(beat=(96.0, 0x04)), False, "unknown", 4000),
        # heartbeats trump SDO timeouts (a Stopped node does not answer SDO)
        (
            Evidence(beat=(99.95, 0x04), heartbeat_ms=100, silence_at=99.99, expect_since=1.0),
            True,
            "stopped",
            50,
        ),
        # no heartbeat (1017h = 0): silence is not loss...
        (Evidence(alive_at=10.0, heartbeat_ms=0, expect_since=10.0), True, "unknown", None),
        # ...an SDO timeout after the last sign of life is
        (Evidence(alive_at=10.0, heartbeat_ms=0, silence_at=50.0), False, "unknown", None),
        # ...and any later sign of life brings it back (an EMCY, a PDO, an SDO answer)
        (
            Evidence(alive_at=10.0, activity=60.0, heartbeat_ms=0, silence_at=50.0),
            True,
            "unknown",
            None,
        ),
        # a boot-up alone is no heartbeat: no age, state pre-operational
        (Evidence(beat=(20.0, 0x00), alive_at=10.0, heartbeat_ms=0), True, "pre-operational", None),
    ],
)
def test_online_state_and_age(
    evidence: Evidence, online: bool, state: str, age_ms: int | None
) -> None:
    health = _assess(evidence)
    assert (health.online, health.nmt_state.value, health.heartbeat_age_ms) == (
        online,
        state,
        age_ms,
    )


@pytest.mark.parametrize(
    ("beat", "command", "state"),
    [
        # a command newer than the last heartbeat: the state follows the command
        ((50.0, 0x7F), (60.0, NmtStateName.OPERATIONAL), "operational"),
        # a heartbeat newer than the command has the last word
        ((70.0, 0x7F), (60.0, NmtStateName.OPERATIONAL), "pre-operational"),
        # same instant: the node's own word wins
        ((60.0, 0x04), (60.0, NmtStateName.OPERATIONAL), "stopped"),
        # reset: initialising until the boot-up
        ((50.0, 0x05), (60.0, NmtStateName.INITIALISING), "initialising"),
        ((61.0, 0x00), (60.0, NmtStateName.INITIALISING), "pre-operational"),
        (None, (60.0, NmtStateName.STOPPED), "stopped"),
        (None, None, "unknown"),
    ],
)
def test_state_follows_the_newer_report(
    beat: tuple[float, int] | None, command: tuple[float, NmtStateName] | None, state: str
) -> None:
    evidence = Evidence(beat=beat, command=command, alive_at=40.0, heartbeat_ms=0)
    assert _assess(evidence).nmt_state.value == state


class FakeClock:
    def __init__(self) -> None:
        self.now = 5.0

    def __call__(self) -> float:
        return self.now


@pytest.mark.parametrize(
    ("can_id", "data", "beat", "activity"),
    [
        (0x701, b"\x05", (1, (5.0, 0x05)), None),  # heartbeat Operational
        (0x77F, b"\x7f", (0x7F, (5.0, 0x7F)), None),  # node 127 Pre-operational
        (0x702, b"\x84", (2, (5.0, 0x04)), None),  # node guarding answer, toggle bit set
        (0x703, b"\x00", (3, (5.0, 0x00)), None),  # boot-up
        (0x583, b"\x43\x00\x10\x00\x92\x01\x02\x00", None, 3),  # SDO answer
        (0x081, b"\x00\x10\x01\x00\x00\x00\x00\x00", None, 1),  # EMCY
        (0x18A, b"\x37\x06", None, 10),  # TPDO1
        (0x603, b"\x40\x00\x10\x00\x00\x00\x00\x00", None, None),  # our own SDO request
        (0x080, b"", None, None),  # SYNC
        (0x000, b"\x01\x00", None, None),  # NMT
        (0x701, b"", None, None),  # malformed heartbeat
    ],
)
def test_frame_watch_records_heartbeats_and_signs_of_life(
    can_id: int, data: bytes, beat: tuple[int, tuple[float, int]] | None, activity: int | None
) -> None:
    watch = FrameWatch(FakeClock())
    boots: list[tuple[int, float]] = []
    watch.on_boot = lambda node, when: boots.append((node, when))
    watch.on_message_received(can.Message(arbitration_id=can_id, data=data, is_extended_id=False))
    assert watch.beats == (dict([beat]) if beat else {})
    assert watch.activity == ({activity: 5.0} if activity else {})
    is_boot = beat is not None and beat[1][1] == 0
    assert boots == ([(beat[0], 5.0)] if beat is not None and is_boot else [])


def test_frame_watch_ignores_remote_error_and_extended_frames() -> None:
    watch = FrameWatch(FakeClock())
    for msg in (
        can.Message(arbitration_id=0x701, is_remote_frame=True, is_extended_id=False, dlc=1),
        can.Message(arbitration_id=0x701, data=b"\x05", is_error_frame=True, is_extended_id=False),
        can.Message(arbitration_id=0x701, data=b"\x05", is_extended_id=True),
    ):
        watch.on_message_received(msg)
    assert watch.beats == {}


@pytest.mark.parametrize(
    ("stamp", "seen_at"),
    [
        (999.5, 4.5),  # taken 0.5 s late by a busy notifier thread: when it was on the bus
        (1000.05, 5.0),  # a simulated burst stamped a little ahead: now
        (998.0, 3.0),  # 2 s late: still trusted
        (990.0, 5.0),  # an adapter stamping on an epoch of its own: now
        (1001.0, 5.0),
        (0.0, 5.0),  # no time stamp at all
    ],
)
def test_frame_watch_dates_a_frame_by_its_time_stamp_where_that_is_plausible(
    stamp: float, seen_at: float
) -> None:
    """A boot-up sent before an NMT stop but handed over after it must not count as newer
    than the stop: the adapter's time stamp does not move with the notifier thread."""
    watch = FrameWatch(FakeClock(), wall=lambda: 1000.0)
    msg = can.Message(arbitration_id=0x701, data=b"\x00", is_extended_id=False, timestamp=stamp)
    watch.on_message_received(msg)
    when, state = watch.beats[1]
    assert when == pytest.approx(seen_at)
    assert state == 0
