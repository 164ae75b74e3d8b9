"""Cursors on a finished capture, pure: per signal the value at cursor A and B (the sample at
or before each), Δt, Δvalue, and min / max / mean / count between them; and a signal reduced
to min/max bins for the overview plot the cursors are dragged on.

The rerun viewer has no measurement API, so this works on the capture's own samples table,
batch by batch (`Batch`: signal position, seconds from the trigger, physical value), in
bounded memory however long the capture.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from servodesk.models.scope import Capture, CaptureSignal, Measurement, SignalMeasurement, Trace
from servodesk.scope.samples import value_batches

Floats = npt.NDArray[np.float64]
Batch = tuple[npt.NDArray[np.int32], Floats, Floats]  # signal, time (s), value
MAX_POINTS = 2000


class CursorError(ValueError):
    """A cursor the capture cannot answer (not a number, outside the capture)."""


@dataclass
class _Running:
    at_a: tuple[float, float] | None = None  # (time, value) of the latest sample ≤ A
    at_b: tuple[float, float] | None = None
    count: int = 0
    total: float = 0.0
    low: float = math.inf
    high: float = -math.inf


def _at_or_before(
    times: Floats, values: Floats, t: float, best: tuple[float, float] | None
) -> tuple[float, float] | None:
    i = int(np.searchsorted(times, t, side="right")) - 1  # a signal's rows are in time order
    if i < 0 or (best is not None and best[0] > times[i]):
        return best
    return float(times[i]), float(values[i])


def check_cursors(t0: float, t1: float, start: float, end: float) -> None:
    """Both cursors finite and within the capture's samples [start, end] (s from trigger)."""
    for name, t in (("t0", t0), ("t1", t1)):
        if not math.isfinite(t):
            raise CursorError(f"{name} must be a number of seconds from the trigger")
        if not start <= t <= end:
            raise CursorError(
                f"{name} = {t:g} s lies outside the capture: pick a time from {start:g} s"
                f" to {end:g} s (seconds from the trigger)"
            )


def measure(
    batches: Iterable[Batch],
    signals: Sequence[CaptureSignal],
    t0: float,
    t1: float,
    *,
    span: tuple[float, float],
) -> Measurement:
    """The readout between cursor A (`t0`) and B (`t1`); B may lie before A (Δt < 0), the
    statistics cover the samples between them either way. `span`: the capture's first and
    last sample time, which the cursors must lie within."""
    start, end = span
    check_cursors(t0, t1, start, end)
    lo, hi = min(t0, t1), max(t0, t1)
    running = [_Running() for _ in signals]
    for signal, times, values in batches:
        for position in np.unique(signal):
            if not 0 <= position < len(running):
                continue
            rows = signal == position
            t, v = times[rows], values[rows]
            r = running[int(position)]
            r.at_a = _at_or_before(t, v, t0, r.at_a)
            r.at_b = _at_or_before(t, v, t1, r.at_b)
            inside = v[(t >= lo) & (t <= hi)]
            if inside.size:
                r.count += int(inside.size)
                r.total += float(inside.sum())
                r.low = min(r.low, float(inside.min()))
                r.high = max(r.high, float(inside.max()))
    return Measurement(
        t0=t0,
        t1=t1,
        dt=t1 - t0,
        start=start,
        end=end,
        signals=[_readout(s, r) for s, r in zip(signals, running, strict=True)],
    )


def _readout(signal: CaptureSignal, r: _Running) -> SignalMeasurement:
    a = r.at_a[1] if r.at_a is not None else None
    b = r.at_b[1] if r.at_b is not None else None
    some = r.count > 0
    return SignalMeasurement(
        node=signal.node,
        index=signal.index,
        subindex=signal.subindex,
        name=signal.name,
        unit=signal.unit,
        at_a=a,
        at_b=b,
        delta=b - a if a is not None and b is not None else None,
        min=r.low if some else None,
        max=r.high if some else None,
        mean=r.total / r.count if some else None,
        count=r.count,
    )


def time_span(batches: Iterable[Batch]) -> tuple[float, float] | None:
    """The first and last sample time of any signal; None for a capture without samples."""
    low, high = math.inf, -math.inf
    for _, times, _ in batches:
        if times.size:
            low, high = min(low, float(times.min())), max(high, float(times.max()))
    return None if low > high else (low, high)


def trace(
    batches: Iterable[Batch],
    position: int,
    unit: str,
    span: tuple[float, float],
    points: int,
) -> Trace:
    """Signal `position` in at most `points` equal time bins over `span`, each bin's lowest
    and highest value at the bin's first sample time; empty bins are left out."""
    start, end = span
    width = (end - start) / points if end > start else 1.0
    low = np.full(points, np.inf)
    high = np.full(points, -np.inf)
    first = np.full(points, np.inf)
    for signal, times, values in batches:
        rows = signal == position
        t, v = times[rows], values[rows]
        if not t.size:
            continue
        bins = np.clip(((t - start) / width).astype(np.int64), 0, points - 1)
        np.minimum.at(low, bins, v)
        np.maximum.at(high, bins, v)
        np.minimum.at(first, bins, t)
    used = np.isfinite(first)
    return Trace(
        signal=position,
        unit=unit,
        start=start,
        end=end,
        times=first[used].tolist(),
        low=low[used].tolist(),
        high=high[used].tolist(),
    )


def measure_file(path: Path, capture: Capture, t0: float, t1: float) -> Measurement:
    """Blocking (reads the samples table twice: its time span, then the readout)."""
    span = time_span(value_batches(path))
    if span is None:
        raise CursorError(f"capture {capture.id} holds no samples: there is nothing to measure")
    return measure(value_batches(path), capture.signals, t0, t1, span=span)


def trace_file(path: Path, capture: Capture, position: int, points: int) -> Trace:
    if not 0 <= position < len(capture.signals):
        raise CursorError(
            f"signal {position} is not in capture {capture.id}: pick 0 to"
            f" {len(capture.signals) - 1} (its position in the capture's signals)"
        )
    span = time_span(value_batches(path)) or (0.0, 0.0)
    unit = capture.signals[position].unit
    return trace(value_batches(path), position, unit, span, points)
