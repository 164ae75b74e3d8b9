"""Turning a capture request into a setup: the signals resolved from the nodes' dictionaries,
their TPDOs planned, the trigger, and the pieces the flush thread runs (streams, tracks).

`resolve` reads (dictionaries and units); `build_core` is pure.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from servodesk.errors import InvalidValueError
from servodesk.models.scope import CaptureRequest, CaptureSignal, TriggerRequest
from servodesk.motion.units import DriveUnits
from servodesk.od.model import ObjectDictionaryModel
from servodesk.pdo.model import PdoConfig
from servodesk.scope.batch import BatchDecoder, FieldSpec
from servodesk.scope.capture import CaptureCore, Output, SignalTrack, Stream, TriggerSetup
from servodesk.scope.plan import NodePlan, Placement
from servodesk.scope.signals import SignalInfo, signal_info
from servodesk.scope.trigger import BitTrigger, LevelTrigger, StateTrigger, parse_state
from servodesk_protocol.cia402 import STATUSWORD

SDO_STREAM_BASE = 0x10000  # stream ids of SDO-polled signals: above every CAN id
Key = tuple[int, int, int]  # node, index, subindex


@dataclass(frozen=True)
class Wanted:
    """The signals a request needs, in order: the user's, then those the trigger and the
    state lane need (with the reason they were added)."""

    keys: tuple[Key, ...]
    added: dict[Key, str]


def wanted(request: CaptureRequest, has_statusword: dict[int, bool]) -> Wanted:
    keys: list[Key] = []
    added: dict[Key, str] = {}
    for signal in request.signals:
        key = (signal.node, signal.index, signal.subindex)
        if key not in keys:
            keys.append(key)
    trigger = request.trigger
    extra: list[tuple[Key, str]] = []
    if trigger.kind in ("level", "bit") and trigger.node is not None:
        index = trigger.index if trigger.index is not None else STATUSWORD
        extra.append(((trigger.node, index, trigger.subindex or 0), "the trigger watches it"))
    if trigger.kind == "state" and trigger.node is not None:
        extra.append(((trigger.node, STATUSWORD, 0), "the state trigger watches it"))
    for node in sorted({key[0] for key in keys}):
        if has_statusword.get(node):
            extra.append(((node, STATUSWORD, 0), "the CiA 402 state lane"))
    for key, why in extra:
        if key not in keys:
            keys.append(key)
            added[key] = why
    return Wanted(tuple(keys), added)


def lookup(key: Key, od: ObjectDictionaryModel, units: DriveUnits) -> SignalInfo:
    node, index, subindex = key
    sub = od.get(index, subindex)
    if sub is None:
        raise InvalidValueError(
            f"node {node} has no object {index:04X}h:{subindex:02X} in its dictionary:"
            " pick a signal the OD page lists for it"
        )
    return signal_info(node, sub, units)


def capture_signals(
    keys: Sequence[Key], plans: dict[int, NodePlan], added: dict[Key, str]
) -> list[CaptureSignal]:
    """The capture's signals in request order, each with where it travels."""
    by_key: dict[Key, Placement] = {}
    for plan in plans.values():
        for placement in plan.placements:
            info = placement.signal
            by_key[(info.node, info.index, info.subindex)] = placement
    out: list[CaptureSignal] = []
    for key in keys:
        placement = by_key[key]
        info = placement.signal
        notes = [n for n in (placement.note, _added(added.get(key))) if n]
        out.append(
            CaptureSignal(
                node=info.node,
                index=info.index,
                subindex=info.subindex,
                name=info.name,
                key=info.key,
                source=placement.source,
                quantity=info.scaling.quantity,
                unit=info.scaling.unit,
                raw_unit=info.scaling.raw_unit,
                scale=info.scaling.scale,
                bits=info.bits or 0,
                tpdo=placement.tpdo,
                cob_id=placement.cob_id,
                note="; ".join(notes) or None,
            )
        )
    return out


def _added(why: str | None) -> str | None:
    return None if why is None else f"added: {why}"


def build_core(
    signals: Sequence[CaptureSignal],
    infos: dict[Key, SignalInfo],
    scope_pdos: Mapping[int, Sequence[PdoConfig]],
    request: CaptureRequest,
    output: Output,
) -> CaptureCore:
    post_s = request.duration_s - request.trigger.pre_s
    post_samples = max(1, round(post_s * 1e6 / request.sync_period_us))
    # the samples a time window of pre_s holds at exact SYNC times (floor, float-safe)
    pre_samples = int(request.trigger.pre_s * 1e6 / request.sync_period_us + 1e-6)
    number_of = {(s.node, s.index, s.subindex): i for i, s in enumerate(signals)}
    tracks = [
        SignalTrack(
            number=i,
            node=s.node,
            index=s.index,
            subindex=s.subindex,
            pdo=s.source == "pdo",
            data_type=infos[(s.node, s.index, s.subindex)].data_type,
            remaining=post_samples,
            before=pre_samples,
        )
        for i, s in enumerate(signals)
    ]
    streams: dict[int, Stream] = {}
    for node, pdos in scope_pdos.items():
        for pdo in pdos:
            fields: list[FieldSpec] = []
            numbers: list[int] = []
            offset = 0
            for obj in pdo.mapping:
                info = infos[(node, obj.index, obj.subindex)]
                fields.append(FieldSpec(offset, obj.bits, info.data_type))
                numbers.append(number_of[(node, obj.index, obj.subindex)])
                offset += obj.bits
            streams[pdo.cob_id] = Stream(BatchDecoder(fields), tuple(numbers))
    for i, s in enumerate(signals):
        if s.source == "sdo":
            streams[SDO_STREAM_BASE + i] = Stream(None, (i,))
    trigger = trigger_setup(request.trigger, signals, number_of)
    return CaptureCore(
        tracks,
        streams,
        trigger,
        output,
        pre_s=request.trigger.pre_s,
        post_s=post_s,
        nodes=sorted({s.node for s in signals}),
    )


def trigger_setup(
    trigger: TriggerRequest, signals: Sequence[CaptureSignal], number_of: dict[Key, int]
) -> TriggerSetup:
    if trigger.kind == "none":
        return TriggerSetup("none")
    if trigger.kind == "emcy":
        return TriggerSetup("emcy", emcy_node=trigger.node)
    node = trigger.node or 0
    index = trigger.index if trigger.index is not None else STATUSWORD
    subindex = trigger.subindex or 0
    if trigger.kind == "state":
        index, subindex = STATUSWORD, 0
    number = number_of[(node, index, subindex)]
    label = f"node {node} {index:04X}h:{subindex:02X} {signals[number].name}"
    if trigger.kind == "level":
        return TriggerSetup(
            "level", LevelTrigger(trigger.level or 0.0, trigger.edge, label), number
        )
    if trigger.kind == "bit":
        return TriggerSetup("bit", BitTrigger(trigger.bit or 0, trigger.edge, label), number)
    try:
        target = parse_state(trigger.state) if trigger.state else None
    except ValueError as error:
        raise InvalidValueError(str(error)) from error
    return TriggerSetup("state", StateTrigger(target, f"node {node} CiA 402 state"), number)
