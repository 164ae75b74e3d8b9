"""PDO parameters from a parameter set (DCF) applied through the transactional PDO apply.

A DCF names raw values per entry (1400h–1BFFh); they are laid over what the device has now,
turned into PDO configurations, checked, and applied per the device's procedure in one
transaction (so a CiA 402 node in Operational is taken to Pre-operational and back instead of
every write failing with 08000022). A PDO with problems is not written and its entries are
reported with the reason; entries past a mapping's count are inactive and skipped.

SYNC follows the rule of every PDO write (sync_rule.py): a synchronous PDO while ServoDesk
produces no SYNC and none is heard is a warning, not a refusal. A parameter set comes from a
machine whose controller produces SYNC, so the load writes such PDOs and lists the warnings.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from servodesk.errors import PdoApplyError
from servodesk.od.model import Value
from servodesk.pdo.model import PdoConfig
from servodesk.pdo.read import Key, RawPdo, Slot, read_raw, to_config
from servodesk.pdo.service import PDO_AREA, PdoService
from servodesk.pdo.sync_rule import EXTERNAL, LOADED, sync_warnings
from servodesk_protocol.pdo import MAP_OFFSET, MAX_ENTRIES, RPDO_COMM, TPDO_COMM


def is_pdo_entry(index: int) -> bool:
    return index in PDO_AREA


@dataclass
class FileOutcome:
    written: set[Key] = field(default_factory=set)
    skipped: set[Key] = field(default_factory=set)
    failed: dict[Key, tuple[int | None, str]] = field(default_factory=dict)  # (abort, reason)
    warnings: list[str] = field(default_factory=list)  # written, but worth knowing


def slot_of(index: int) -> Slot:
    comm = index - MAP_OFFSET if (index - RPDO_COMM) % 0x400 >= MAP_OFFSET else index
    if comm >= TPDO_COMM:
        return Slot("tpdo", comm - TPDO_COMM + 1)
    return Slot("rpdo", comm - RPDO_COMM + 1)


async def apply_file_values(
    pdos: PdoService, node: int, values: Mapping[Key, Value], *, actor: str | None = None
) -> FileOutcome:
    """Apply the PDO entries of a parameter set to `node` (keys all in 1400h–1BFFh)."""
    outcome = FileOutcome()
    facts = pdos.facts(node)
    by_slot: dict[Slot, dict[Key, int]] = {}
    for key, value in values.items():
        slot = slot_of(key[0])
        if slot not in facts.slots:
            outcome.failed[key] = (None, f"this drive has no {slot.label}")
        elif not isinstance(value, int) or isinstance(value, bool):
            outcome.failed[key] = (None, "a PDO parameter is a number")
        else:
            by_slot.setdefault(slot, {})[key] = value
    if not by_slot:
        return outcome
    session = pdos.access.session(node)
    configs: dict[Slot, PdoConfig] = {}
    async with session.exclusive(actor) as tx:
        for slot, given in sorted(by_slot.items()):
            current: RawPdo = await read_raw(tx, facts.od, slot, all_entries=True)
            configs[slot] = to_config(RawPdo(slot, {**current.values, **given}), facts.od)
        check = await pdos.check(facts, list(configs.values()), sync_source=None)
        for problem in check.problems:
            slot = Slot(problem.kind, problem.number)
            for key in by_slot.pop(slot, {}):
                outcome.failed[key] = (None, problem.message)
            configs.pop(slot, None)
        loaded = sync_warnings(list(configs.values()), check.sync, then=LOADED)
        try:
            # the set names its SYNC source: the controller of the machine it comes from
            await pdos.apply(node, list(configs.values()), actor=actor, sync_source=EXTERNAL)
        except PdoApplyError as error:
            for slot in configs:
                for key in by_slot[slot]:
                    outcome.failed[key] = (error.abort_code, str(error))
            return outcome
    outcome.warnings = [warning.message for warning in loaded]
    for slot, config in configs.items():
        for key in by_slot[slot]:
            inactive = key[0] == slot.mapping and len(config.mapping) < key[1] <= MAX_ENTRIES
            (outcome.skipped if inactive else outcome.written).add(key)
    return outcome
