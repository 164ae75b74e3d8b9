"""Pure cores of the motion service, table-tested: units both ways, statusword bits and
transitions in words, homing progress, planned IP paths, the "why won't it enable" explainer."""

from __future__ import annotations

import pytest

from servodesk.models.motion import FaultInfo
from servodesk.motion.explain import Observed, explain
from servodesk.motion.homing import METHODS, homing_phase, methods_for
from servodesk.motion.trajectory import planned_offset, setpoints, sync_jitter
from servodesk.motion.units import DriveUnits
from servodesk.motion.words import TRANSITION_TEXTS, mode_key, status_bits, transition
from servodesk_protocol.cia402 import Cia402State as S

DEFAULT = DriveUnits()  # 131072 inc/rev, 6091h 131072 : 100000
GEARED = DriveUnits.of(131072, (131072 * 3, 100000))  # 3 motor revs per 100000 user units


@pytest.mark.parametrize(
    ("units", "rev", "user", "inc"),
    [
        (DEFAULT, 1.0, 100000, 131072),
        (DEFAULT, -0.5, -50000, -65536),
        (DEFAULT, 0.0, 0, 0),
        (GEARED, 3.0, 100000, 393216),
    ],
)
def test_positions_convert_both_ways(units: DriveUnits, rev: float, user: int, inc: int) -> None:
    assert units.rev_to_user(rev) == user
    assert units.user_to_rev(user) == pytest.approx(rev)
    assert units.user_to_inc(user) == inc
    assert units.inc_to_user(inc) == user
    assert units.inc_to_rev(inc) == pytest.approx(rev)


@pytest.mark.parametrize(
    ("rpm", "velocity", "rpm_s", "acceleration"),
    [
        (60.0, 100000, 60.0, 100),  # 1 rev/s = 100000 units/s; 1 rev/s² = 100 units/s/ms
        (3000.0, 5000000, 6000.0, 10000),
        (-300.0, -500000, 0.001, 1),  # an acceleration never rounds to 0
    ],
)
def test_velocity_and_acceleration(
    rpm: float, velocity: int, rpm_s: float, acceleration: int
) -> None:
    assert DEFAULT.rpm_to_velocity(rpm) == velocity
    assert DEFAULT.velocity_to_rpm(velocity) == pytest.approx(rpm)
    assert DEFAULT.rpm_s_to_acceleration(rpm_s) == acceleration


@pytest.mark.parametrize(("pct", "raw"), [(100.0, 1000), (5.5, 55), (-12.3, -123)])
def test_torque_in_tenths_of_a_percent(pct: float, raw: int) -> None:
    assert DriveUnits.pct_to_torque(pct) == raw
    assert DriveUnits.torque_to_pct(raw) == pytest.approx(pct)


def test_velocity_actual_in_rpm_or_in_user_units() -> None:
    assert DEFAULT.actual_velocity_rpm(1500) == 1500.0
    generic = DriveUnits.of(None, None, velocity_actual_rpm=False)
    assert generic.actual_velocity_rpm(100000) == pytest.approx(60.0)


def test_missing_or_zero_gear_keeps_the_default() -> None:
    assert DriveUnits.of(None, (0, 100000)).gear == (131072, 100000)
    assert DriveUnits.of(4096, None).counts_per_rev == 4096


@pytest.mark.parametrize(
    ("before", "after", "words"),
    [
        (S.SWITCH_ON_DISABLED, S.READY_TO_SWITCH_ON, "shutdown (2)"),
        (S.READY_TO_SWITCH_ON, S.SWITCHED_ON, "switch on (3)"),
        (S.SWITCHED_ON, S.OPERATION_ENABLED, "enable operation (4)"),
        (S.READY_TO_SWITCH_ON, S.OPERATION_ENABLED, "switch on and enable operation (3, 4)"),
        (S.OPERATION_ENABLED, S.QUICK_STOP_ACTIVE, "quick stop (11)"),
        (S.QUICK_STOP_ACTIVE, S.OPERATION_ENABLED, "enable operation (16)"),
        (S.OPERATION_ENABLED, S.FAULT, "fault (13)"),
        (S.FAULT, S.SWITCH_ON_DISABLED, "fault reset (15)"),
        (S.SWITCHED_ON, S.SWITCHED_ON, None),
        (S.SWITCH_ON_DISABLED, S.OPERATION_ENABLED, "Switch on disabled → Operation enabled"),
    ],
)
def test_transition_names(before: S, after: S, words: str | None) -> None:
    taken = transition(before, after)
    assert (taken.message if taken else None) == words
    if taken is not None:  # the same words by id, for the page's catalogue
        assert TRANSITION_TEXTS[taken.message_id].format(**taken.params) == words


