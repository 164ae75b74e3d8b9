"""The plant alone: control cascade, torque limit, determinism, unit conversions, publishing."""

from __future__ import annotations

import math

import pytest

from servodesk_sim.plant import (
    ControlKind,
    Plant,
    PlantCommand,
    PlantParams,
    Scaling,
    publish_feedback,
    read_or,
    wrap_int32,
)
from servodesk_sim.values import DictValues

DT = 0.001
INC = 131072


def run(plant: Plant, command: PlantCommand, seconds: float) -> list[float]:
    torques = []
    for _ in range(round(seconds / DT)):
        plant.step(DT, command)
        torques.append(plant.torque)
    return torques


@pytest.mark.parametrize("step_inc", [100.0, -1000.0, 20000.0])
def test_position_step_settles_on_the_target(step_inc: float) -> None:
    plant = Plant()
    run(plant, PlantCommand(ControlKind.POSITION, position=step_inc), 0.4)
    assert plant.position == pytest.approx(step_inc, abs=0.5)
    assert abs(plant.rpm) < 0.01


def test_position_step_does_not_overshoot_much() -> None:
    plant = Plant()
    peak = 0.0
    for _ in range(400):
        plant.step(DT, PlantCommand(ControlKind.POSITION, position=10000.0))
        peak = max(peak, plant.position)
    assert peak < 10000.0 * 1.05


@pytest.mark.parametrize("limit", [300, 1000, 3000])
def test_torque_saturates_at_the_max_torque(limit: int) -> None:
    plant = Plant()
    torques = run(
        plant, PlantCommand(ControlKind.POSITION, position=20 * INC, torque_limit=limit), 0.05
    )
    assert max(abs(t) for t in torques) == pytest.approx(limit)
    assert torques[0] == pytest.approx(limit)  # a big step asks for more than allowed


def test_velocity_loop_reaches_and_holds_the_speed() -> None:
    plant = Plant()
    run(plant, PlantCommand(ControlKind.VELOCITY, velocity=1000 * INC / 60), 0.3)
    assert plant.rpm == pytest.approx(1000.0, abs=0.5)


def test_torque_mode_is_capped_at_the_speed_limit() -> None:
    plant = Plant()
    limit = 3000 * INC / 60
    speeds = []
    for _ in range(2000):
        plant.step(DT, PlantCommand(ControlKind.TORQUE, torque=1000, velocity_limit=limit))
        speeds.append(plant.rpm)
    assert max(speeds) <= 3000.0
    assert speeds[-1] > 2900.0  # it does get up to the limit ("进入调速阶段")
    assert plant.torque < 1000  # and only uses the torque it needs there


def test_torque_mode_below_the_limit_applies_the_torque() -> None:
    plant = Plant()
    plant.step(DT, PlantCommand(ControlKind.TORQUE, torque=-500, velocity_limit=3000 * INC / 60))
    assert plant.torque == pytest.approx(-500)
    assert plant.rpm < 0.0


def test_off_coasts_down_through_friction() -> None:
    plant = Plant()
    run(plant, PlantCommand(ControlKind.VELOCITY, velocity=600 * INC / 60), 0.2)
    run(plant, PlantCommand(ControlKind.OFF), 0.5)
    assert plant.torque == 0.0
    time_constant = 1.0e-4 / 2.0e-4  # inertia / viscous friction
    assert 0.0 < plant.rpm < 600.0 * math.exp(-0.5 / time_constant) * 1.01


def test_constant_load_torque_is_held_by_the_integrator() -> None:
    plant = Plant(PlantParams(load_torque=0.5))
    run(plant, PlantCommand(ControlKind.POSITION, position=0.0), 1.0)
    assert plant.position == pytest.approx(0.0, abs=1.0)
    assert plant.torque == pytest.approx(0.5 / 1.27 * 1000, rel=0.01)


def test_same_inputs_give_identical_outputs() -> None:
    trace = []
    for _ in range(2):
        plant = Plant(position=123.0)
        samples = []
        for n in range(300):
            command = PlantCommand(ControlKind.POSITION, position=50.0 * n, velocity=50000.0)
            plant.step(DT, command)
            samples.append((plant.position, plant.velocity, plant.torque))
        trace.append(samples)
    assert trace[0] == trace[1]


