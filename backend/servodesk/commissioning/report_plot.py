"""Line plots of a capture for the commissioning report, as inline SVG.

A hand-written SVG polyline rather than a plotting library: the report must be self-contained
(no scripts, no fetched files), WeasyPrint draws SVG natively, and a stack of small panels (one
per signal, each with its own unit and scale) is all a technician needs to see a stop or a
move. The samples are reduced while they are read: each signal keeps the smallest and largest
value per time bucket, so a long capture plots in bounded memory and a short spike still
shows."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from html import escape
from pathlib import Path

import numpy as np
import numpy.typing as npt

from servodesk.commissioning.report_words import EN, Words
from servodesk.models.scope import Capture
from servodesk.scope.samples import value_batches

BUCKETS = 400  # per signal: about one per horizontal pixel of a panel
WIDTH, PANEL_HEIGHT = 680, 130
LEFT, RIGHT, TOP, BOTTOM = 78, 12, 22, 26  # room for the value and time labels
COLOURS = ("#1f5fa8", "#c0392b", "#1e8449", "#8e44ad", "#b9770e", "#17707a")
Floats = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Series:
    name: str
    unit: str
    time: Floats  # s from the trigger
    value: Floats


def capture_series(
    capture: Capture, samples: Path, buckets: int = BUCKETS, words: Words = EN
) -> list[Series]:
    """Each signal of the capture reduced to at most 2 × `buckets` points (min and max per
    bucket, in time order). Two streaming passes over the samples table: the time span, then
    the buckets. Blocking: call it in a worker thread. `words` name the signal's node (the
    signal's own name is the capture's, as stored)."""
    count = len(capture.signals)
    if count == 0:
        return []
    start, end = math.inf, -math.inf
    for _, times, _ in value_batches(samples):
        if len(times):
            start, end = min(start, float(times.min())), max(end, float(times.max()))
    if start > end:
        return []
    span = end - start or 1.0
    low = np.full((count, buckets), np.inf)
    high = np.full((count, buckets), -np.inf)
    for signal, times, values in value_batches(samples):
        keep = (signal >= 0) & (signal < count) & np.isfinite(values)
        slot = np.minimum(((times[keep] - start) / span * buckets).astype(np.intp), buckets - 1)
        np.minimum.at(low, (signal[keep], slot), values[keep])
        np.maximum.at(high, (signal[keep], slot), values[keep])
    centres = start + (np.arange(buckets) + 0.5) * span / buckets
    series: list[Series] = []
    for position, signal_info in enumerate(capture.signals):
        filled = np.isfinite(low[position])
        if not filled.any():
            continue
        # min then max at the bucket's centre: the envelope, drawn as one line
        time = np.repeat(centres[filled], 2)
        value = np.column_stack((low[position][filled], high[position][filled])).ravel()
        name = words("plot.signal", name=signal_info.name, node=signal_info.node)
        series.append(Series(name, signal_info.unit, time, value))
    return series


def _number(value: float) -> str:
    return f"{value:.4g}"


def _panel(series: Series, top: float, colour: str, t0: float, t1: float) -> list[str]:
    inner_w = WIDTH - LEFT - RIGHT
    inner_h = PANEL_HEIGHT - TOP - BOTTOM
    v0, v1 = float(series.value.min()), float(series.value.max())
    if v0 == v1:  # a flat line sits in the middle of its panel
        v0, v1 = v0 - 1.0, v1 + 1.0
    xs = LEFT + (series.time - t0) / ((t1 - t0) or 1.0) * inner_w
    ys = top + TOP + (1.0 - (series.value - v0) / (v1 - v0)) * inner_h
    points = " ".join(f"{x:.1f},{y:.1f}" for x, y in zip(xs.tolist(), ys.tolist(), strict=True))
    y_top, y_bottom = top + TOP, top + TOP + inner_h
    label = escape(f"{series.name} [{series.unit}]" if series.unit else series.name)
    return [
        f'<text x="{LEFT}" y="{top + 15:.0f}" class="t">{label}</text>',
        f'<rect x="{LEFT}" y="{y_top:.0f}" width="{inner_w}" height="{inner_h}" class="f"/>',
        f'<text x="{LEFT - 4}" y="{y_top + 9:.0f}" class="v">{_number(v1)}</text>',
        f'<text x="{LEFT - 4}" y="{y_bottom:.0f}" class="v">{_number(v0)}</text>',
        f'<text x="{LEFT}" y="{y_bottom + 14:.0f}" class="s">{_number(t0)} s</text>',
        f'<text x="{WIDTH - RIGHT}" y="{y_bottom + 14:.0f}" class="e">{_number(t1)} s</text>',
        f'<polyline points="{points}" fill="none" stroke="{colour}" stroke-width="1.2"/>',
    ]


def svg_plot(series: Sequence[Series], title: str) -> str:
    """One panel per series, stacked, on a shared time axis; the SVG element as text (every
    name escaped)."""
    if not series:
        return ""
    t0 = min(float(s.time.min()) for s in series)
    t1 = max(float(s.time.max()) for s in series)
    height = PANEL_HEIGHT * len(series) + 20
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" '
        f'viewBox="0 0 {WIDTH} {height}" role="img" aria-label="{escape(title)}">',
        "<style>text{font-size:10px;fill:#222}.t{font-weight:bold}.v{text-anchor:end}"
        ".e{text-anchor:end}.f{fill:none;stroke:#999;stroke-width:0.6}</style>",
        f'<text x="{LEFT}" y="13" class="t">{escape(title)}</text>',
    ]
    for number, one in enumerate(series):
        top = 20 + number * PANEL_HEIGHT
        parts.extend(_panel(one, top, COLOURS[number % len(COLOURS)], t0, t1))
    parts.append("</svg>")
    return "\n".join(parts)
