"""The order in which one PDO is changed on a device (pure; table-tested).

Each drive family accepts a PDO change in its own way:
- MDi-S1-C (MDi-S1-C CANopen manual §2.5.4; CiA 301 §7.5.2.35–38): mapping and communication
  parameters change only while the PDO is invalid. Invalidate the COB-ID (bit 31), mapping
  count 0, the entries, the count, the other communication parameters, then the COB-ID again
  (valid if it is to be). CiA 301 devices accept this order, so it is the default.
- Kinco (Kinco servo CANopen manual §5.4.4–§5.4.6): the PDO stays valid; the manual writes
  the communication parameters (transmission type, inhibit time) first, then the entries with
  the mapping count last (count 0 first, as CiA 301 needs to change entries). Only a new
  identifier needs the PDO invalid around the change (CiA 301 §7.5.2.35).
- Nanotec-style CiA 402 (Nanotec CANopen article): no PDO parameter changes in Operational
  (abort 08000022). The node is taken to Pre-operational around the MDi order (see apply.py).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum

from servodesk.pdo.read import Key, Slot, size_of
from servodesk_data import DriveData, PdoRemapRule
from servodesk_protocol.pdo import COB_INVALID
from servodesk_protocol.pdo import SUB_COB_ID as COB

KINCO = "kinco"  # profile name


class Procedure(StrEnum):
    INVALIDATE_FIRST = "invalidate_first"  # MDi-S1-C manual §2.5.4, CiA 301
    COMM_FIRST = "comm_first"  # Kinco manual §5.4.4–§5.4.6
    OUTSIDE_OPERATIONAL = "outside_operational"  # Nanotec article: Pre-operational around it

    @property
    def comm_first(self) -> bool:
        return self is Procedure.COMM_FIRST

    @property
    def words(self) -> str:
        return PROCEDURE_WORDS[self]


PROCEDURE_WORDS: Mapping[Procedure, str] = {
    Procedure.INVALIDATE_FIRST: (
        "invalidate the COB-ID, mapping count 0, entries, count, communication parameters, "
        "COB-ID (MDi-S1-C CANopen manual §2.5.4)"
    ),
    Procedure.COMM_FIRST: (
        "the PDO stays valid: communication parameters, mapping count 0, entries, count "
        "(Kinco servo CANopen manual §5.4.4–§5.4.6); invalid around a new CAN id"
    ),
    Procedure.OUTSIDE_OPERATIONAL: (
        "Pre-operational, then invalidate the COB-ID, mapping count 0, entries, count, "
        "communication parameters, COB-ID, then back to the previous NMT state "
        "(Nanotec CANopen article: no PDO changes in Operational, abort 08000022)"
    ),
}


# a node without a profile: what CiA 301 asks of every device (no manual to cite)
GENERIC_WORDS = (
    "invalidate the COB-ID (bit 31), mapping count 0, entries, count, communication parameters, "
    "COB-ID valid again (CiA 301 §7.5.2.35–38)"
)


def procedure_words(procedure: Procedure, data: DriveData | None) -> str:
    """How the drive takes a new mapping, in words, citing where that comes from."""
    if data is None and procedure is Procedure.INVALIDATE_FIRST:
        return GENERIC_WORDS
    return procedure.words


def procedure_for(profile: str, data: DriveData | None) -> Procedure:
    if data is not None and data.quirks.pdo_remap_rule is PdoRemapRule.OUTSIDE_OPERATIONAL:
        return Procedure.OUTSIDE_OPERATIONAL
    if profile == KINCO or (
        data is not None and data.quirks.pdo_remap_rule is PdoRemapRule.WHILE_UNMAPPED
    ):
        return Procedure.COMM_FIRST
    return Procedure.INVALIDATE_FIRST


@dataclass(frozen=True, slots=True)
class Write:
    index: int
    subindex: int
    value: int
    size: int  # bytes

    @property
    def key(self) -> Key:
        return (self.index, self.subindex)

    @property
    def data(self) -> bytes:
        return self.value.to_bytes(self.size, "little")

    @property
    def label(self) -> str:
        """`write 1A00h:01 = 60410010h`"""
        return f"write {self.index:04X}h:{self.subindex:02X} = {self.value:0{2 * self.size}X}h"


def plan(
    slot: Slot,
    before: Mapping[Key, int],
    after: Mapping[Key, int],
    procedure: Procedure,
    *,
    force: frozenset[Key] = frozenset(),
) -> list[Write]:
    """The writes that take one PDO from `before` to `after` (raw values by (index, sub)).

    Only what differs is written, plus the keys in `force` (a restore writes back everything
    a failed apply touched, whatever the device holds now)."""
    cob_key = (slot.comm, COB)
    changed = {key for key in after if key in force or before.get(key) != after[key]}
    if not changed:
        return []

    def write(key: Key, value: int) -> Write:
        return Write(key[0], key[1], value, size_of(slot, key))

    cob_before = before.get(cob_key, after[cob_key])
    cob_after = after[cob_key]
    mapping = sorted(key for key in changed if key[0] == slot.mapping and key[1] != 0)
    count_changes = (slot.mapping, 0) in changed or bool(mapping)
    comm = sorted(key for key in changed if key[0] == slot.comm and key != cob_key)
    identifier_changes = (cob_before ^ cob_after) & ~COB_INVALID
    restoring = cob_key in force
    out: list[Write] = []
    invalidated = False
    # COMM_FIRST drives change a valid PDO's parameters; only a new identifier needs it invalid
    needs_invalid = identifier_changes or (
        not procedure.comm_first and (mapping or count_changes or comm)
    )
    if restoring or (needs_invalid and not cob_before & COB_INVALID):
        # a restore does not know what the device holds: invalidate with the identifier it
        # goes back to (always accepted, also by drives whose identifier is fixed)
        out.append(write(cob_key, (cob_after if restoring else cob_before) | COB_INVALID))
        invalidated = True
    map_writes: list[Write] = []
    if count_changes:
        if before.get((slot.mapping, 0)) != 0 or (slot.mapping, 0) in force:
            map_writes.append(write((slot.mapping, 0), 0))  # entries change only at count 0
        map_writes += [write(key, after[key]) for key in mapping]
        map_writes.append(write((slot.mapping, 0), after[(slot.mapping, 0)]))
    comm_writes = [write(key, after[key]) for key in comm]
    out += comm_writes + map_writes if procedure.comm_first else map_writes + comm_writes
    last = out[0].value if invalidated else cob_before
    if cob_after != last or (cob_key in changed and not invalidated):
        out.append(write(cob_key, cob_after))
    return out
