"""Whether a node is online, and in which NMT state, from the evidence gathered about it.

Pure: the caller passes the time, so the rules are table-tested without a clock.

- A node that produces heartbeats (its 1017h is known to be non-zero, or heartbeats arrive while
  1017h is unknown) is online while its last heartbeat is younger than lost_factor × its period
  (settings.default_heartbeat_timeout when the period is unknown). Its SDO timeouts do not
  count: the heartbeat is the better witness (a Stopped node does not answer SDO).
- A node without heartbeats is judged by SDO activity: it goes offline only when an SDO request
  to it timed out (or a scan did not find it) after its last sign of life, and comes back with
  the next sign of life (an SDO answer, a boot-up, an EMCY or a PDO). Silence alone never makes
  it lost: without a heartbeat there is nothing to miss.
- The NMT state is the newer of the last heartbeat's state and the last command the tool sent:
  after a command the state follows the command until a heartbeat says otherwise. Offline
  nodes are in state "unknown".
"""

from __future__ import annotations

from dataclasses import dataclass

from servodesk.models.nodes import NmtStateName
from servodesk.network.nmt import BOOT_UP, state_from_byte

MS = 1000.0


@dataclass(frozen=True)
class Evidence:
    """Times are monotonic seconds."""

    beat: tuple[float, int] | None = None  # last 700h+id frame: (time, state byte; 0 = boot-up)
    activity: float | None = None  # last SDO answer / EMCY / TPDO frame from the node
    alive_at: float | None = None  # last SDO exchange through the tool that got an answer
    silence_at: float | None = None  # last SDO timeout, or a scan that did not find the node
    command: tuple[float, NmtStateName] | None = None  # last NMT command sent by the tool
    heartbeat_ms: int | None = None  # 1017h Producer heartbeat time as last read/written
    expect_since: float | None = None  # when that heartbeat expectation started


@dataclass(frozen=True)
class Health:
    online: bool
    nmt_state: NmtStateName
    heartbeat_age_ms: int | None
    last_seen: float | None  # monotonic time of the last sign of life
    lost_after_s: float | None  # heartbeat limit; None = judged by SDO activity


def heartbeat_limit(ev: Evidence, *, lost_factor: float, default_timeout: float) -> float | None:
    """Seconds without a heartbeat after which the node is lost; None when it has none."""
    if ev.heartbeat_ms:
        return lost_factor * ev.heartbeat_ms / MS
    if ev.heartbeat_ms is None and ev.beat is not None and ev.beat[1] != BOOT_UP:
        return default_timeout  # beats arrive but the period is unknown
    return None


def _latest(*times: float | None) -> float | None:
    known = [t for t in times if t is not None]
    return max(known) if known else None


def reported_state(
    beat: tuple[float, int] | None, command: tuple[float, NmtStateName] | None
) -> NmtStateName:
    """The NMT state last reported: the newer of the heartbeat and the tool's own command; on a
    tie the heartbeat (the node's own word)."""
    if beat is not None and (command is None or beat[0] >= command[0]):
        return state_from_byte(beat[1])
    if command is not None:
        return command[1]
    return NmtStateName.UNKNOWN


def assess(ev: Evidence, now: float, *, lost_factor: float, default_timeout: float) -> Health:
    beat_time = ev.beat[0] if ev.beat is not None else None
    last_seen = _latest(beat_time, ev.activity, ev.alive_at)
    limit = heartbeat_limit(ev, lost_factor=lost_factor, default_timeout=default_timeout)
    age_ms: int | None = None
    if limit is not None:
        reference = _latest(beat_time, ev.expect_since)
        online = reference is not None and now - reference <= limit
        if beat_time is not None:
            age_ms = max(0, round((now - beat_time) * MS))
    else:
        online = ev.silence_at is None or (last_seen is not None and last_seen > ev.silence_at)
    state = reported_state(ev.beat, ev.command)
    return Health(
        online=online,
        nmt_state=state if online else NmtStateName.UNKNOWN,
        heartbeat_age_ms=age_ms,
        last_seen=last_seen,
        lost_after_s=limit,
    )
