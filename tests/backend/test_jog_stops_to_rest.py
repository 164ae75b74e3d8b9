"""A jog's stop brings the axis to rest, on ServoDesk's terms: a released torque jog does not
coast on, the stop ramp is never only the client's, the jog says "stopping" until the axis
stands, a torque jog stops at its own speed cap, and a script's jog is protected like a page's.
Asserted on the drives' own readings (606Ch, 6083h, 1016h), against the simulated drives."""

from __future__ import annotations

import asyncio

import pytest

from servodesk.access.actor import Actor, Role, acting
from servodesk.models.safety import JogInfo, JogRequest
from servodesk.motion.jog import NotJogOwnerError, travel_end
from servodesk.motion.lease import Client
from tests.backend.motion_rig import CIA402, KINCO, NODES
from tests.backend.network_rig import eventually
from tests.backend.safety_rig import PAGE, SafetyRig, safety_rig

pytestmark = pytest.mark.anyio

PROFILE_ACCELERATION = 0x6083
QUICK_STOP_DECELERATION = 0x6085
REST_RPM = 5.0  # the settings' jog_rest_rpm


async def hold(rig: SafetyRig, info: JogInfo, seconds: float) -> None:
    """Keep the jog alive as a page does (every 50 ms) for `seconds`."""
    for _ in range(round(seconds / 0.05)):
        rig.keep(info)
        await asyncio.sleep(0.05)


async def held_until_the_server_stops_it(rig: SafetyRig, info: JogInfo) -> JogInfo:
    """Keep the jog alive (as a held button does) until the server stops it by itself."""
    for _ in range(200):
        jog = rig.safety.jogs.get(info.jog_id)
        if jog.state != "running":
            return jog
        rig.keep(info)
        await asyncio.sleep(0.03)
    raise AssertionError(f"node {info.node}: the server never stopped the jog")


async def watch_until_stopped(rig: SafetyRig, info: JogInfo) -> list[tuple[str, float]]:
    """(jog state, |speed| read right after it) until the jog says "stopped"."""
    seen: list[tuple[str, float]] = []
    for _ in range(300):
        state = rig.safety.jogs.get(info.jog_id).state
        rpm = abs((await rig.motion.state(info.node)).velocity_rpm)
        seen.append((state, rpm))
        if state == "stopped":
            return seen
        await asyncio.sleep(0.02)
    raise AssertionError(f"node {info.node}: the jog never came to rest: {seen[-5:]}")


@pytest.mark.parametrize("node", NODES)
async def test_a_released_torque_jog_comes_to_rest_and_says_stopping_until_then(
    node: int,
) -> None:
    """2 % torque held 0.3 s and released (no load: it reaches hundreds of rpm): the axis is
    braked to rest within the distance the drive's quick stop ramp needs, the jog says
    "stopping" while it moves and "stopped" only at rest, and the drive stays enabled."""
    async with safety_rig() as rig:
        await rig.motion.enable(node)
        # a quick stop ramp of 2000 rpm/s, as many machines have (the simulation's default
        # stands the axis within milliseconds: no "stopping" to see)
        gentle = rig.motion.units(node).rpm_s_to_acceleration(2000)
        await rig.write(node, QUICK_STOP_DECELERATION, 0, gentle)
        await rig.widen_switches(node)  # a slow host holds longer: the travel is checked below
        cap = rig.motion.limits(node).max_velocity_rpm  # only the drive's own limit
        request = JogRequest(mode="pt", torque_pct=2.0, keepalive_ms=300, speed_cap_rpm=cap)
        info = await rig.safety.start_jog(node, request, PAGE)
        await hold(rig, info, 0.3)
        released = await rig.motion.state(node)
        assert abs(released.velocity_rpm) > 50, "the torque jog did not move the axis"
        await rig.safety.jogs.stop(info.jog_id, "stopped by the user")
        seen = await watch_until_stopped(rig, info)
        moving = [rpm for state, rpm in seen if rpm >= REST_RPM]
        assert moving, "the axis stood at once: nothing was checked"
        assert all(state == "stopping" for state, rpm in seen if rpm >= REST_RPM), seen
        end = await rig.motion.state(node)
        assert abs(end.velocity_rpm) < REST_RPM
        assert end.state == "operation_enabled", end.fault  # braked, not faulted
        # what a 2000 rpm/s ramp needs from the release speed, plus 0.3 s of latency
        rev_s = abs(released.velocity_rpm) / 60
        allowed = rev_s**2 / (2 * 2000 / 60) + rev_s * 0.3 + 0.5
        travelled = abs(end.position_rev - released.position_rev)
        assert travelled < allowed, f"{travelled:.2f} rev after the release ({allowed:.2f})"


async def test_a_stop_on_lost_control_never_brakes_on_the_client_s_slow_ramp() -> None:
    """A jog taken over with a 1 rpm/s ramp at 300 rpm, then left without keep-alives: the
    stop writes ServoDesk's deceleration (at least the floor, or the drive's 6085h) before
    the halt, so the axis is at rest in well under a second instead of five minutes."""
    async with safety_rig() as rig:
        node = KINCO
        info = await rig.jog(node, rpm=300)
        slow = JogRequest(mode="pv", velocity_rpm=300, acceleration_rpm_s=1.0, keepalive_ms=100)
        again = await rig.safety.start_jog(node, slow, PAGE)
        assert again.stop_deceleration_rpm_s is not None
        assert again.stop_deceleration_rpm_s >= 1000  # the settings' floor
        assert rig.safety.jogs.get(info.jog_id).state == "stopped"  # replaced, not stopped
        seen = await watch_until_stopped(rig, again)  # no keep-alive: it stops by itself
        stopped = rig.safety.jogs.get(again.jog_id)
        assert stopped.stop_reason is not None
        assert stopped.stop_reason.startswith("keep-alive missed")
        assert len(seen) < 100, f"still moving after {len(seen)} readings"
        ramp = await rig.read(node, PROFILE_ACCELERATION, signed=False)
        one_rpm_s = rig.motion.units(node).rpm_s_to_acceleration(1.0)
        assert ramp > 100 * one_rpm_s, "the stop ramp is still the client's"


