"""Parameter sets as DCF files (CiA 306): save a drive's configuration, load it back in a safe
order, and compare a drive with a file and with its EDS defaults.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from servodesk.errors import (
    CommTimeoutError,
    ConfirmationRequiredError,
    IdentityMismatchError,
    SdoAbortError,
)
from servodesk.events.texts import say
from servodesk.events.tool_writes import Publish, tool_write, where
from servodesk.models.paramsets import (
    CompareResult,
    CompareRow,
    DcfDifference,
    DcfFailure,
    DcfLoadResult,
)
from servodesk.nodes.access import NodeAccess
from servodesk.nodes.session import NodeSession
from servodesk.od import ObjectDictionaryModel, OdSub, export_dcf
from servodesk.od import datatypes as dt
from servodesk.od.model import Value
from servodesk.od.parser import OdParser
from servodesk.params.dcf_identity import check_identity, load_questions
from servodesk.params.dcf_order import Write, plan_writes, skip_reason
from servodesk.pdo.file_values import apply_file_values, is_pdo_entry
from servodesk.pdo.service import PdoService
from servodesk.sdo import codec
from servodesk.sdo.bulk import BulkOutcome, EntryRead, as_entry_read, read_entries
from servodesk.sdo.jobs import readable_entries
from servodesk.sdo_aborts import abort_meaning
from servodesk_protocol.cob_id import CAN_ID_MASK

CONFIGURATION_ACCESS = frozenset({"rw", "rwr", "rww"})  # readable and writable
IDENTITY = (
    0x1000,  # Device type
    0x1008,  # Manufacturer device name
    0x1009,  # Manufacturer hardware version
    0x100A,  # Manufacturer software version
    0x1018,  # Identity object
)
MAX_TIMEOUTS_IN_A_ROW = 3
NOT_WRITTEN = "not written: the node stopped answering"

Key = tuple[int, int]


def configuration_entries(model: ObjectDictionaryModel) -> list[OdSub]:
    """What a DCF export reads: the readable and writable entries, plus identification."""
    return [
        sub
        for sub in readable_entries(model)
        if sub.access in CONFIGURATION_ACCESS or sub.index in IDENTITY
    ]


def read_problem(read: EntryRead) -> str:
    if read.abort_code is not None:
        return f"SDO abort 0x{read.abort_code:08X} ({abort_meaning(read.abort_code)})"
    return "no answer"


def file_values(model: ObjectDictionaryModel, node: int) -> dict[Key, tuple[OdSub, Value]]:
    """Each entry's ParameterValue, else its DefaultValue, for the drive at `node`.

    `model` is loaded for `node` ($NODEID resolves to it). A value written as a plain number in
    a DCF made for another node (our own exports write COB-IDs so) moves to `node` when its
    CAN-ID is the default one of the file's node: a PDO set copied from node 1 to node 5 then
    uses node 5's CAN-IDs, as the EDS defaults would.
    """
    source = model.device.node_id
    out: dict[Key, tuple[OdSub, Value]] = {}
    for obj in model.objects.values():
        for sub in obj.subs.values():
            value = sub.value if sub.value is not None else sub.default
            if value is None:
                continue
            if (
                source is not None
                and source != node
                and sub.value is not None
                and not sub.value_relative
                and sub.relative
                and isinstance(value, int)
                and isinstance(sub.default, int)
                and value & CAN_ID_MASK == (sub.default - node + source) & CAN_ID_MASK
            ):
                value = value - source + node
            out[(sub.index, sub.subindex)] = (sub, value)
    return out


def _fits(sub: OdSub, value: Value) -> bool:
    """Whether a decoded answer has the entry's type (an empty answer to a number has not)."""
    if dt.is_integer(sub.data_type):
        return isinstance(value, int)
    if dt.is_float(sub.data_type):
        return isinstance(value, float)
    if dt.is_text(sub.data_type):
        return isinstance(value, str)
    return isinstance(value, bytes)


