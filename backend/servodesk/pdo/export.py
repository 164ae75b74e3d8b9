"""A node's PDO configuration as text other tools take: CiA 306 DCF sections and a python-canopen
script. Both carry the same values the PDO service writes: communication parameter (14xxh/18xxh)
and mapping parameter (16xxh/1Axxh) of every PDO given.
"""

from __future__ import annotations

from collections.abc import Sequence

from servodesk.od import datatypes as dt
from servodesk.od.model import ObjectDictionaryModel
from servodesk.pdo.model import PdoConfig
from servodesk.pdo.validate import object_label, pdo_label
from servodesk_protocol.pdo import (
    COB_INVALID,
    COB_NO_RTR,
    MAX_ENTRIES,
    SUB_COB_ID,
    SUB_EVENT_TIMER,
    SUB_INHIBIT,
    SUB_SYNC_START,
    SUB_TRANSMISSION,
    comm_index,
    map_index,
)

# CiA 301 §7.5.2.35/36: name and type of each communication parameter sub-index
_COMM_SUBS: dict[int, tuple[str, int]] = {
    0: ("Highest sub-index supported", dt.DataType.UNSIGNED8),
    SUB_COB_ID: ("COB-ID", dt.DataType.UNSIGNED32),
    SUB_TRANSMISSION: ("Transmission type", dt.DataType.UNSIGNED8),
    SUB_INHIBIT: ("Inhibit time", dt.DataType.UNSIGNED16),
    SUB_EVENT_TIMER: ("Event timer", dt.DataType.UNSIGNED16),
    SUB_SYNC_START: ("SYNC start value", dt.DataType.UNSIGNED8),
}
_RECORD = 0x9
_VAR = 0x7


def comm_values(pdo: PdoConfig, od: ObjectDictionaryModel | None = None) -> dict[int, int]:
    """Sub-index -> value of `pdo`'s communication parameter (sub 0 excluded).

    With `od`, only the sub-indices the drive has (Kinco's 1400h stops at sub 2), and bit 30
    (no RTR) kept as the drive's default COB-ID has it; without, what CiA 301 defines for the
    direction, the optional ones only when they are set.
    """
    index = comm_index(pdo.direction, pdo.number)
    cob = pdo.cob_id | (0 if pdo.valid else COB_INVALID)
    default = od.get(index, SUB_COB_ID) if od is not None else None
    if default is not None and isinstance(default.default, int) and default.default & COB_NO_RTR:
        cob |= COB_NO_RTR
    values = {
        SUB_COB_ID: cob,
        SUB_TRANSMISSION: pdo.transmission_type,
        SUB_INHIBIT: pdo.inhibit_time_100us,
        SUB_EVENT_TIMER: pdo.event_timer_ms,
        SUB_SYNC_START: pdo.sync_start,
    }
    if od is not None and index in od.objects:
        return {sub: value for sub, value in values.items() if od.get(index, sub) is not None}
    # a TPDO has inhibit time and event timer in every CiA 301 device; an RPDO ignores them
    wanted = {SUB_COB_ID, SUB_TRANSMISSION}
    wanted |= {SUB_INHIBIT, SUB_EVENT_TIMER} if pdo.kind == "tpdo" else set()
    return {sub: v for sub, v in values.items() if sub in wanted or v}


def dcf_fragment(
    node: int, pdos: Sequence[PdoConfig], *, od: ObjectDictionaryModel | None = None
) -> str:
    """CiA 306 DCF sections ([1400], [1400sub1] ..., ParameterValue=) for every PDO given."""
    lines = [
        f"; PDO configuration of node {node}, written by ServoDesk.",
        "; CiA 306 DCF sections: paste them into the node's DCF in place of these objects.",
    ]
    for pdo in _ordered(pdos):
        comm = comm_values(pdo, od)
        index = comm_index(pdo.direction, pdo.number)
        name = f"{pdo_label(pdo.kind, pdo.number)} communication parameter"
        subs = [(0, *_COMM_SUBS[0], "ro", max(comm))]
        subs += [(sub, *_COMM_SUBS[sub], "rw", value) for sub, value in comm.items()]
        _record(lines, index, name, subs, od)
        mapping = map_index(pdo.direction, pdo.number)
        name = f"{pdo_label(pdo.kind, pdo.number)} mapping parameter"
        raws = [obj.entry.raw for obj in pdo.mapping]
        slots = max(MAX_ENTRIES, len(raws), _highest(od, mapping))
        subs = [(0, "Number of mapped objects", dt.DataType.UNSIGNED8, "rw", len(raws))]
        subs += [
            (
                n,
                f"Mapped object {n}",
                dt.DataType.UNSIGNED32,
                "rw",
                raws[n - 1] if n <= len(raws) else 0,
            )
            for n in range(1, slots + 1)
        ]
        _record(lines, mapping, name, subs, od)
    return "\n".join(lines) + "\n"


