"""The "tool-write" event of a jog's end (`jog-stop`, events/tool_writes.py). The app adds
`jog_stopped` as a listener of the jog watchdog (`MotionSafety.jogs`)."""

from __future__ import annotations

from servodesk.events.texts import say
from servodesk.events.tool_writes import Publish, tool_write
from servodesk.models.safety import JogInfo
from servodesk.motion.jog import REPLACED
from servodesk.motion.stop_reasons import nested_stop


def jog_stopped(publish: Publish, jog: JogInfo) -> None:
    """A jog's end on the timeline with its reason, so "why did the axis stop?" has an answer
    there too (a jog a new one took over did not stop the axis: no event)."""
    if (jog.stop_reason or "").endswith(REPLACED):
        return
    # "stopping" when the stop went out, "at rest" once the axis stands: the timeline never
    # says a jog stopped while the axis still runs
    reason = nested_stop(jog.stop_reason, jog.stop_reason_id, jog.stop_reason_params)
    how = "event.jog_stopping" if jog.state == "stopping" else "event.jog_at_rest"
    publish(
        tool_write(
            jog.node,
            say(how, node=jog.node, mode=jog.mode.upper(), **reason),
            "jog-stop",
            jog_id=jog.jog_id,
            mode=jog.mode,
            reason=jog.stop_reason,
            state=jog.state,
        )
    )
