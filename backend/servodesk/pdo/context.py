"""What the pure PDO cores need to know about one node: its PDO counts, mapping granularity,
RTR support, fixed CAN ids, the procedure it accepts changes in, and the bus around it."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from servodesk.od import ObjectDictionaryModel
from servodesk.pdo.procedure import Procedure, procedure_for, procedure_words
from servodesk.pdo.read import Slot, slots
from servodesk.pdo.validate import PdoContext
from servodesk_data import DriveData

BYTE = 8  # EDS [DeviceInfo] Granularity: 8 = whole bytes only


@dataclass(frozen=True)
class NodePdoFacts:
    """A node's PDO-related facts, from its profile (quirks) or else its dictionary."""

    node: int
    profile: str
    od: ObjectDictionaryModel
    slots: tuple[Slot, ...]
    byte_granular: bool
    rtr_supported: bool
    fixed_cob_ids: int
    procedure: Procedure
    procedure_text: str  # the procedure in words, citing the manual section

    @property
    def rpdo_count(self) -> int:
        return sum(1 for slot in self.slots if slot.kind == "rpdo")

    @property
    def tpdo_count(self) -> int:
        return sum(1 for slot in self.slots if slot.kind == "tpdo")

    def context(self, *, sync_producing: bool, other_ids: Mapping[int, str]) -> PdoContext:
        return PdoContext(
            node=self.node,
            od=self.od,
            byte_granular=self.byte_granular,
            rpdo_count=self.rpdo_count,
            tpdo_count=self.tpdo_count,
            sync_producing=sync_producing,
            other_ids=other_ids,
            rtr_supported=self.rtr_supported,
            fixed_cob_ids=self.fixed_cob_ids,
        )


def node_facts(
    node: int, profile: str, od: ObjectDictionaryModel, data: DriveData | None
) -> NodePdoFacts:
    if data is not None:
        quirks = data.quirks
        byte_granular = quirks.pdo_byte_granular
        rtr = quirks.pdo_rtr_transmission
        fixed = quirks.pdo_fixed_cob_ids
    else:
        # a generic node: what its dictionary says (Granularity 8 = byte mapping only)
        granularity = od.device.granularity
        byte_granular = granularity is not None and granularity >= BYTE
        rtr, fixed = True, 0
    procedure = procedure_for(profile, data)
    return NodePdoFacts(
        node=node,
        profile=profile,
        od=od,
        slots=tuple(slots(od, data)),
        byte_granular=byte_granular,
        rtr_supported=rtr,
        fixed_cob_ids=fixed,
        procedure=procedure,
        procedure_text=procedure_words(procedure, data),
    )
