"""What PDO validation finds wrong, as plain data: the foundation that both the PDO package
(`servodesk.pdo.validate`, which finds problems) and the error model (`servodesk.errors`'s
`PdoInvalidError`, which carries them) build on, so the errors import nothing above them.
The API schema's `PdoProblem` (servodesk.models.pdo) mirrors `Problem` field for field.

A problem's words are said by id (`PDO_TEXTS`, the page's `server` catalogue: docs/api.md
"Texts in the user's language"). Who else uses a CAN id is an `Owner`: its English words as a
`str` (as the scope's planner and the PDO service pass them on) that also know their id, so a
problem naming it carries the owner's id as `owner_id` and `owner_*` parameters."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Literal

from servodesk.said import Params, SaidText, nested

PdoKind = Literal["rpdo", "tpdo"]

PDO_TEXTS: Mapping[str, str] = MappingProxyType(
    {
        "pdo.twice": "{pdo} is given twice",
        "pdo.no_such": "{pdo} does not exist: this drive has {count} {kind}s ({kind}1–{kind}"
        "{count})",
        "pdo.too_many_objects": "{pdo} maps {objects} objects; a PDO holds at most {max}",
        "pdo.too_many_bits": "{pdo} maps {bits} bits; one CAN frame carries at most {max} (8 "
        "bytes)",
        "pdo.not_in_dictionary": "{pdo}: {what} is not in this drive's dictionary",
        "pdo.not_mappable": "{pdo}: {what} is not PDO-mappable in this drive's dictionary",
        "pdo.read_only": "{pdo}: {what} is read-only ({access}); an RPDO writes into it",
        "pdo.write_only": "{pdo}: {what} is write-only; a TPDO reads it",
        "pdo.no_fixed_size": "{pdo}: {what} is {type}, which has no fixed size and cannot be "
        "mapped",
        "pdo.wrong_bits": "{pdo}: {what} is {type} ({want} bits) but is mapped with {bits} bits",
        "pdo.wrong_bits_boolean": "{pdo}: {what} is {type} (1 or 8 bits) but is mapped with "
        "{bits} bits",
        "pdo.whole_bytes": "{pdo}: {what} is mapped with {bits} bits; this drive maps whole "
        "bytes only (8, 16, 32 bits)",
        "pdo.dummy_unsupported": "{pdo}: dummy entry {dummy}h ({type}) is not supported by this "
        "drive",
        "pdo.dummy_bits": "{pdo}: dummy entry {dummy}h ({type}) takes {want} bits, not {bits}",
        "pdo.transmission_range": "{pdo} transmission type {t} is outside 0–255",
        "pdo.transmission_reserved": "{pdo} transmission type {t} is reserved (use 0–240 or "
        "252–255)",
        "pdo.rtr_rpdo": "{pdo} transmission type {t} (remote request) is for TPDOs only; use "
        "0–240 or 254/255",
        "pdo.rtr_unsupported": "{pdo} transmission type {t} (remote request): this drive has no "
        "RTR-triggered PDOs",
        "pdo.inhibit_range": "{pdo} inhibit time {value} is outside 0–{limit}",
        "pdo.event_timer_range": "{pdo} event timer {value} is outside 0–{limit}",
        "pdo.sync_start_range": "{pdo} SYNC start value {value} is outside 0–{limit}",
        "pdo.inhibit_missing": "{pdo} sets the inhibit time but this drive has no {entry} "
        "inhibit time",
        "pdo.event_timer_missing": "{pdo} sets the event timer but this drive has no {entry} "
        "event timer",
        "pdo.sync_start_missing": "{pdo} sets the SYNC start value but this drive has no {entry} "
        "SYNC start value",
        "pdo.can_id_range": "{pdo} CAN id {can_id}h is not an 11-bit identifier (0–7FFh)",
        "pdo.can_id_fixed": "{pdo} CAN id {can_id}h cannot be set: this drive fixes it at "
        "{fixed}h ({base}h + node id); only the valid bit can change",
        "pdo.can_id_reserved": "{pdo} CAN id {can_id}h is reserved by CiA 301 ({use})",
        "pdo.can_id_used": "{pdo} CAN id {can_id}h is already used by {owner}",
        "pdo.sync_missing_ask": "{pdo} is synchronous ({words}) but no SYNC is produced or heard "
        "on the bus: it acts only once SYNC comes; start the SYNC producer, or confirm that SYNC "
        'comes from the machine\'s controller (sync_source "external")',
        "pdo.sync_missing_loaded": "{pdo} is synchronous ({words}) but no SYNC is produced or "
        "heard on the bus: it acts only once SYNC comes; written as the parameter set gives it: "
        "the machine's controller is to produce SYNC",
        # who uses a CAN id (Owner)
        "owner.node_service": "node {node} {service}",
        "owner.node_pdo": "node {node} {pdo}",
        "owner.this_node": "this node's {service}",
        "owner.sync": "SYNC",
        "owner.pdo": "{pdo}",
    }
)


class Owner(SaidText):
    """Who uses a CAN id, in English, with its message id and parameters."""

    TEXTS = PDO_TEXTS


def owner_params(owner: str) -> Params:
    """`owner` as the parameters of a problem that names it (`owner`, `owner_id`, `owner_*`)."""
    return nested("owner", owner)


@dataclass(frozen=True, slots=True)
class Problem:
    """One reason a configuration cannot be applied, in words, with the object it concerns."""

    kind: PdoKind
    number: int
    message: str
    index: int | None = None
    subindex: int | None = None
    message_id: str | None = None
    params: Params = field(default_factory=dict)


def problem(
    kind: PdoKind,
    number: int,
    message_id: str,
    index: int | None = None,
    subindex: int | None = None,
    /,
    **params: str | int,
) -> Problem:
    """A problem said by id; `params` fill its template (PDO_TEXTS)."""
    message = PDO_TEXTS[message_id].format(**params)
    return Problem(kind, number, message, index, subindex, message_id, params)
