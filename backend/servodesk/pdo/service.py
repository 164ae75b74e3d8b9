"""The PDO service: read a node's PDOs, validate, apply as one transaction, recommend, export,
estimate bus load and run the live check. The I/O shell around the pure cores (validate,
bus_load, recommended, decode, export) and the transactional apply (apply.py).

Each node's PDOs are cached for the bus-wide views (bus load, CAN-id collisions with other
nodes) and the scope's plan: refreshed by every read and apply, dropped on NMT commands,
boot-ups, dictionary changes, bus changes and every SDO write to a PDO parameter seen on the bus
(`forget`, `on_event`, `on_bus`, write_watch.py). A read that a change overtook is not kept (a
generation per node), and callers asking at once share one read.
"""

from __future__ import annotations

import asyncio
import dataclasses
from collections.abc import Callable, Mapping, Sequence
from functools import partial
from typing import Literal

import canopen

from servodesk.errors import InvalidValueError, PdoInvalidError, ServodeskError
from servodesk.events.bus import BusEvent, EventKind
from servodesk.models.bus import BusState, BusStatus
from servodesk.models.network import SyncConfig
from servodesk.models.pdo import (
    BusLoadResult,
    LiveCheck,
    PdoProblem,
    PdoRules,
    PdoSync,
    PdoValidation,
)
from servodesk.nodes.access import NodeAccess
from servodesk.pdo.apply import apply_pdos
from servodesk.pdo.bus_load import DEFAULT_MASTER_PERIOD_MS, bus_load
from servodesk.pdo.context import NodePdoFacts, node_facts
from servodesk.pdo.export import canopen_snippet, dcf_fragment
from servodesk.pdo.live_check import LiveChecks
from servodesk.pdo.model import PdoConfig
from servodesk.pdo.procedure import Procedure
from servodesk.pdo.read import Runner, read_raw, to_config, with_names
from servodesk.pdo.recommended import recommended
from servodesk.pdo.sync_heard import SyncHeard
from servodesk.pdo.sync_rule import SyncCheck, SyncPresence, SyncSource, sync_warnings
from servodesk.pdo.validate import used_ids, validate
from servodesk.pdo_problems import Problem
from servodesk_protocol.pdo import MAP_OFFSET, RPDO_COMM, TPDO_MAP

PDO_AREA = range(RPDO_COMM, TPDO_MAP + MAP_OFFSET)  # 1400h–1BFFh: communication and mapping
DEFAULT_BITRATE = 500_000  # bit/s, when the bus does not say (virtual bus)
DEFAULT_THRESHOLD = 70.0  # percent
ExportFormat = Literal["dcf", "python"]
# after an apply: (node, the PDOs cached before or None, the PDOs read back) — the timeline
Applied = Callable[[int, Sequence[PdoConfig] | None, Sequence[PdoConfig]], None]