async def test_a_torque_jog_stops_at_servodesk_s_own_speed_cap() -> None:
    async with safety_rig() as rig:
        node = CIA402
        await rig.motion.enable(node)
        await rig.widen_switches(node)
        request = JogRequest(mode="pt", torque_pct=2.0, keepalive_ms=300, speed_cap_rpm=100)
        info = await rig.safety.start_jog(node, request, PAGE)
        assert info.speed_cap_rpm == 100
        stopped = await held_until_the_server_stops_it(rig, info)
        assert stopped.stop_reason is not None
        assert stopped.stop_reason.startswith("speed cap 100 rpm passed"), stopped
        await watch_until_stopped(rig, info)


async def test_a_torque_jog_without_a_cap_gets_the_default_one() -> None:
    async with safety_rig() as rig:
        await rig.motion.enable(CIA402)
        request = JogRequest(mode="pt", torque_pct=1.0, keepalive_ms=300)
        info = await rig.safety.start_jog(CIA402, request, PAGE)
        assert info.speed_cap_rpm == 300  # the settings' jog_pt_speed_cap_rpm
        await rig.safety.jogs.stop(info.jog_id, "test")
        await watch_until_stopped(rig, info)


async def test_a_script_s_jog_has_an_owner_and_the_drive_s_own_protection() -> None:
    """A jog without a client id holds the drive with the heartbeat consumer set (the drive
    stops by itself if ServoDesk dies) until its axis is at rest; then 1016h is restored."""
    async with safety_rig() as rig:
        node = CIA402
        await rig.motion.enable(node)
        await rig.widen_switches(node)
        script = Client.anonymous_one()
        request = JogRequest(mode="pv", velocity_rpm=200, keepalive_ms=300)
        info = await rig.safety.start_jog(node, request, script)
        assert info.owner is not None
        assert info.owner.startswith("script-")
        held = rig.safety.controller(node, script)
        assert held.holder is not None
        assert held.holder.client_id == info.owner
        assert held.protection.active, held.protection.message
        consumer = await rig.read(node, 0x1016, 1, signed=False)
        assert consumer >> 16 == rig.safety.heartbeat.status(node).tool_node_id
        rig.safety.keepalive(info.jog_id, script)  # the script's own keep-alive counts
        await rig.safety.jogs.stop(info.jog_id, "stopped by the script")
        await watch_until_stopped(rig, info)
        await eventually(  # the release is written once the axis is at rest
            lambda: rig.safety.controller(node, script).holder is None, what="released"
        )
        released = rig.safety.controller(node, script)
        assert released.holder is None
        assert not released.protection.active
        assert await rig.read(node, 0x1016, 1, signed=False) >> 16 == 0


async def test_keepalives_count_only_from_the_jog_s_owner() -> None:
    async with safety_rig() as rig:
        info = await rig.jog(CIA402)
        with acting(Actor("viewer", Role.VIEWER)), pytest.raises(NotJogOwnerError):
            rig.safety.keepalive(info.jog_id, Client(id=PAGE.id))  # another login, same id
        with pytest.raises(NotJogOwnerError):
            rig.safety.keepalive(info.jog_id, Client(id="another-page"))
        rig.safety.keepalive(info.jog_id, PAGE)
        assert rig.safety.jogs.get(info.jog_id).state == "running"
        await rig.safety.jogs.stop(info.jog_id, "test")
        await watch_until_stopped(rig, info)


@pytest.mark.parametrize(
    ("rev", "reach", "limits", "stops"),
    [
        (1.0, 0.5, (None, 2.0), False),  # the stop ends inside
        (1.6, 0.5, (None, 2.0), True),  # it would end beyond: stop now
        (2.5, -0.5, (None, 2.0), False),  # moving back into the travel
        (2.5, 0.0, (None, 2.0), False),  # standing: nothing to stop
        (-1.6, -0.5, (-2.0, None), True),
        (-1.6, 0.5, (-2.0, None), False),
        (0.0, 100.0, (None, None), False),  # no limits set
    ],
)
def test_travel_end_stops_where_braking_would_pass_the_limit(
    rev: float, reach: float, limits: tuple[float | None, float | None], stops: bool
) -> None:
    assert (travel_end(rev, reach, limits) is not None) is stops


async def test_a_jog_stops_inside_servodesk_s_travel_limits() -> None:
    """Travel limits set on the Drive page hold for a PV jog too: it is stopped early enough
    for its deceleration to end inside them."""
    async with safety_rig() as rig:
        node = CIA402
        await rig.motion.enable(node)
        await rig.widen_switches(node)
        start = (await rig.motion.state(node)).position_rev
        limits = rig.motion.limits(node).model_copy(update={"max_position_rev": start + 2.0})
        rig.motion.set_limits(node, limits)
        request = JogRequest(mode="pv", velocity_rpm=300, keepalive_ms=300)
        info = await rig.safety.start_jog(node, request, PAGE)
        stopped = await held_until_the_server_stops_it(rig, info)
        assert stopped.stop_reason is not None
        assert stopped.stop_reason.startswith("ServoDesk's travel limit"), stopped
        await watch_until_stopped(rig, info)
        end = (await rig.motion.state(node)).position_rev
        assert start + 0.5 < end <= start + 2.0, f"stopped at {end - start:.3f} rev"