class ParamSetService:
    def __init__(
        self,
        access: NodeAccess,
        parser: OdParser | None = None,
        pdos: PdoService | None = None,
        *,
        publish: Publish | None = None,
    ) -> None:
        self._access = access
        self._publish = publish  # "tool-write" events: each entry written, then the load
        self._parser = parser or OdParser()
        # PDO parameters go through the PDO service's transactional apply; without one (tests
        # of the plain write order) they are written in dcf_order's order
        self._pdos = pdos

    async def _load_file(self, data: bytes, filename: str, node: int) -> ObjectDictionaryModel:
        return await self._parser.parse(data, filename, node_id=node)

    async def _read_all(
        self,
        node: int,
        session: NodeSession,
        subs: list[OdSub],
        progress: Callable[[int, int], None] | None = None,
    ) -> list[EntryRead]:
        reads: list[EntryRead] = []
        outcome = await read_entries(session, subs, as_entry_read, reads, progress=progress)
        if outcome is BulkOutcome.STALLED:
            raise CommTimeoutError(node, f"reading its entries (stopped after {len(reads)})")
        return reads

    async def export_dcf(
        self, node: int, *, progress: Callable[[int, int], None] | None = None
    ) -> str:
        """A DCF of the node's configuration as read from the device now; `progress(done,
        total)` is told after every chunk read (the CLI's progress bar)."""
        model = self._access.od(node)
        session = self._access.session(node)
        reads = await self._read_all(node, session, configuration_entries(model), progress)
        values: dict[Key, Value] = {}
        missing: list[str] = []
        for read in reads:
            sub = read.sub
            value = codec.decode(sub, read.data) if read.data is not None else None
            where = f"{sub.index:04X}h sub {sub.subindex}"
            if value is None:
                missing.append(f"{where}: {read_problem(read)}")
            elif not _fits(sub, value):
                missing.append(f"{where}: unexpected answer {codec.hex_bytes(read.data or b'')}")
            elif isinstance(value, str) and ("\n" in value or "\r" in value):
                missing.append(f"{where}: text with a line break")
            else:
                values[(sub.index, sub.subindex)] = value
        if missing:
            # entries the drive would not give are left out, and the file says which and why
            note = "\n".join(["Not read from the device:", *missing])
            comments = f"{model.device.comments}\n{note}" if model.device.comments else note
            device = dataclasses.replace(model.device, comments=comments)
            model = dataclasses.replace(model, device=device)
        return export_dcf(model, values, node_id=node)

    async def load_dcf(
        self, node: int, data: bytes, filename: str, *, confirm: bool = False
    ) -> DcfLoadResult:
        """Write a parameter set in a safe order, then read back what was written. A set made
        for another kind of device is refused unless `confirm` (IdentityMismatchError)."""
        target = self._access.od(node)
        session = self._access.session(node)
        model = await self._load_file(data, filename, node)
        identity = check_identity(model, filename, self._access.info(node))
        in_file = file_values(model, node)
        questions = load_questions(identity, filename, {k: v for k, (_, v) in in_file.items()})
        if questions and not confirm:
            error = ConfirmationRequiredError if identity.matches else IdentityMismatchError
            raise error(f"{questions[0]}: nothing was written. Load it anyway with confirm")
        values: dict[Key, Value] = {}
        skipped = 0
        for key, (file_sub, value) in sorted(in_file.items()):
            sub = target.get(*key)
            if sub is None or skip_reason(file_sub) or skip_reason(sub):
                skipped += 1
                continue
            values[key] = value
        failed: dict[Key, DcfFailure] = {}
        warnings: list[str] = []
        # the whole set is one transaction on the node: nothing else slips in between
        async with session.exclusive():
            pdo_values: dict[Key, Value] = {}
            if self._pdos is not None:
                pdo_values = {key: v for key, v in values.items() if is_pdo_entry(key[0])}
            plain = {key: v for key, v in values.items() if key not in pdo_values}
            written, stalled = await self._write_plan(session, target, plan_writes(plain), failed)
            if pdo_values and self._pdos is not None and not stalled:
                self._pdos.forget(node)  # whatever happens next, the cached PDOs may be stale
                outcome = await apply_file_values(self._pdos, node, pdo_values)
                warnings += outcome.warnings
                written |= outcome.written
                skipped += len(outcome.skipped)
                for key, (code, message) in outcome.failed.items():
                    failed[key] = self._failure(target, key, code, message)
                for key in outcome.skipped:
                    del values[key]
            differences: list[DcfDifference] = []
            if stalled:
                for key in values.keys() - written - failed.keys():
                    failed[key] = self._failure(target, key, None, NOT_WRITTEN)
            else:
                differences = await self._differences(node, session, target, values, written)
        self._published(node, filename, target, values, written, skipped, len(failed))
        return DcfLoadResult(
            identity=identity,
            written=len(written),
            skipped=skipped,
            failed=sorted(failed.values(), key=lambda f: (f.index, f.subindex)),
            differences=differences,
            warnings=warnings,
        )

    async def compare(self, node: int, data: bytes | None, filename: str) -> CompareResult:
        """Device values against a file (if given) and the dictionary's defaults."""
        target = self._access.od(node)
        reads = await self._read_all(node, self._access.session(node), readable_entries(target))
        model = None if data is None else await self._load_file(data, filename, node)
        in_file = {} if model is None else file_values(model, node)
        identity = (
            None if model is None else check_identity(model, filename, self._access.info(node))
        )
        profile = self._access.profile_data(node)
        units = {} if profile is None else {p.object: p.unit for p in profile.parameters}
        rows: list[CompareRow] = []
        read_only: list[CompareRow] = []
        for read in reads:
            sub = read.sub
            key = (sub.index, sub.subindex)
            device = codec.decode(sub, read.data) if read.data is not None else None
            file_value = in_file[key][1] if key in in_file else None
            default = sub.default
            # status and read-only values are not part of a parameter set: listed apart
            configuration = sub.access in CONFIGURATION_ACCESS
            (rows if configuration else read_only).append(
                CompareRow(
                    index=sub.index,
                    subindex=sub.subindex,
                    name=codec.entry_name(target, sub),
                    unit=sub.unit or units.get(key, ""),
                    device=codec.api_value(device),
                    file=codec.api_value(file_value),
                    default=codec.api_value(default),
                    device_text=(
                        codec.display_text(sub, device)
                        if device is not None
                        else read_problem(read)
                    ),
                    file_text=codec.display_text(sub, file_value),
                    default_text=codec.display_text(sub, default),
                    differs_from_file=(
                        configuration
                        and device is not None
                        and file_value is not None
                        and not codec.same_value(sub, file_value, device)
                    ),
                    differs_from_default=(
                        configuration
                        and device is not None
                        and default is not None
                        and not codec.same_value(sub, default, device)
                    ),
                )
            )
        questions = (
            []
            if identity is None
            else load_questions(identity, filename, {k: v for k, (_, v) in in_file.items()})
        )
        return CompareResult(rows=rows, read_only=read_only, identity=identity, confirm=questions)

    # ------------------------------------------------------------------------------ helpers

    def _published(
        self,
        node: int,
        filename: str,
        target: ObjectDictionaryModel,
        values: dict[Key, Value],
        written: set[Key],
        skipped: int,
        failed: int,
    ) -> None:
        """The timeline: one event per entry written, then one for the load with the counts."""
        if self._publish is None:
            return
        for key in sorted(written):
            sub = target.get(*key)
            value = codec.api_value(values[key])
            name = codec.entry_name(target, sub) if sub is not None else ""
            self._publish(
                tool_write(
                    node,
                    say(
                        "event.dcf_entry",
                        file=filename,
                        where=where(*key),
                        name=name,
                        value=str(value),
                    )
                    if name
                    else say(
                        "event.dcf_entry_unnamed",
                        file=filename,
                        where=where(*key),
                        value=str(value),
                    ),
                    "dcf-entry",
                    file=filename,
                    index=key[0],
                    subindex=key[1],
                    value=value,
                )
            )
        loaded: dict[str, str | int] = {"file": filename, "node": node, "written": len(written)}
        said = (
            say("event.dcf_loaded_failed", **loaded, failed=failed)
            if failed
            else say("event.dcf_loaded", **loaded)
        )
        self._publish(
            tool_write(
                node,
                said,
                "dcf-load",
                file=filename,
                written=len(written),
                skipped=skipped,
                failed=failed,
            )
        )

    async def _write_plan(
        self,
        session: NodeSession,
        target: ObjectDictionaryModel,
        plan: list[Write],
        failed: dict[Key, DcfFailure],
    ) -> tuple[set[Key], bool]:
        """Write every step; aborts are collected in `failed` and never stop the load. Returns
        the entries whose final value was written, and whether the node stopped answering."""
        written: set[Key] = set()
        timeouts = 0
        for step in plan:
            key = (step.index, step.subindex)
            sub = target.get(*key)
            if sub is None:
                continue
            how = "" if step.final else "invalidating the PDO first: "
            try:
                await session.download(step.index, step.subindex, codec.encode(sub, step.value))
            except SdoAbortError as abort:
                timeouts = 0
                failed.setdefault(key, self._failure(target, key, abort.code, how + abort.meaning))
                continue
            except CommTimeoutError as error:
                timeouts += 1
                failed.setdefault(key, self._failure(target, key, None, how + str(error)))
                if timeouts >= MAX_TIMEOUTS_IN_A_ROW:
                    return written, True
                continue
            except (ValueError, OverflowError, UnicodeEncodeError) as error:
                failed.setdefault(key, self._failure(target, key, None, f"{how}{error}"))
                continue
            timeouts = 0
            if step.final:
                written.add(key)
                failed.pop(key, None)  # a failed intermediate step did not stop the final one
        return written, False

    async def _differences(
        self,
        node: int,
        session: NodeSession,
        target: ObjectDictionaryModel,
        values: dict[Key, Value],
        written: set[Key],
    ) -> list[DcfDifference]:
        subs = [sub for key in sorted(written) if (sub := target.get(*key)) and sub.access != "wo"]
        differences: list[DcfDifference] = []
        for read in await self._read_all(node, session, subs):
            sub = read.sub
            key = (sub.index, sub.subindex)
            actual = codec.decode(sub, read.data) if read.data is not None else None
            if not codec.same_value(sub, values[key], actual):
                differences.append(
                    DcfDifference(
                        index=sub.index,
                        subindex=sub.subindex,
                        name=codec.entry_name(target, sub),
                        expected=codec.api_value(values[key]),
                        actual=codec.api_value(actual),
                    )
                )
        return differences

    @staticmethod
    def _failure(
        target: ObjectDictionaryModel, key: Key, code: int | None, message: str
    ) -> DcfFailure:
        sub = target.get(*key)
        return DcfFailure(
            index=key[0],
            subindex=key[1],
            name=codec.entry_name(target, sub) if sub is not None else "",
            abort_code=None if code is None else f"0x{code:08X}",
            message=message,
        )