def test_substeps_follow_max_substep() -> None:
    coarse = Plant(PlantParams(max_substep=1e-3))
    fine = Plant()
    command = PlantCommand(ControlKind.VELOCITY, velocity=100 * INC / 60)
    coarse.step(DT, command)
    fine.step(DT, command)
    assert coarse.velocity != fine.velocity  # two half steps are not one whole step


@pytest.mark.parametrize(
    ("scaling", "increments", "user"),
    [
        (Scaling(), INC, 100000.0),
        (Scaling(), -INC / 2, -50000.0),
        (Scaling(INC, 360), INC, 360.0),
        (Scaling(reversed=True), INC, -100000.0),
    ],
)
def test_scaling_converts_both_ways(scaling: Scaling, increments: float, user: float) -> None:
    assert scaling.to_user(increments) == pytest.approx(user)
    assert scaling.to_increments(user) == pytest.approx(increments)


def test_scaling_rpm_in_user_units() -> None:
    assert Scaling().rpm_to_user(60.0) == pytest.approx(100000.0)  # 1 rev/s
    assert Scaling().user_to_rpm(100000.0) == pytest.approx(60.0)


@pytest.mark.parametrize(
    ("stored", "expected"),
    [
        ({}, Scaling()),
        ({(0x6091, 1): 4 * INC, (0x6091, 2): 1000}, Scaling(4 * INC, 1000)),
        ({(0x6091, 1): 0, (0x6091, 2): 1000}, Scaling()),  # a zero half keeps the default
        ({(0x607E, 0): 1}, Scaling(reversed=True)),
        ({(0x607E, 0): 0x80}, Scaling(reversed=True)),
    ],
)
def test_scaling_read_from_the_objects(
    stored: dict[tuple[int, int], int], expected: Scaling
) -> None:
    assert Scaling.read(DictValues(stored)) == expected


@pytest.mark.parametrize(
    ("value", "expected"),
    [(0, 0), (2**31 - 1, 2**31 - 1), (2**31, -(2**31)), (-(2**31) - 1, 2**31 - 1), (1.6, 2)],
)
def test_wrap_int32(value: float, expected: int) -> None:
    assert wrap_int32(value) == expected


def test_read_or_falls_back_only_for_missing_objects() -> None:
    values = DictValues({(0x6081, 0): 5})
    assert read_or(values, 0x6081, 0, 9) == 5
    assert read_or(values, 0x6083, 0, 9) == 9


def test_publish_feedback_uses_gear_ratio_polarity_and_origin() -> None:
    plant = Plant(position=2 * INC)
    values = DictValues()
    scaling = Scaling(INC, 10000, reversed=True)
    publish_feedback(values, plant, scaling, origin=INC / 2, demand=-15100.0)
    assert values.get(0x6063) == 3 * INC // 2  # internal increments from the origin
    assert values.get(0x6064) == -15000  # 1.5 rev, reversed, 10000 units/rev
    assert values.get(0x60F4) == -100  # demand - actual
    assert values.get(0x606C) == 0
    assert values.get(0x6077) == 0


def test_publish_feedback_velocity_and_torque_in_user_direction() -> None:
    plant = Plant()
    run(plant, PlantCommand(ControlKind.VELOCITY, velocity=500 * INC / 60), 0.3)
    values = DictValues()
    publish_feedback(values, plant, Scaling(reversed=True), origin=0.0, demand=0.0)
    assert values.get(0x606C) == -500
    plant.step(DT, PlantCommand(ControlKind.TORQUE, torque=250))
    publish_feedback(values, plant, Scaling(reversed=True), origin=0.0, demand=0.0)
    assert values.get(0x6077) == -250


def test_a_profile_is_tracked_without_lag_or_overshoot() -> None:
    # The feed-forward lets the loops follow a ramp to 1000 rpm at 1e7 increments/s².
    plant = Plant()
    plant.step(DT, PlantCommand(ControlKind.POSITION))  # enabled at standstill first
    top = 1000 * INC / 60
    position = velocity = 0.0
    worst = peak = 0.0
    for _ in range(300):
        new_velocity = min(velocity + 1.0e7 * DT, top)
        position += 0.5 * (velocity + new_velocity) * DT
        velocity = new_velocity
        plant.step(DT, PlantCommand(ControlKind.POSITION, position=position, velocity=velocity))
        worst = max(worst, abs(position - plant.position))
        peak = max(peak, plant.rpm)
    assert worst < 5.0  # increments
    assert peak < 1000.05
    assert plant.rpm == pytest.approx(1000.0, abs=0.01)
