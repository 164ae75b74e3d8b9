"""The homing step: run the drive's homing with the method it is set up for (6098h) or the one
chosen, through the motion service (the same start as the Drive page's wizard), wait for the
statusword to say attained or error, and keep the method, the result, the home offset (607Ch),
the speeds (6099h) and where the axis ended. The axis is left stopped, disabled and released."""

from __future__ import annotations

import asyncio
import time
from typing import Any

from servodesk.commissioning.axis_run import POLL_S, AxisRun, StepError
from servodesk.commissioning.evidence import Outcome
from servodesk.commissioning.reads import read_listed
from servodesk.errors import InvalidValueError
from servodesk.models.motion import HomeRequest
from servodesk.motion.drive_io import HOME_OFFSET, HOMING_METHOD, HOMING_SPEEDS

# the longest a homing may search: a slow creep over a long axis; the step fails after it
HOMING_TIMEOUT_S = 120.0
SETTINGS = [(HOMING_METHOD, 0), (HOMING_SPEEDS, 1), (HOMING_SPEEDS, 2), (HOME_OFFSET, 0)]


def _values(read: list[dict[str, Any]]) -> dict[str, Any]:
    return {row["object"]: row.get("value") for row in read}


async def run(axis: AxisRun, method: int | None) -> tuple[Outcome, dict[str, float]]:
    motion, node = axis.safety.motion, axis.node
    listed = {info.method: info for info in motion.homing_methods(node)}
    before = _values(await read_listed(axis.access, axis.sdo, node, SETTINGS))
    configured = before.get("6098:00")
    chosen = method if method is not None else configured
    if not isinstance(chosen, int) or chosen not in listed:
        given = "chosen" if method is not None else "set in 6098h"
        raise InvalidValueError(
            f"homing method {chosen} ({given}) is not one node {node} supports "
            f"({', '.join(map(str, sorted(listed)))}): pick one with `method`"
        )
    evidence: dict[str, Any] = {
        "method": chosen,
        "method_name": listed[chosen].name,
        "method_source": "chosen for the step" if method is not None else "6098h as set",
        "before": before,
    }
    started = time.monotonic()
    phase, message = "interrupted", "homing did not start"
    async with axis.controlled():
        await motion.enable(node)
        await motion.home(node, HomeRequest(method=chosen))
        loop = asyncio.get_running_loop()
        deadline = loop.time() + HOMING_TIMEOUT_S
        while True:
            state = await motion.state(node)
            if state.homing is not None and state.homing.phase != "running":
                phase, message = state.homing.phase, state.homing.message
                break
            if loop.time() > deadline:
                await axis.safety.quick_stop(node)
                raise StepError(
                    f"node {node}: homing method {chosen} did not end within "
                    f"{HOMING_TIMEOUT_S:g} s (statusword {state.statusword:04X}h); quick stop sent"
                )
            await asyncio.sleep(POLL_S)
        took = time.monotonic() - started
        at = await motion.state(node)
    after = _values(await read_listed(axis.access, axis.sdo, node, SETTINGS))
    evidence |= {
        "phase": phase,
        "message": message,
        "home_offset": after.get("607C:00"),
        "speeds": {"fast": after.get("6099:01"), "slow": after.get("6099:02")},
        "position_inc": at.position_inc,
        "position_rev": round(at.position_rev, 6),
        "homed": at.homed,
        "audit_ids": await axis.audit_ids(),
    }
    if axis.notes:
        evidence["notes"] = axis.notes
    figures = {"homing_time_s": round(took, 3), "position_after_rev": round(at.position_rev, 6)}
    if phase != "attained":
        return ("failed", evidence, f"homing method {chosen}: {message}"), figures
    return ("done", evidence, None), figures
