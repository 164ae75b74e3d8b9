"""stop_test: a quick stop from a chosen speed and a keep-alive loss stop, each measured from a
scope capture (606Ch, 6064h, 6041h) against what the drive's quick stop deceleration predicts.

1. Quick stop: a PV jog at the chosen speed, steady; the quick stop through the motion safety
   layer (the node's priority lane, as the Drive page's button); stop time from the moment it
   was sent to |606Ch| < the rest threshold, stop distance over that time; predicted from 6085h
   (or 6084h where 605Ah says the quick stop ramps on it): t = v/a, d = v²/2a.
2. Keep-alive loss: a jog the other way, its keep-alives stopped once it runs steady; the jog
   watchdog stops it by itself. Measured from the last keep-alive; predicted: the keep-alive
   window at speed, then the deceleration the tool's own stop uses (the steeper of the jog's
   stop ramp and 6085h, motion/jog.py).
The axis is left stopped, disabled and released, whatever happens (axis_run.AxisRun)."""

from __future__ import annotations

import time
from typing import Any

from servodesk.commissioning import stop_figures as sf
from servodesk.commissioning.axis_run import (
    POSITION_ACTUAL,
    VELOCITY_ACTUAL,
    AxisRun,
    StepError,
)
from servodesk.commissioning.evidence import Outcome
from servodesk.commissioning.reads import read_listed
from servodesk.models.safety import JogRequest
from servodesk.scope.units import drive_units
from servodesk_protocol.cia402 import QUICK_STOP_OPTION, STATUSWORD

DEFAULT_SPEED_RPM = 200.0  # a jog any commissioned axis takes; capped below by its limits
SPEED_SHARE = 0.5  # the default never above half the speed limit in force
KEEPALIVE_MS = 200  # the keep-alive loss jog's window: short, so the axis runs on little
QUICK_STOP_DECELERATION = 0x6085  # Quick stop deceleration
PROFILE_DECELERATION = 0x6084  # Profile deceleration
# 605Ah options that ramp on 6084h; 3, 4, 7, 8 brake at the torque limit, 0 coasts (no ramp)
ON_PROFILE_DECELERATION = (1, 5)
ON_QUICK_STOP_DECELERATION = (2, 6)
SIGNALS = (VELOCITY_ACTUAL, POSITION_ACTUAL, STATUSWORD)


async def _decelerations(run: AxisRun) -> tuple[dict[str, Any], float | None]:
    """605Ah, 6085h and 6084h as read, and the deceleration (rpm/s) the quick stop ramps on.
    Read while the jog runs: the jog's own ramp is in 6084h then, which 605Ah 1/5 stops on."""
    objects = [(QUICK_STOP_OPTION, 0), (QUICK_STOP_DECELERATION, 0), (PROFILE_DECELERATION, 0)]
    read = {v["index"]: v.get("value") for v in await read_listed(
        run.access, run.sdo, run.node, objects
    )}  # fmt: skip
    units = await drive_units(run.access, run.node)
    option = read.get(QUICK_STOP_OPTION)
    quick = read.get(QUICK_STOP_DECELERATION)
    profile = read.get(PROFILE_DECELERATION)
    info: dict[str, Any] = {"quick_stop_option": option, "6085h": quick, "6084h": profile}
    if isinstance(quick, int) and quick > 0:
        info["quick_stop_deceleration_rpm_s"] = round(units.acceleration_to_rpm_s(quick), 3)
    source, raw = "6085h", quick
    if isinstance(option, int) and option in ON_PROFILE_DECELERATION:
        source, raw = "6084h", profile
    elif isinstance(option, int) and option not in ON_QUICK_STOP_DECELERATION:
        info["prediction"] = (
            f"605Ah = {option}: the quick stop does not ramp on 6085h (0 coasts, 3/4/7/8 brake "
            "at the torque limit); the time is measured, not held against a prediction"
        )
        return info, None
    if not isinstance(raw, int) or raw <= 0:
        info["prediction"] = f"{source} could not be read: no prediction"
        return info, None
    rpm_s = units.acceleration_to_rpm_s(raw)
    info.update(deceleration_object=source, deceleration_rpm_s=round(rpm_s, 3))
    return info, rpm_s


def _speed(run: AxisRun, asked: float | None) -> float:
    limit = run.safety.motion.limits(run.node).max_velocity_rpm
    if asked is None:
        return min(DEFAULT_SPEED_RPM, limit * SPEED_SHARE)
    if asked > limit:
        raise StepError(f"speed_rpm {asked:g} is above the speed limit in force, {limit:g} rpm")
    return asked


async def _direction(run: AxisRun) -> float:
    """+1 or −1: toward the end of travel that is farther away (limit switches, 607Dh,
    ServoDesk's travel limits), + when none is known."""
    state = await run.safety.motion.state(run.node)
    at = state.position_rev
    lows: list[float] = []
    highs: list[float] = []
    travel = state.travel
    for ends in (travel.switches, travel.software_limit) if travel else ():
        if ends is not None:
            lows += [] if ends.min_rev is None else [ends.min_rev]
            highs += [] if ends.max_rev is None else [ends.max_rev]
    limits = state.limits
    lows += [] if limits.min_position_rev is None else [limits.min_position_rev]
    highs += [] if limits.max_position_rev is None else [limits.max_position_rev]
    room_up = min(highs) - at if highs else float("inf")
    room_down = at - max(lows) if lows else float("inf")
    return 1.0 if room_up >= room_down else -1.0


def _ramp_timeout(rpm: float, run: AxisRun) -> float:
    accel = run.settings.motion_default_acceleration_rpm_s
    return abs(rpm) / accel * 3 + 5.0  # generous: a busy PC reads the drive late


