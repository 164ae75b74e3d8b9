"""test_move: enable, one short jog per chosen mode the drive supports (pv, pt), each stopped
through the normal jog stop, then a PP move of a chosen distance with a capture of 6064h, 606Ch,
60F4h and 6041h: time to target, overshoot, settling time, peak following error. The report
plots the move from the capture. The axis is left stopped, disabled and released."""

from __future__ import annotations

import asyncio
import time
from typing import Any

from servodesk.commissioning import move_figures as mf
from servodesk.commissioning.axis_run import (
    FOLLOWING_ERROR,
    POLL_S,
    POSITION_ACTUAL,
    VELOCITY_ACTUAL,
    AxisRun,
)
from servodesk.commissioning.evidence import Outcome
from servodesk.commissioning.reads import read_listed
from servodesk.models.motion import MoveRequest
from servodesk.models.safety import JogRequest
from servodesk.motion.stop_reasons import Reason
from servodesk.scope.units import drive_units
from servodesk_protocol.cia402 import STATUSWORD

JOG_MODES = ("pv", "pt")
JOG_SECONDS = 1.0  # each mode's jog runs this long before it is stopped
JOG_RPM = 60.0  # pv: a slow, safe speed; never above half the speed limit in force
JOG_TORQUE_PCT = 1.0  # pt: a small torque; the jog's speed cap stops a free axis early
DEFAULT_DISTANCE_REV = 0.5
MOVE_RPM = 120.0  # the PP move's profile velocity (never above half the speed limit)
POSITION_WINDOW = 0x6067  # Position window
MOVE_SIGNALS = (POSITION_ACTUAL, VELOCITY_ACTUAL, FOLLOWING_ERROR, STATUSWORD)
DEFAULT_WINDOW_REV = 0.001  # where the drive has no 6067h


async def _jog(run: AxisRun, mode: str) -> dict[str, Any]:
    """One short jog: moved (|606Ch| above the rest threshold seen), stopped (the jog at rest)."""
    safety, node = run.safety, run.node
    limit = safety.motion.limits(node).max_velocity_rpm
    await safety.motion.enable(node)
    if mode == "pv":
        request = JogRequest(mode="pv", velocity_rpm=min(JOG_RPM, limit / 2))
    else:
        request = JogRequest(
            mode="pt", torque_pct=JOG_TORQUE_PCT, speed_cap_rpm=min(JOG_RPM * 2, limit / 2)
        )
    jog = await safety.start_jog(node, request, run.client)
    peak = 0.0
    loop = asyncio.get_running_loop()
    async with run.keepalives(jog):
        until = loop.time() + JOG_SECONDS
        while loop.time() < until and safety.jogs.get(jog.jog_id).state == "running":
            peak = max(peak, abs(await safety.motion.velocity_rpm(node)))
            await asyncio.sleep(POLL_S)
    info = await safety.jogs.stop(jog.jog_id, Reason("stop.test_jog_ended"))
    info = await run.wait_jog_stopped(jog.jog_id, 15.0)
    at_rest = abs(await safety.motion.velocity_rpm(node)) < run.rest_rpm
    return {
        "mode": mode,
        "value": jog.value,
        "peak_rpm": round(peak, 3),
        "moved": peak >= run.rest_rpm,
        "stopped": info.state == "stopped" and at_rest,
        "stop_reason": info.stop_reason,
    }


async def _window_rev(run: AxisRun) -> tuple[float, str]:
    read = await read_listed(run.access, run.sdo, run.node, [(POSITION_WINDOW, 0)])
    units = await drive_units(run.access, run.node)
    if read and isinstance(read[0].get("value"), int) and read[0]["value"] > 0:
        return units.user_to_rev(read[0]["value"]), "6067h"
    return DEFAULT_WINDOW_REV, f"{DEFAULT_WINDOW_REV:g} rev (no 6067h)"