class PdoService:
    def __init__(
        self,
        access: NodeAccess,
        *,
        known_nodes: Callable[[], Sequence[int]],
        network: Callable[[], canopen.Network],
        bitrate: Callable[[], int | None],
        sync: Callable[[], SyncConfig],
        on_applied: Applied | None = None,
    ) -> None:
        self.access = access
        self._on_applied = on_applied
        self._known_nodes = known_nodes
        self._network = network
        self._bitrate = bitrate
        self._sync = sync
        self._cache: dict[int, list[PdoConfig]] = {}
        # bumped by every `forget` (also from the notifier thread): a read that started before
        # a change must not be cached after it
        self._generation: dict[int, int] = {}
        self._epoch = 0  # bumped when every node is forgotten (a bus change)
        self._reading: dict[int, asyncio.Task[list[PdoConfig]]] = {}
        self._live = LiveChecks()
        # SYNC from another producer (the machine's controller): the app feeds it every frame
        self.sync_heard = SyncHeard()

    # ------------------------------------------------------------------ reading

    def facts(self, node: int) -> NodePdoFacts:
        info = self.access.info(node)
        return node_facts(node, info.profile, self.access.od(node), self.access.profile_data(node))

    async def read(self, node: int) -> list[PdoConfig]:
        """Every PDO of the node as the device has it now (and the cache refreshed)."""
        facts = self.facts(node)
        generation = self._stamp(node)
        async with self.access.session(node).exclusive(reading=True) as tx:  # one picture
            pdos = await _read_all(tx, facts)
        self._keep(node, generation, pdos)
        return pdos

    def _stamp(self, node: int) -> tuple[int, int]:
        return self._epoch, self._generation.get(node, 0)

    def _keep(self, node: int, stamp: tuple[int, int], pdos: list[PdoConfig]) -> None:
        """Cache what was read unless a change came while it was read."""
        if self._stamp(node) == stamp:
            self._cache[node] = pdos

    def rules(self, node: int) -> PdoRules:
        return rules_of(self.facts(node))

    def known(self, node: int) -> list[PdoConfig] | None:
        """The cached PDOs of `node` without asking the device (None: not read since the last
        change); a change gives a new list, never the old one altered."""
        return self._cache.get(node)

    def network(self) -> canopen.Network:
        """The connection PDOs travel on now (BusNotConnectedError without one)."""
        return self._network()

    async def cached(self, node: int) -> list[PdoConfig]:
        """The node's PDOs as the cache knows them, read once when it does not (callers
        asking meanwhile share that read; one caller giving up does not cancel it)."""
        known = self._cache.get(node)
        if known is not None:
            return known
        task = self._reading.get(node)
        if task is None:
            task = asyncio.create_task(self.read(node))
            self._reading[node] = task
            task.add_done_callback(partial(self._read_done, node))
        return await asyncio.shield(task)

    def _read_done(self, node: int, task: asyncio.Task[list[PdoConfig]]) -> None:
        self._reading.pop(node, None)
        if not task.cancelled():
            task.exception()  # retrieved: every caller may have given up waiting

    # ------------------------------------------------------------------ checking and applying

    async def validate(
        self,
        node: int,
        pdos: Sequence[PdoConfig],
        *,
        threshold: float = DEFAULT_THRESHOLD,
        master_period_ms: int = DEFAULT_MASTER_PERIOD_MS,
        sync_source: SyncSource | None = None,
    ) -> PdoValidation:
        """`ok`: an apply of the same PDOs and `sync_source` would be accepted."""
        facts = self.facts(node)
        check = await self.check(facts, pdos, sync_source=sync_source)
        current = await self.cached(node)
        load = await self.bus_load(
            threshold, master_period_ms=master_period_ms, replace={node: _merged(current, pdos)}
        )
        return PdoValidation(
            ok=not check.blocking,
            problems=_rows(check.problems),
            warnings=_rows(check.warnings),
            sync=self.sync_state(sync_source),
            bus_load=load,
        )

    async def apply(
        self,
        node: int,
        pdos: Sequence[PdoConfig],
        *,
        actor: str | None = None,
        sync_source: SyncSource | None = None,
    ) -> list[PdoConfig]:
        """Validate, then change the device's PDOs in its own procedure as one transaction;
        returns every PDO read back. PdoInvalidError (nothing written) or PdoApplyError
        (the device left as it was). A synchronous PDO while nothing produces SYNC is written
        only when `sync_source` says where SYNC comes from (sync_rule.py)."""
        facts = self.facts(node)
        blocking = (await self.check(facts, pdos, sync_source=sync_source)).blocking
        if blocking:
            raise PdoInvalidError(node, blocking)
        access = self.access
        before = self._cache.get(node)
        async with access.session(node).exclusive(actor) as tx:
            try:
                await apply_pdos(
                    tx,
                    facts.od,
                    pdos,
                    facts.procedure,
                    nmt_state=access.info(node).nmt_state,
                    nmt=lambda command: access.nmt(node, command),
                )
            finally:
                self.forget(node)
            stamp = self._stamp(node)
            result = await _read_all(tx, facts)
        self._keep(node, stamp, result)
        if self._on_applied is not None:
            self._on_applied(node, before, result)
        if self._live.active(node):  # decode with the new mapping
            self._live.start(node, self._network(), result, facts.od)
        return result

    async def check(
        self, facts: NodePdoFacts, pdos: Sequence[PdoConfig], *, sync_source: SyncSource | None
    ) -> SyncCheck:
        """The problems of `pdos` on this node, and the SYNC rule's warnings apart."""
        others = await self._other_ids(facts.node)
        sync = self.sync_presence(sync_source)
        # SYNC known to be on the bus (or coming) takes 080h from the PDOs
        on_bus = sync.present or sync.acknowledged
        problems = validate(pdos, facts.context(sync_producing=on_bus, other_ids=others))
        return SyncCheck(problems, sync_warnings(pdos, sync), sync)

    def sync_presence(self, source: SyncSource | None = None) -> SyncPresence:
        return SyncPresence(self._sync().producing, self.sync_heard.seen().recent, source)

    def sync_state(self, source: SyncSource | None = None) -> PdoSync:
        """Where SYNC comes from now, as the API shows it."""
        heard = self.sync_heard.seen()
        own = self._sync()
        return PdoSync(
            producing=own.producing,
            period_us=own.period_us if own.producing else None,
            heard=heard.recent,
            heard_frames=heard.frames,
            heard_period_us=heard.period_us if heard.recent else None,
            source=source,
        )

    async def taken_ids(self, node: int) -> dict[int, str]:
        """The CAN ids the other known nodes use (services and valid PDOs): what a new PDO of
        `node` must not take."""
        return await self._other_ids(node)

    async def _other_ids(self, node: int) -> dict[int, str]:
        ids: dict[int, str] = {}
        for other, pdos in (await self._all_pdos([node]))[0].items():
            ids.update(used_ids(other, pdos))
        return ids

    async def recommended(self, node: int, modes: Sequence[str]) -> list[PdoConfig]:
        facts = self.facts(node)
        try:
            pdos = recommended(
                facts.profile,
                modes,
                node=node,
                od=facts.od,
                byte_granular=facts.byte_granular,
                rpdo_count=facts.rpdo_count,
                tpdo_count=facts.tpdo_count,
                current=await self.cached(node),
            )
        except ValueError as error:
            raise InvalidValueError(str(error)) from error
        return [with_names(pdo, facts.od) for pdo in pdos]

    async def export(self, node: int, fmt: ExportFormat) -> str:
        pdos = await self.read(node)
        if fmt == "dcf":
            return dcf_fragment(node, pdos)
        return canopen_snippet(node, pdos, eds_name=self.access.info(node).od_filename)

    # ------------------------------------------------------------------ bus load

    async def bus_load(
        self,
        threshold: float = DEFAULT_THRESHOLD,
        *,
        master_period_ms: int = DEFAULT_MASTER_PERIOD_MS,
        replace: Mapping[int, Sequence[PdoConfig]] | None = None,
        sync_period_us: int | None = None,
    ) -> BusLoadResult:
        """Per node and total, at the tool's SYNC period (else the assumed master cycle for
        the master's event-driven RPDOs) and the bus bitrate; `sync_period_us` computes it for
        another SYNC period (the scope's, before it starts)."""
        pdos_by_node, notes = await self._all_pdos(list(replace or ()))
        pdos_by_node.update(replace or {})
        bitrate = self._bitrate()
        if bitrate is None:
            bitrate = DEFAULT_BITRATE
            notes.append(
                f"the bus bitrate is not known (virtual or simulated bus): "
                f"computed for {DEFAULT_BITRATE // 1000} kbit/s"
            )
        sync = self._sync()
        if sync_period_us is None and sync.producing:
            sync_period_us = sync.period_us
        load = bus_load(
            pdos_by_node,
            bitrate=bitrate,
            sync_period_us=sync_period_us,
            threshold_percent=threshold,
            master_period_ms=master_period_ms,
        )
        result = BusLoadResult.model_validate(dataclasses.asdict(load))
        result.notes = notes + result.notes
        return result

    async def _all_pdos(
        self, skip: Sequence[int]
    ) -> tuple[dict[int, Sequence[PdoConfig]], list[str]]:
        """The PDOs of every known node except `skip` (read in parallel where not cached);
        a node that cannot be read is left out with a note."""
        nodes = [node for node in self._known_nodes() if node not in skip]
        reads = await asyncio.gather(*(self.cached(n) for n in nodes), return_exceptions=True)
        out: dict[int, Sequence[PdoConfig]] = {}
        notes: list[str] = []
        for node, read in zip(nodes, reads, strict=True):
            if isinstance(read, ServodeskError):
                notes.append(f"node {node} is not counted: its PDOs could not be read ({read})")
            elif isinstance(read, BaseException):
                raise read
            else:
                out[node] = read
        return out, notes

    # ------------------------------------------------------------------ live check

    async def start_live(self, node: int) -> LiveCheck:
        pdos = await self.read(node)
        return self._live.start(node, self._network(), pdos, self.access.od(node))

    def stop_live(self, node: int) -> LiveCheck:
        self.access.info(node)  # NodeNotFoundError for an unknown node
        return self._live.stop(node)

    def live(self, node: int) -> LiveCheck:
        self.access.info(node)
        return self._live.status(node)

    # ------------------------------------------------------------------ keeping the cache true

    def forget(self, node: int | None = None) -> None:
        """Drop the cached PDOs of `node` (all nodes: None)."""
        if node is None:
            self._epoch += 1
            self._cache.clear()
        else:
            self._generation[node] = self._generation.get(node, 0) + 1
            self._cache.pop(node, None)

    def sdo_written(self, node: int, index: int, _subindex: int) -> None:
        """A raw SDO write (or one that may have landed) to a PDO parameter (1400h–1BFFh)."""
        if index in PDO_AREA:
            self.forget(node)

    def on_event(self, event: BusEvent) -> None:
        """A boot-up or NMT command may have reset a node's PDOs to their stored values."""
        if event.kind in (EventKind.BOOT_UP, EventKind.NMT):
            self.forget(event.node)
        elif event.kind is EventKind.BUS:
            self.forget()

    def on_bus(self, status: BusStatus) -> None:
        """Captures belong to one connection: stop them when it ends or is renewed."""
        if status.state is not BusState.CONNECTED:
            self._live.stop_all()
            self.forget()
            return
        try:
            current = self._network()
        except ServodeskError:
            current = None
        self._live.stop_all(keep=lambda network: network is current)

    def close(self) -> None:
        self._live.stop_all()


