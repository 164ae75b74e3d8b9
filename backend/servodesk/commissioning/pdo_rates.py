"""The pdo step's judgements (pure: table-tested): at what rate each TPDO should arrive, whether
the rate seen on the bus matches, and whether the mapping carries what each chosen mode needs.

Transmission types (CiA 301 §7.5.2.35, 1800h:02): 0 acyclic synchronous (on a SYNC after a
change), 1–240 every n-th SYNC, 252/253 on request (RTR), 254/255 event-driven with the event
timer 1800h:05 as the longest gap; the inhibit time 1800h:03 is the shortest gap."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo_problems import PdoKind

RATE_TOLERANCE = 0.2  # a cyclic TPDO within ±20 % of its period counts as on time
# the window a live check listens: three of the slowest period, within these bounds
MIN_WINDOW_S = 2.0
MAX_WINDOW_S = 10.0


@dataclass(frozen=True)
class Expected:
    """What a TPDO's communication parameter promises."""

    rate_hz: float | None  # None: no fixed rate (on change, on request)
    basis: str  # the promise in words, with the object that sets it
    exact: bool = False  # cyclic synchronous: the rate itself, not a lower bound
    max_hz: float | None = None  # the inhibit time's ceiling
    no_sync: bool = False  # synchronous, but nothing sends SYNC: it cannot be checked


@dataclass(frozen=True)
class Verdict:
    ok: bool
    text: str


def expected_rate(pdo: PdoConfig, sync_period_us: int | None) -> Expected:
    """The rate `pdo` (a TPDO) should arrive at; `sync_period_us` is the SYNC on the bus (None:
    no SYNC)."""
    kind = pdo.transmission_type
    cap = 10_000 / pdo.inhibit_time_100us if pdo.inhibit_time_100us else None
    if 1 <= kind <= 240:
        if sync_period_us is None or sync_period_us <= 0:
            words = f"every {_nth(kind)}SYNC (type {kind}), but no SYNC is on the bus"
            return Expected(None, words, no_sync=True)
        rate = 1e6 / (sync_period_us * kind)
        return Expected(
            rate, f"every {_nth(kind)}SYNC of {sync_period_us / 1000:g} ms (type {kind})", True
        )
    if kind == 0:
        return Expected(None, "on a SYNC after a change (type 0): no fixed rate")
    if kind in (252, 253):
        return Expected(None, f"on request only (RTR, type {kind}): no fixed rate")
    if pdo.event_timer_ms > 0:
        return Expected(
            1000 / pdo.event_timer_ms,
            f"event timer {pdo.event_timer_ms} ms (1800h:05, type {kind}) and on change",
            max_hz=cap,
        )
    words = f"on change only (type {kind}, no event timer): no fixed rate"
    return Expected(None, words, max_hz=cap)


def _nth(n: int) -> str:
    if n == 1:
        return ""
    suffix = {2: "nd", 3: "rd"}.get(n % 10 if n % 100 not in (11, 12, 13) else 0, "th")
    return f"{n}{suffix} "


def judge(expected: Expected, frames: int, rate_hz: float | None, window_s: float) -> Verdict:
    """Whether the frames seen in `window_s` keep the promise; `rate_hz` is frame to frame."""
    if expected.rate_hz is None:
        if expected.no_sync:
            return Verdict(False, f"not checked: {expected.basis}; start SYNC on the PDO page")
        seen = f"{frames} frame(s) seen" if frames else "none seen"
        return Verdict(True, f"{expected.basis}; {seen} in {window_s:g} s")
    want = expected.rate_hz
    if frames == 0:
        return Verdict(False, f"not seen in {window_s:g} s (expected {want:.3g} Hz)")
    if rate_hz is None:
        return Verdict(False, f"one frame in {window_s:g} s (expected {want:.3g} Hz)")
    low = want * (1 - RATE_TOLERANCE)
    if rate_hz < low:
        return Verdict(False, f"{rate_hz:.3g} Hz, below the expected {want:.3g} Hz")
    high = want * (1 + RATE_TOLERANCE) if expected.exact else None
    if expected.max_hz is not None:
        ceiling = expected.max_hz * (1 + RATE_TOLERANCE)
        high = ceiling if high is None else min(high, ceiling)
    if high is not None and rate_hz > high:
        limit = "its inhibit time allows" if not expected.exact else "expected"
        return Verdict(False, f"{rate_hz:.3g} Hz, above what {limit} ({high:.3g} Hz)")
    return Verdict(True, f"{rate_hz:.3g} Hz (expected {want:.3g} Hz)")


def window_s(expected: Sequence[Expected]) -> float:
    """How long to listen: three of the slowest promised period, within the bounds."""
    periods = [1 / e.rate_hz for e in expected if e.rate_hz]
    longest = max(periods, default=0.0)
    return min(MAX_WINDOW_S, max(MIN_WINDOW_S, 3 * longest))


def missing_objects(
    needs: Mapping[PdoKind, Sequence[MappedObject]], pdos: Sequence[PdoConfig]
) -> list[str]:
    """What a mode needs that no valid PDO of the right direction maps, as "6041h:00 Statusword
    (TPDO)"."""
    out: list[str] = []
    for kind, objects in needs.items():
        mapped = {
            (obj.index, obj.subindex) for pdo in pdos if pdo.kind == kind and pdo.valid
            for obj in pdo.mapping
        }  # fmt: skip
        for obj in objects:
            if (obj.index, obj.subindex) not in mapped:
                name = f" {obj.name}" if obj.name else ""
                out.append(f"{obj.index:04X}h:{obj.subindex:02X}{name} ({kind.upper()})")
    return out