async def _move(run: AxisRun, distance: float) -> dict[str, Any]:
    safety, node = run.safety, run.node
    window, window_source = await _window_rev(run)
    capture = await run.start_capture(f"commissioning: test move node {node}", MOVE_SIGNALS)
    await safety.motion.enable(node)
    start = await safety.motion.state(node)
    rpm = min(MOVE_RPM, start.limits.max_velocity_rpm / 2)
    request = MoveRequest(position_rev=distance, relative=True, velocity_rpm=rpm)
    sent_at = time.time()
    state = await safety.motion.move(node, request)
    # bounded: the profile's time at speed, its ramps, and a busy PC's slack
    loop = asyncio.get_running_loop()
    deadline = loop.time() + abs(distance) / (rpm / 60) * 3 + 10.0
    while loop.time() < deadline:
        state = await safety.motion.state(node)
        if state.move is None or state.move.phase != "moving":
            break
        await asyncio.sleep(POLL_S)
    phase = state.move.phase if state.move else "interrupted"
    capture, series = await run.end_capture(capture.id)
    target = start.position_rev + distance
    position = series.get(POSITION_ACTUAL)
    figures = None
    if position is not None and len(position):
        at = position.at_or_before(sent_at)
        start_rev = at if at is not None else start.position_rev
        figures = mf.move_figures(
            position,
            sent_at,
            start_rev,
            start_rev + distance,
            window,
            velocity=series.get(VELOCITY_ACTUAL),
            following_error=series.get(FOLLOWING_ERROR),
            statusword=series.get(STATUSWORD),
        )
        target = start_rev + distance
    signals = {s.index: s for s in capture.signals}
    following = signals.get(FOLLOWING_ERROR)
    return {
        "capture_id": capture.id,
        "sync_period_us": capture.sync_period_us,
        "distance_rev": distance,
        "velocity_rpm": rpm,
        "target_rev": target,
        "window_rev": window,
        "window_source": window_source,
        "phase": phase,
        "message": state.move.message if state.move else None,
        "sent_at": sent_at,
        "following_error": (
            "not in the drive's dictionary"
            if following is None
            else f"{following.source.upper()}" + (f" ({following.note})" if following.note else "")
        ),
        "figures": figures,
    }


async def run(
    axis: AxisRun, modes: list[str], supported: list[str] | None, distance: float | None
) -> tuple[Outcome, dict[str, float]]:
    known = set(supported) if supported is not None else None
    skipped: dict[str, str] = {}
    wanted: list[str] = []
    for mode in (m for m in modes if m in JOG_MODES):
        if known is not None and mode not in known:
            skipped[mode] = f"not among the drive's modes (6502h: {', '.join(sorted(known))})"
        else:
            wanted.append(mode)
    pp = "pp" in modes and (known is None or "pp" in known)
    if "pp" in modes and not pp:
        skipped["pp"] = "the drive has no profile position mode (6502h): no test move"
    jogs: list[dict[str, Any]] = []
    move: dict[str, Any] | None = None
    async with axis.controlled():
        for mode in wanted:
            jogs.append(await _jog(axis, mode))
        if pp:
            move = await _move(axis, distance if distance is not None else DEFAULT_DISTANCE_REV)
    end = await axis.safety.motion.state(axis.node)
    figures: dict[str, float] = {f"{j['mode']}_peak_rpm": j["peak_rpm"] for j in jogs}
    reasons = [
        f"{j['mode']} jog: " + ("did not move" if not j["moved"] else "did not come to rest")
        for j in jogs
        if not (j["moved"] and j["stopped"])
    ]
    evidence: dict[str, Any] = {"jogs": jogs, "skipped": skipped}
    if move is not None:
        result: mf.MoveFigures | None = move.pop("figures")
        evidence["move"] = move | ({} if result is None else result.figures())
        evidence["capture_ids"] = [move["capture_id"]]
        if result is not None:
            figures |= result.figures()
        if move["phase"] != "reached":
            reasons.append(f"PP move: {move['phase']}" + (f" ({move['message']})" if move[
                "message"] else ""))  # fmt: skip
        elif result is None or result.settling_time_s is None:
            reasons.append("PP move: the position did not settle within the window in the capture")
    if not jogs and move is None:
        reasons.append("none of the record's modes (pv, pt, pp) could be tested on this drive")
    evidence |= {
        "end_state": end.state,
        "found_state": axis.found_state,
        "audit_ids": await axis.audit_ids(),
    }
    if axis.notes:
        evidence["notes"] = axis.notes
    if end.state == "operation_enabled":
        reasons.append(f"the drive was left {end.state_label}: it could not be disabled")
    if reasons:
        return ("failed", evidence, "; ".join(reasons)), figures
    return ("done", evidence, None), figures
