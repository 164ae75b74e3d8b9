"""Applying PDO configurations to a device as one transaction, all or nothing.

Inside `NodeSession.exclusive()`: read every sub of the PDOs to change (the snapshot), write
them in the device's procedure (procedure.py), read every value back. On an abort, a timeout or
a value that reads back differently, everything touched is written back from the snapshot in
the same procedure and read again; the error names the failed step, its abort code and whether
the restore worked. A node that refuses PDO changes in its NMT state (abort 08000022, Nanotec
CANopen article) is taken to Pre-operational and returned to its state afterwards, whatever
happens.
"""

from __future__ import annotations

import logging
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass, field

from servodesk.errors import PdoApplyError, SdoAbortError, ServodeskError
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NmtStateName
from servodesk.nodes.session import Transaction
from servodesk.od import ObjectDictionaryModel
from servodesk.pdo.model import PdoConfig
from servodesk.pdo.procedure import Procedure, Write, plan
from servodesk.pdo.read import (
    Key,
    RawPdo,
    Slot,
    read_raw,
    same_value,
    size_of,
    target_values,
)
from servodesk_protocol.sdo_abort import DEVICE_STATE

log = logging.getLogger(__name__)


Nmt = Callable[[NmtCommandName], Awaitable[object]]


@dataclass
class _Failure(Exception):
    step: str
    abort_code: int | None
    detail: str


@dataclass
class _Run:
    """One apply: what was read before, what is wanted, and what was written so far."""

    tx: Transaction
    od: ObjectDictionaryModel
    procedure: Procedure
    snapshot: dict[Slot, RawPdo] = field(default_factory=dict)
    targets: dict[Slot, dict[Key, int]] = field(default_factory=dict)
    touched: dict[Slot, set[Key]] = field(default_factory=dict)

    async def write(self, slot: Slot, step: Write) -> None:
        self.touched.setdefault(slot, set()).add(step.key)
        try:
            await self.tx.download(step.index, step.subindex, step.data)
        except SdoAbortError as abort:
            raise _Failure(step.label, abort.code, abort.meaning) from abort
        except ServodeskError as error:
            raise _Failure(step.label, None, str(error)) from error

    async def verify(self, slot: Slot, expected: dict[Key, int]) -> None:
        """Read the PDO back; every value must be the expected one."""
        try:
            actual = await read_raw(self.tx, self.od, slot, all_entries=True)
        except SdoAbortError as abort:
            step = f"read back {abort.index:04X}h:{abort.subindex:02X}"
            raise _Failure(step, abort.code, abort.meaning) from abort
        except ServodeskError as error:
            raise _Failure(f"read back {slot.label}", None, str(error)) from error
        for key, value in sorted(expected.items()):
            got = actual.get(*key)
            if not same_value(slot, key, value, got):
                size = 2 * size_of(slot, key)
                raise _Failure(
                    f"read back {key[0]:04X}h:{key[1]:02X}",
                    None,
                    f"expected {value:0{size}X}h, the device has {got:0{size}X}h",
                )


async def apply_pdos(
    tx: Transaction,
    od: ObjectDictionaryModel,
    pdos: Sequence[PdoConfig],
    procedure: Procedure,
    *,
    nmt_state: NmtStateName,
    nmt: Nmt,
) -> None:
    """Apply `pdos` (already validated) on the node of `tx`; PdoApplyError when it fails, with
    the device left as it was (or `restored=False` when even that failed)."""
    run = _Run(tx, od, procedure)
    for pdo in sorted(pdos, key=lambda p: (p.kind, p.number)):
        slot = Slot(pdo.kind, pdo.number)
        try:
            run.snapshot[slot] = await read_raw(tx, od, slot, all_entries=True)
        except SdoAbortError as abort:
            step = f"read {abort.index:04X}h:{abort.subindex:02X}"
            raise PdoApplyError(
                tx.node_id, step, abort_code=abort.code, detail=abort.meaning, restored=True
            ) from abort
        run.targets[slot] = target_values(run.snapshot[slot], pdo, od)
    steps = [
        (slot, step)
        for slot, target in run.targets.items()
        for step in plan(slot, run.snapshot[slot].values, target, procedure)
    ]
    if not steps:
        return
    leave_operational = (
        procedure is Procedure.OUTSIDE_OPERATIONAL and nmt_state is NmtStateName.OPERATIONAL
    )
    back_to: NmtCommandName | None = None
    try:
        if leave_operational:
            await nmt(NmtCommandName.PRE_OPERATIONAL)
            back_to = NmtCommandName.START
        try:
            await _write_all(run, steps)
        except _Failure as failure:
            if failure.abort_code != DEVICE_STATE or run_wrote(run) or back_to is not None:
                raise
            # Refused in its present NMT state before anything changed (a node in Operational
            # whose state the tool did not know): Pre-operational, then once more.
            run.touched.clear()
            await nmt(NmtCommandName.PRE_OPERATIONAL)
            back_to = NmtCommandName.START
            await _write_all(run, steps)
    except _Failure as failure:
        restored = await _restore(run)
        raise PdoApplyError(
            tx.node_id,
            failure.step,
            abort_code=failure.abort_code,
            detail=failure.detail,
            restored=restored,
        ) from None
    finally:
        if back_to is not None:
            await _return(nmt, back_to, tx.node_id)


async def _return(nmt: Nmt, command: NmtCommandName, node: int) -> None:
    """Back to the NMT state the node had; a failure here must not hide why the apply failed
    (the node's state is visible in the node list)."""
    try:
        await nmt(command)
    except ServodeskError:
        log.exception("node %d: could not return it to its NMT state after a PDO change", node)


def run_wrote(run: _Run) -> bool:
    """Whether a write before the failing one went through (the failing one is touched too)."""
    return sum(len(keys) for keys in run.touched.values()) > 1


async def _write_all(run: _Run, steps: list[tuple[Slot, Write]]) -> None:
    for slot, step in steps:
        await run.write(slot, step)
    for slot, target in run.targets.items():
        await run.verify(slot, target)


async def _restore(run: _Run) -> bool:
    """Write back from the snapshot everything a failed apply touched; True when every value
    of those PDOs reads back as before."""
    try:
        for slot, keys in sorted(run.touched.items()):
            before = run.snapshot[slot].values
            force = frozenset(keys) | {(slot.comm, 1)}
            for step in plan(slot, run.targets[slot], before, run.procedure, force=force):
                await run.tx.download(step.index, step.subindex, step.data)
        for slot in run.touched:
            await run.verify(slot, dict(run.snapshot[slot].values))
    except (_Failure, ServodeskError):
        return False
    return True
