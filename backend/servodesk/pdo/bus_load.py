"""Worst-case CAN bus load of the PDOs (and SYNC) a set of nodes would produce.

Pure arithmetic: every frame is counted with worst-case bit stuffing, every PDO at the highest
rate its transmission type allows. Where no bound exists (event-driven without inhibit time, or
an RPDO whose rate is the master's business) the PDO is listed as unbounded and named in a note,
instead of being guessed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from servodesk.pdo.model import PdoConfig, PdoKind
from servodesk_protocol.pdo import (
    EVENT_RTR,
    INHIBIT_UNIT_S,
    SYNC_ACYCLIC,
    SYNC_CYCLIC_MAX,
    SYNC_RTR,
    Direction,
    frame_length,
    transmission_words,
)

DEFAULT_THRESHOLD_PERCENT = 70.0  # above this, arbitration delays for low-priority ids grow fast
_FIXED_BITS = 47  # SOF, 11-bit id, RTR, IDE, r0, DLC, CRC + delimiter, ACK, EOF, 3-bit intermission
_STUFFED_BITS = 34  # SOF .. CRC without data: the part of the frame that bit stuffing applies to


def frame_bits(data_bytes: int) -> int:
    """Worst-case bits on the wire of a classic 11-bit data frame, intermission included.

    CiA / Bosch: 8n + 47 + floor((34 + 8n - 1) / 4); an 8-byte frame takes 135 bits.
    """
    if not 0 <= data_bytes <= 8:
        raise ValueError(f"a classic CAN frame carries 0–8 data bytes, not {data_bytes}")
    data = 8 * data_bytes
    return data + _FIXED_BITS + (_STUFFED_BITS + data - 1) // 4


def frames_per_second(pdo: PdoConfig, *, sync_period_us: int | None) -> float | None:
    """The highest rate `pdo` can be sent at; None = unbounded."""
    return _rate(pdo, sync_period_us)[0]


@dataclass(frozen=True)
class PdoLoad:
    kind: PdoKind
    number: int
    cob_id: int
    frames_per_s: float | None  # None = unbounded
    bits_per_frame: int
    bits_per_s: float  # 0 when unbounded (named in BusLoad.notes instead)
    basis: str  # how the rate was found, in words


@dataclass(frozen=True)
class NodeLoad:
    node: int
    bits_per_s: float
    percent: float
    pdos: list[PdoLoad]


@dataclass(frozen=True)
class BusLoad:
    bitrate: int
    sync_period_us: int | None
    sync_bits_per_s: float
    nodes: list[NodeLoad]
    total_bits_per_s: float
    percent: float
    threshold_percent: float
    over_threshold: bool
    notes: list[str]


def bus_load(
    pdos_by_node: Mapping[int, Sequence[PdoConfig]],
    *,
    bitrate: int,
    sync_period_us: int | None,
    threshold_percent: float = DEFAULT_THRESHOLD_PERCENT,
) -> BusLoad:
    """Load of the valid PDOs of every node plus the SYNC frame, at `bitrate` bit/s."""
    if bitrate <= 0:
        raise ValueError(f"bitrate must be positive, not {bitrate}")
    period = sync_period_us if sync_period_us and sync_period_us > 0 else None
    sync_bits = frame_bits(0) * 1e6 / period if period else 0.0
    notes: list[str] = []
    nodes: list[NodeLoad] = []
    for node, pdos in sorted(pdos_by_node.items()):
        loads = [_pdo_load(pdo, period) for pdo in pdos if pdo.valid]
        for load in loads:
            if load.frames_per_s is None or load.frames_per_s == 0:
                label = f"node {node} {load.kind.upper()}{load.number}"
                notes.append(f"{label} is not counted: {load.basis}")
        bits = sum(load.bits_per_s for load in loads)
        nodes.append(NodeLoad(node, bits, 100.0 * bits / bitrate, loads))
    total = sync_bits + sum(node.bits_per_s for node in nodes)
    percent = 100.0 * total / bitrate
    if percent > threshold_percent:
        notes.append(
            f"the bus would be {percent:.1f} % loaded (over {threshold_percent:g} %): lengthen the"
            " SYNC period or inhibit times, or map fewer objects"
        )
    return BusLoad(
        bitrate=bitrate,
        sync_period_us=period,
        sync_bits_per_s=sync_bits,
        nodes=nodes,
        total_bits_per_s=total,
        percent=percent,
        threshold_percent=threshold_percent,
        over_threshold=percent > threshold_percent,
        notes=notes,
    )


def _pdo_load(pdo: PdoConfig, period: int | None) -> PdoLoad:
    rate, basis = _rate(pdo, period)
    bits = frame_bits(min(frame_length(pdo.entries), 8))
    per_s = rate * bits if rate is not None else 0.0
    return PdoLoad(pdo.kind, pdo.number, pdo.cob_id, rate, bits, per_s, basis)


def _rate(pdo: PdoConfig, period: int | None) -> tuple[float | None, str]:
    """(frames per second, basis in words)."""
    t = pdo.transmission_type
    if not pdo.valid:
        return 0.0, "not valid: never sent"
    if t <= SYNC_CYCLIC_MAX:
        if period is None:
            return 0.0, "synchronous, but no SYNC period is set"
        every = max(t, 1)
        at = _duration(period)
        if t == SYNC_ACYCLIC:
            basis = f"at most every SYNC at {at} (acyclic, on change)"
        else:
            # the master's synchronous RPDOs are counted like TPDOs of the same type
            basis = f"{transmission_words(t, Direction.TRANSMIT)} at {at}"
        return 1e6 / (period * every), basis
    if t in (SYNC_RTR, EVENT_RTR):
        return 0.0, "sent on remote request only (RTR frames are the requester's load)"
    if t < SYNC_RTR:
        return 0.0, f"transmission type {t} is reserved"
    if pdo.kind == "rpdo":
        return None, "unbounded: event-driven, sent as often as the master sends it"
    if pdo.inhibit_time_100us > 0:
        seconds = pdo.inhibit_time_100us * INHIBIT_UNIT_S
        return 1.0 / seconds, f"at most every {seconds * 1e3:.1f} ms (inhibit time)"
    if pdo.event_timer_ms > 0:
        return 1e3 / pdo.event_timer_ms, f"event timer {pdo.event_timer_ms} ms"
    return None, "unbounded: event-driven without inhibit time"


def _duration(us: int) -> str:
    """1000 -> '1 ms', 500 -> '500 µs', 2500 -> '2.5 ms'."""
    return f"{us / 1000:g} ms" if us >= 1000 else f"{us} µs"