def test_status_bits_are_named_for_the_mode() -> None:
    pp = status_bits(0x1637, 1)
    assert [b.bit for b in pp if b.on] == [0, 1, 2, 4, 5, 9, 10, 12]
    assert pp[12].name == "set-point acknowledge"
    assert status_bits(0x1637, 6)[12].name == "homing attained"
    assert status_bits(0x8000, 6, reference_found_bit15=True)[15].name == "reference found"


@pytest.mark.parametrize(
    ("value", "key"), [(1, "pp"), (3, "pv"), (4, "pt"), (6, "hm"), (7, "ip"), (0, None), (-3, "-3")]
)
def test_mode_keys(value: int, key: str | None) -> None:
    assert mode_key(value) == key


@pytest.mark.parametrize(
    ("statusword", "phase"),
    [
        (0x0237, "running"),  # 13/12/10 = 0/0/0
        (0x0637, "interrupted"),  # 0/0/1
        (0x1237, "running"),  # 0/1/0: home found, still stopping
        (0x1637, "attained"),  # 0/1/1
        (0x2637, "error"),  # 1/0/1
    ],
)
def test_homing_phase(statusword: int, phase: str) -> None:
    assert homing_phase(statusword)[0] == phase


def test_homing_methods_have_paths() -> None:
    assert [m.method for m in methods_for(frozenset({35, 17, 99}))] == [17, 35]
    assert [(s.direction, s.speed) for s in METHODS[27].path] == [
        ("negative", "fast"),
        ("positive", "slow"),
    ]
    assert METHODS[35].path == []


@pytest.mark.parametrize("trajectory", ["point_to_point", "sine"])
def test_planned_paths_start_and_end_at_rest(trajectory: str) -> None:
    end = 1000.0 if trajectory == "point_to_point" else 0.0
    assert planned_offset(trajectory, 0.0, 2.0, 1000.0) == 0.0  # type: ignore[arg-type]
    assert planned_offset(trajectory, 2.0, 2.0, 1000.0) == pytest.approx(end)  # type: ignore[arg-type]
    assert planned_offset(trajectory, 1.0, 2.0, 1000.0) == pytest.approx(  # type: ignore[arg-type]
        500.0 if trajectory == "point_to_point" else 1000.0
    )


def test_setpoints_one_per_period_one_period_ahead() -> None:
    points = setpoints("point_to_point", 100, 1000.0, 0.1, 0.01)
    assert len(points) == 10
    assert points[-1] == 1100
    assert points[4] == 100 + round(planned_offset("point_to_point", 0.05, 0.1, 1000.0))


def test_sync_jitter() -> None:
    assert sync_jitter([0.0, 0.002, 0.0045, 0.0065], 0.002) == pytest.approx((0.0005, 0.0025))
    assert sync_jitter([1.0], 0.002) == (0.0, 0.0)


SOD, RTSO, OE, QSA, FAULT = 0x0250, 0x0231, 0x0237, 0x0217, 0x0218
ALARM_4 = FaultInfo(code=4, code_hex="0x0004", name="Following error too large", text="gains")


@pytest.mark.parametrize(
    ("seen", "codes"),
    [
        (Observed(None, None, "stopped"), ["nmt_stopped"]),
        (Observed(None, None, "unknown"), ["timeout"]),
        (Observed(SOD, 0x06, "operational", needs_pdos=True), ["timeout"]),
        (Observed(SOD, 0x06, "pre-operational", needs_pdos=True), ["nmt_not_operational"]),
        (Observed(FAULT, 0x00, "operational", fault=ALARM_4), ["fault"]),
        (Observed(FAULT, 0x80, "operational"), ["fault", "fault_reset_high"]),
        (Observed(SOD & ~0x10, 0x06, "operational"), ["voltage_disabled"]),
        (Observed(0x0000, 0x06, "operational"), ["not_ready"]),
        (Observed(QSA, 0x02, "operational"), ["quick_stop_active"]),
        (Observed(OE, 0x10F, "operational"), ["halt_set"]),
        (Observed(OE, 0x0F, "operational", mode=2, mode_display=0), ["mode_unsupported"]),
        (
            Observed(OE, 0x0F, "operational", mode=9, mode_display=1, supported=frozenset({1, 3})),
            ["mode_unsupported"],
        ),
        (Observed(RTSO, 0x06, "pre-operational", held_by="browser A"), ["held_by_other"]),
    ],
)
def test_explainer_names_the_cause(seen: Observed, codes: list[str]) -> None:
    assert [reason.code for reason in explain(seen)] == codes


def test_explainer_words_carry_the_decoded_fault() -> None:
    (reason,) = explain(Observed(FAULT, 0, "operational", fault=ALARM_4))
    assert "0x0004 Following error too large" in reason.message
    assert "gains" in reason.message