def rules_of(facts: NodePdoFacts) -> PdoRules:
    """How the node takes PDO changes (GET …/pdos/rules)."""
    return PdoRules(
        byte_granular=facts.byte_granular,
        fixed_cob_ids=facts.fixed_cob_ids,
        rtr_supported=facts.rtr_supported,
        rpdo_count=facts.rpdo_count,
        tpdo_count=facts.tpdo_count,
        procedure=facts.procedure_text,
        needs_pre_operational=facts.procedure is Procedure.OUTSIDE_OPERATIONAL,
    )


async def _read_all(runner: Runner, facts: NodePdoFacts) -> list[PdoConfig]:
    return [to_config(await read_raw(runner, facts.od, slot), facts.od) for slot in facts.slots]


def _rows(problems: Sequence[Problem]) -> list[PdoProblem]:
    return [PdoProblem.model_validate(p, from_attributes=True) for p in problems]


def _merged(current: Sequence[PdoConfig], given: Sequence[PdoConfig]) -> list[PdoConfig]:
    """`current` with the PDOs in `given` replacing those of the same kind and number."""
    replaced = {(pdo.kind, pdo.number): pdo for pdo in given}
    kept = [pdo for pdo in current if (pdo.kind, pdo.number) not in replaced]
    return kept + list(replaced.values())