def _ordered(pdos: Sequence[PdoConfig]) -> list[PdoConfig]:
    return sorted(pdos, key=lambda pdo: comm_index(pdo.direction, pdo.number))


def _highest(od: ObjectDictionaryModel | None, index: int) -> int:
    obj = od.objects.get(index) if od is not None else None
    return max(obj.subs) if obj is not None and obj.subs else 0


def _record(
    lines: list[str],
    index: int,
    name: str,
    subs: Sequence[tuple[int, str, int, str, int]],
    od: ObjectDictionaryModel | None,
) -> None:
    obj = od.objects.get(index) if od is not None else None
    lines += ["", f"[{index:04X}]", f"ParameterName={obj.name if obj else name}"]
    lines += [f"ObjectType=0x{_RECORD:X}", f"SubNumber={len(subs)}"]
    for sub, sub_name, data_type, access, value in subs:
        known = od.get(index, sub) if od is not None else None
        text = f"0x{value:08X}" if data_type == dt.DataType.UNSIGNED32 else str(value)
        lines += ["", f"[{index:04X}sub{sub:X}]"]
        lines.append(f"ParameterName={known.name if known else sub_name}")
        lines += [f"ObjectType=0x{_VAR:X}", f"DataType=0x{data_type:04X}"]
        lines += [f"AccessType={known.access if known else access}", "PDOMapping=0"]
        lines += [f"DefaultValue={known.default_raw if known and known.default_raw else text}"]
        lines.append(f"ParameterValue={text}")


def canopen_snippet(
    node: int,
    pdos: Sequence[PdoConfig],
    *,
    eds_name: str = "drive.eds",
    od: ObjectDictionaryModel | None = None,
    interface: str = "socketcan",
    channel: str = "can0",
    bitrate: int = 500_000,
) -> str:
    """A python-canopen (2.x) script that writes the same PDO configuration to node `node`."""
    lines = [
        f'"""Configure the PDOs of CANopen node {node} with python-canopen (written by ServoDesk).',
        "",
        "Run it with the drive on the bus and its EDS beside the script. The drive is put in",
        "Pre-operational first: some drives refuse PDO changes in Operational (abort 08000022h),",
        "others only while the PDO is invalid, which PdoMap.save() takes care of.",
        '"""',
        "",
        "import canopen",
        "",
        f"NODE_ID = {node}",
        f"EDS = {eds_name!r}",
        "",
        "",
        "def map_object(pdo, index, subindex, bits):",
        "    # add_variable only logs a warning for an object the EDS lacks: stop instead",
        "    if pdo.add_variable(index, subindex, bits) is None:",
        '        raise SystemExit(f"{index:04X}h:{subindex:02X} is not in {EDS}")',
        "",
        "",
        "network = canopen.Network()",
        f"network.connect(interface={interface!r}, channel={channel!r}, bitrate={bitrate})",
        "try:",
        "    node = network.add_node(NODE_ID, EDS)",
        '    node.nmt.state = "PRE-OPERATIONAL"',
        "    node.rpdo.read()",
        "    node.tpdo.read()",
    ]
    for pdo in _ordered(pdos):
        lines += ["", *_pdo_lines(pdo, od)]
    lines += [
        "",
        "    node.rpdo.save()",
        "    node.tpdo.save()",
        "    # node.store()  # 1010h:01 'save all parameters', if the drive has it",
        '    # node.nmt.state = "OPERATIONAL"  # PDOs run only in Operational',
        "finally:",
        "    network.disconnect()",
    ]
    return "\n".join(lines) + "\n"


def _pdo_lines(pdo: PdoConfig, od: ObjectDictionaryModel | None) -> list[str]:
    label = pdo_label(pdo.kind, pdo.number)
    state = "valid" if pdo.valid else "invalid"
    lines = [
        f"    # {label}: {state}, CAN id {pdo.cob_id:X}h, transmission type"
        f" {pdo.transmission_type}",
        f"    pdo = node.{pdo.kind}[{pdo.number}]",
        "    pdo.clear()",
    ]
    for obj in pdo.mapping:
        what = object_label(obj.index, obj.subindex, obj.name)
        lines.append(
            f"    map_object(pdo, 0x{obj.index:04X}, 0x{obj.subindex:02X}, {obj.bits})  # {what}"
        )
    comm = comm_values(pdo, od)
    lines.append(f"    pdo.cob_id = 0x{pdo.cob_id:03X}")
    lines.append(f"    pdo.trans_type = {pdo.transmission_type}")
    # python-canopen writes only what is set; an attribute for a missing sub-index would fail
    for sub, attribute in (
        (SUB_INHIBIT, "inhibit_time"),
        (SUB_EVENT_TIMER, "event_timer"),
        (SUB_SYNC_START, "sync_start_value"),
    ):
        if sub in comm:
            lines.append(f"    pdo.{attribute} = {comm[sub]}")
    lines.append(f"    pdo.enabled = {pdo.valid}")
    return lines
