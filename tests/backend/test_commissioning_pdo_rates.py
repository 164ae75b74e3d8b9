"""The pdo step's pure judgements: the rate each TPDO promises (CiA 301 transmission types,
event timer, inhibit time, SYNC), the verdict on a measured rate, the listening window, and
what a mode needs that the mapping lacks."""

from __future__ import annotations

import pytest

from servodesk.commissioning import pdo_rates as rates
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo_problems import PdoKind


def tpdo(kind: int, *, timer: int = 0, inhibit: int = 0, valid: bool = True) -> PdoConfig:
    return PdoConfig(
        "tpdo", 1, 0x181, valid, kind, inhibit_time_100us=inhibit, event_timer_ms=timer,
        mapping=(MappedObject(0x6041, 0, 16, "Statusword"),),
    )  # fmt: skip


@pytest.mark.parametrize(
    ("pdo", "sync_us", "rate", "exact", "words"),
    [
        (tpdo(255, timer=100), None, 10.0, False, "event timer 100 ms"),
        (tpdo(254, timer=20), 10_000, 50.0, False, "event timer 20 ms"),
        (tpdo(255), None, None, False, "on change only"),
        (tpdo(1), 10_000, 100.0, True, "every SYNC of 10 ms"),
        (tpdo(2), 10_000, 50.0, True, "every 2nd SYNC of 10 ms"),
        (tpdo(3), 2_000, 1e6 / 6000, True, "every 3rd SYNC of 2 ms"),
        (tpdo(11), 1_000, 1e6 / 11_000, True, "every 11th SYNC"),
        (tpdo(1), None, None, False, "no SYNC is on the bus"),
        (tpdo(0), 10_000, None, False, "after a change"),
        (tpdo(253), None, None, False, "on request only"),
    ],
)
def test_expected_rate(
    pdo: PdoConfig, sync_us: int | None, rate: float | None, exact: bool, words: str
) -> None:
    expected = rates.expected_rate(pdo, sync_us)
    assert expected.rate_hz == pytest.approx(rate) if rate else expected.rate_hz is None
    assert expected.exact is exact
    assert words in expected.basis


EVERY_100MS = rates.expected_rate(tpdo(255, timer=100), None)
EVERY_SYNC = rates.expected_rate(tpdo(1), 10_000)
CAPPED = rates.expected_rate(tpdo(255, timer=100, inhibit=500), None)  # ≥ 50 ms apart: ≤ 20 Hz


@pytest.mark.parametrize(
    ("expected", "frames", "rate", "ok", "words"),
    [
        (EVERY_100MS, 20, 10.0, True, "10 Hz (expected 10 Hz)"),
        (EVERY_100MS, 30, 15.0, True, "15 Hz"),  # sent on change too: more is fine
        (EVERY_100MS, 10, 5.0, False, "below the expected 10 Hz"),
        (EVERY_100MS, 0, None, False, "not seen in 2 s"),
        (EVERY_100MS, 1, None, False, "one frame"),
        (EVERY_SYNC, 200, 99.0, True, "99 Hz"),
        (EVERY_SYNC, 400, 200.0, False, "above what expected"),
        (CAPPED, 60, 30.0, False, "its inhibit time allows"),
        (CAPPED, 36, 18.0, True, "18 Hz"),
        (rates.expected_rate(tpdo(255), None), 0, None, True, "none seen"),
        (rates.expected_rate(tpdo(1), None), 0, None, False, "start SYNC"),
    ],
)
def test_judge(
    expected: rates.Expected, frames: int, rate: float | None, ok: bool, words: str
) -> None:
    verdict = rates.judge(expected, frames, rate, 2.0)
    assert verdict.ok is ok
    assert words in verdict.text


def test_window_listens_three_of_the_slowest_periods_within_bounds() -> None:
    assert rates.window_s([]) == rates.MIN_WINDOW_S
    assert rates.window_s([EVERY_100MS, EVERY_SYNC]) == rates.MIN_WINDOW_S
    slow = rates.expected_rate(tpdo(255, timer=1500), None)
    assert rates.window_s([EVERY_100MS, slow]) == pytest.approx(4.5)
    glacial = rates.expected_rate(tpdo(255, timer=60_000), None)
    assert rates.window_s([glacial]) == rates.MAX_WINDOW_S


def test_missing_objects_counts_valid_pdos_of_the_right_direction_only() -> None:
    status = MappedObject(0x6041, 0, 16, "Statusword")
    target = MappedObject(0x60FF, 0, 32, "Target velocity")
    mapped = [
        tpdo(255, timer=100),
        PdoConfig("rpdo", 2, 0x301, False, 255, mapping=(target,)),  # not valid
        PdoConfig("tpdo", 2, 0x281, True, 255, mapping=(target,)),  # the wrong direction
    ]
    needs: dict[PdoKind, list[MappedObject]] = {"rpdo": [target], "tpdo": [status]}
    assert rates.missing_objects(needs, mapped) == ["60FFh:00 Target velocity (RPDO)"]
    assert rates.missing_objects({"tpdo": [status]}, mapped) == []
