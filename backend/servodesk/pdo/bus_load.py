"""Worst-case CAN bus load of the PDOs (and SYNC) a set of nodes would produce.

Pure arithmetic: every frame is counted with worst-case bit stuffing, every PDO at the highest
rate its transmission type allows. Event-driven RPDOs are the master's: counted once per SYNC
when a SYNC producer runs, else at an assumed master cycle. Where no bound exists (a TPDO sent
on change without inhibit time) the PDO is left out instead of being guessed. Every assumption
and every PDO left out is named in one note per kind of reason, listing the PDOs it concerns.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import groupby

from servodesk.pdo.model import PdoConfig
from servodesk.pdo_problems import PdoKind
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
DEFAULT_MASTER_PERIOD_MS = 10  # assumed master cycle for event-driven RPDOs without SYNC
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


def frames_per_second(
    pdo: PdoConfig,
    *,
    sync_period_us: int | None,
    master_period_ms: int = DEFAULT_MASTER_PERIOD_MS,
) -> float | None:
    """The highest rate `pdo` can be sent at; None = unbounded."""
    return _rate(pdo, sync_period_us, master_period_ms).frames_per_s


@dataclass(frozen=True)
class _Rate:
    frames_per_s: float | None  # None = unbounded
    basis: str  # in words, for the PDO's row
    note: str | None = None  # the assumption or the reason it is not counted, for the notes


@dataclass(frozen=True)
class PdoLoad:
    kind: PdoKind
    number: int
    cob_id: int
    frames_per_s: float | None  # None = unbounded
    bits_per_frame: int
    bits_per_s: float  # 0 when not counted (named in BusLoad.notes instead)
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
    master_period_ms: int
    notes: list[str]


PdoRef = tuple[int, PdoKind, int]  # (node, kind, number)


def bus_load(
    pdos_by_node: Mapping[int, Sequence[PdoConfig]],
    *,
    bitrate: int,
    sync_period_us: int | None,
    threshold_percent: float = DEFAULT_THRESHOLD_PERCENT,
    master_period_ms: int = DEFAULT_MASTER_PERIOD_MS,
) -> BusLoad:
    """Load of the valid PDOs of every node plus the SYNC frame, at `bitrate` bit/s; event-driven
    RPDOs at the SYNC period, else every `master_period_ms`."""
    if bitrate <= 0:
        raise ValueError(f"bitrate must be positive, not {bitrate}")
    if master_period_ms <= 0:
        raise ValueError(f"master period must be positive, not {master_period_ms} ms")
    period = sync_period_us if sync_period_us and sync_period_us > 0 else None
    sync_bits = frame_bits(0) * 1e6 / period if period else 0.0
    concerned: dict[str, list[PdoRef]] = {}  # note -> the PDOs it concerns, in order
    nodes: list[NodeLoad] = []
    for node, pdos in sorted(pdos_by_node.items()):
        loads: list[PdoLoad] = []
        for pdo in pdos:
            if not pdo.valid:
                continue
            rate = _rate(pdo, period, master_period_ms)
            loads.append(_pdo_load(pdo, rate))
            if rate.note is not None:
                concerned.setdefault(rate.note, []).append((node, pdo.kind, pdo.number))
        bits = sum(load.bits_per_s for load in loads)
        nodes.append(NodeLoad(node, bits, 100.0 * bits / bitrate, loads))
    notes = [f"{pdo_list(refs)}: {note}" for note, refs in concerned.items()]
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
        master_period_ms=master_period_ms,
        notes=notes,
    )


def pdo_list(refs: Sequence[PdoRef]) -> str:
    """`node 1 RPDO1–3 and TPDO5, node 3 RPDO1–4`: runs of numbers joined, per node."""
    parts: list[str] = []
    for node, of_node in groupby(sorted(refs), key=lambda ref: ref[0]):
        labels: list[str] = []
        for kind, of_kind in groupby(of_node, key=lambda ref: ref[1]):
            labels += [f"{kind.upper()}{run}" for run in _runs([ref[2] for ref in of_kind])]
        listed = labels[0] if len(labels) == 1 else f"{', '.join(labels[:-1])} and {labels[-1]}"
        parts.append(f"node {node} {listed}")
    return ", ".join(parts)


def _runs(numbers: Sequence[int]) -> list[str]:
    """[1, 2, 3, 5] -> ['1–3', '5']."""
    runs: list[list[int]] = []
    for number in numbers:
        if runs and number == runs[-1][-1] + 1:
            runs[-1].append(number)
        else:
            runs.append([number])
    return [f"{run[0]}–{run[-1]}" if len(run) > 1 else f"{run[0]}" for run in runs]


def _pdo_load(pdo: PdoConfig, rate: _Rate) -> PdoLoad:
    bits = frame_bits(min(frame_length(pdo.entries), 8))
    per_s = rate.frames_per_s * bits if rate.frames_per_s is not None else 0.0
    return PdoLoad(pdo.kind, pdo.number, pdo.cob_id, rate.frames_per_s, bits, per_s, rate.basis)


def _rate(pdo: PdoConfig, period: int | None, master_period_ms: int) -> _Rate:
    t = pdo.transmission_type
    if not pdo.valid:
        return _Rate(0.0, "not valid: never sent")
    if t <= SYNC_CYCLIC_MAX:
        if period is None:
            reason = "synchronous, but no SYNC period is set"
            return _Rate(0.0, reason, f"not counted: {reason}")
        every = max(t, 1)
        at = _duration(period)
        if t == SYNC_ACYCLIC:
            basis = f"at most every SYNC at {at} (acyclic, on change)"
        else:
            # the master's synchronous RPDOs are counted like TPDOs of the same type
            basis = f"{transmission_words(t, Direction.TRANSMIT)} at {at}"
        return _Rate(1e6 / (period * every), basis)
    if t in (SYNC_RTR, EVENT_RTR):
        reason = "sent on remote request only (RTR frames are the requester's load)"
        return _Rate(0.0, reason, f"not counted: {reason}")
    if t < SYNC_RTR:
        reason = f"transmission type {t} is reserved"
        return _Rate(0.0, reason, f"not counted: {reason}")
    if pdo.kind == "rpdo":
        return _master_rate(period, master_period_ms)
    if pdo.inhibit_time_100us > 0:
        seconds = pdo.inhibit_time_100us * INHIBIT_UNIT_S
        return _Rate(1.0 / seconds, f"at most every {seconds * 1e3:.1f} ms (inhibit time)")
    if pdo.event_timer_ms > 0:
        return _Rate(1e3 / pdo.event_timer_ms, f"event timer {pdo.event_timer_ms} ms")
    reason = "unbounded: event-driven without inhibit time"
    return _Rate(None, reason, f"not counted: {reason}")


def _master_rate(period: int | None, master_period_ms: int) -> _Rate:
    """An event-driven RPDO: the master sends it, assumed once per SYNC or master cycle."""
    if period is not None:
        at = _duration(period)
        return _Rate(
            1e6 / period,
            f"sent by the master every {at} (assumed: once per SYNC)",
            f"counted once per SYNC ({at}), as the master is assumed to send them",
        )
    at = _duration(master_period_ms * 1000)
    return _Rate(
        1e3 / master_period_ms,
        f"sent by the master every {at} (assumed master cycle)",
        f"counted at the assumed {at} master cycle",
    )


def _duration(us: int) -> str:
    """1000 -> '1 ms', 500 -> '500 µs', 2500 -> '2.5 ms'."""
    return f"{us / 1000:g} ms" if us >= 1000 else f"{us} µs"