async def _quick_stop(run: AxisRun, rpm: float) -> dict[str, Any]:
    safety, node = run.safety, run.node
    capture = await run.start_capture(f"commissioning: quick stop node {node}", SIGNALS)
    await safety.motion.enable(node)
    jog = await safety.start_jog(node, JogRequest(mode="pv", velocity_rpm=rpm), run.client)
    async with run.keepalives(jog):
        await run.wait_steady(rpm, _ramp_timeout(rpm, run))
        decelerations, decel = await _decelerations(run)
        steady = await run.wait_steady(rpm, _ramp_timeout(rpm, run))
        sent_at = time.time()
        await safety.quick_stop(node)
    allowed = sf.predict(steady, decel)[0]
    rested = await run.wait_rest((allowed or 0.0) * sf.MARGIN_FACTOR + 10.0)
    capture, series = await run.end_capture(capture.id)
    figures = sf.stop_figures(
        series.get(VELOCITY_ACTUAL, sf.Series.of([], [])),
        series.get(POSITION_ACTUAL, sf.Series.of([], [])),
        sent_at,
        rest_rpm=run.rest_rpm,
        deceleration_rpm_s=decel,
    )
    return {
        "capture_id": capture.id,
        "sync_period_us": capture.sync_period_us,
        "speed_rpm": rpm,
        "sent_at": sent_at,
        "rest_at": figures.rest_at,
        "read_at_rest": rested,
        "deceleration": decelerations,
        "figures": figures,
    }


async def _keepalive_loss(run: AxisRun, rpm: float, decel: float | None) -> dict[str, Any]:
    safety, node = run.safety, run.node
    capture = await run.start_capture(f"commissioning: keep-alive loss node {node}", SIGNALS)
    await safety.motion.enable(node)
    request = JogRequest(mode="pv", velocity_rpm=rpm, keepalive_ms=KEEPALIVE_MS)
    jog = await safety.start_jog(node, request, run.client)
    async with run.keepalives(jog) as sent:
        await run.wait_steady(rpm, _ramp_timeout(rpm, run))
    last = sent[-1]  # no keep-alive after this one: the watchdog must stop the axis
    info = await run.wait_jog_stopped(jog.jog_id, KEEPALIVE_MS / 1000 + 15.0)
    capture, series = await run.end_capture(capture.id)
    # the tool's own stop (a halt) brakes on the steeper of the jog's stop ramp and 6085h
    used = max(info.stop_deceleration_rpm_s or 0.0, decel or 0.0) or None
    figures = sf.stop_figures(
        series.get(VELOCITY_ACTUAL, sf.Series.of([], [])),
        series.get(POSITION_ACTUAL, sf.Series.of([], [])),
        last,
        rest_rpm=run.rest_rpm,
        deceleration_rpm_s=used,
        delay_s=KEEPALIVE_MS / 1000,
    )
    return {
        "capture_id": capture.id,
        "sync_period_us": capture.sync_period_us,
        "speed_rpm": rpm,
        "keepalive_ms": KEEPALIVE_MS,
        "last_keepalive_at": last,
        "rest_at": figures.rest_at,
        "jog_state": info.state,
        "stop_reason": info.stop_reason,
        "stop_deceleration_rpm_s": used,
        "figures": figures,
    }


def _public(part: dict[str, Any]) -> dict[str, Any]:
    figures: sf.StopFigures = part["figures"]
    return {k: v for k, v in part.items() if k != "figures"} | {
        "stop_time_s": figures.stop_time_s,
        "distance_rev": figures.distance_rev,
        "predicted_time_s": figures.predicted_time_s,
        "predicted_distance_rev": figures.predicted_distance_rev,
        "time_ratio": figures.time_ratio,
        "distance_ratio": figures.distance_ratio,
        "allowed_time_s": figures.allowed_time_s(),
    }


async def run(axis: AxisRun, speed_rpm: float | None) -> tuple[Outcome, dict[str, float]]:
    """The step: (status, evidence, reason) and its figures."""
    rpm = _speed(axis, speed_rpm)
    async with axis.controlled():
        direction = await _direction(axis)
        quick = await _quick_stop(axis, rpm * direction)
        direction = await _direction(axis)
        decel = quick["deceleration"].get("quick_stop_deceleration_rpm_s")
        loss = await _keepalive_loss(axis, rpm * direction, decel)
    end = await axis.safety.motion.state(axis.node)
    figures = quick["figures"].figures("quick_stop") | loss["figures"].figures("keepalive_loss")
    evidence: dict[str, Any] = {
        "quick_stop": _public(quick),
        "keepalive_loss": _public(loss),
        "capture_ids": [quick["capture_id"], loss["capture_id"]],
        "deceleration": quick["deceleration"],
        "rest_rpm": axis.rest_rpm,
        "margin": {
            "factor": sf.MARGIN_FACTOR,
            "slack_s": sf.MARGIN_SLACK_S,
            "why": "the measured time includes the stop's trip to the drive, its cycle, the "
            "SYNC sample spacing and the host's lag beyond the ramp itself",
        },
        "end_state": end.state,
        "found_state": axis.found_state,
        "audit_ids": await axis.audit_ids(),
    }
    if axis.notes:
        evidence["notes"] = axis.notes
    reasons = [
        r
        for r in (
            sf.verdict("quick stop", quick["figures"], axis.rest_rpm),
            sf.verdict("keep-alive loss stop", loss["figures"], axis.rest_rpm),
        )
        if r is not None
    ]
    if end.state == "operation_enabled":
        reasons.append(f"the drive was left {end.state_label}: it could not be disabled")
    if reasons:
        return ("failed", evidence, "; ".join(reasons)), figures
    return ("done", evidence, None), figures
