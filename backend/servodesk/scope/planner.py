"""Planning a capture (reads only): the signals resolved against each node's dictionary, the
TPDOs the scope needs planned beside the node's own, and the bus load of the whole bus during
the capture. `Setup` carries the plan and, once the bus is set up, what to undo."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from servodesk.errors import ServodeskError
from servodesk.models.network import SyncConfig
from servodesk.models.nodes import NmtStateName
from servodesk.models.pdo import BusLoadResult
from servodesk.models.scope import CaptureRequest, CaptureSignal, ScopePlan
from servodesk.motion.units import DriveUnits
from servodesk.nodes.access import NodeAccess
from servodesk.pdo.model import PdoConfig
from servodesk.pdo.procedure import Procedure
from servodesk.pdo.service import PdoService
from servodesk.scope.checks import check_request, overload, trigger_nodes
from servodesk.scope.plan import NodePlan, plan_node
from servodesk.scope.setup import Key, capture_signals, lookup, wanted
from servodesk.scope.signals import SignalInfo
from servodesk.scope.units import drive_units
from servodesk_protocol.cia402 import STATUSWORD

MAX_LOAD_PERCENT = 100.0


@dataclass
class Setup:
    """What a capture series changed on the bus, to be undone when it ends."""

    request: CaptureRequest
    signals: list[CaptureSignal]
    infos: dict[Key, SignalInfo]
    plans: dict[int, NodePlan]
    bus_load_percent: float
    notes: list[str]
    sync_before: SyncConfig | None = None  # None: the scope did not touch SYNC
    applied: list[int] = field(default_factory=list)  # nodes whose scope TPDOs are written
    started: dict[int, NmtStateName] = field(default_factory=dict)  # node -> state before
    series: int | None = None
    kept: list[int] = field(default_factory=list)  # captures of the series, oldest first


class ScopePlanner:
    def __init__(
        self, access: NodeAccess, pdos: PdoService, known_nodes: Callable[[], Sequence[int]]
    ) -> None:
        self.access = access
        self.pdos = pdos
        self.known_nodes = known_nodes

    async def plan(self, request: CaptureRequest) -> ScopePlan:
        setup = await self.prepare(request)
        problems = []
        if setup.bus_load_percent > MAX_LOAD_PERCENT:
            problems.append(overload(setup.bus_load_percent, request.sync_period_us))
        load = await self.bus_load(setup)
        return ScopePlan(
            ok=not problems,
            signals=setup.signals,
            bus_load=load,
            problems=problems,
            notes=setup.notes,
        )

    async def prepare(self, request: CaptureRequest) -> Setup:
        """Resolve the signals, plan their TPDOs and compute the bus load (reads only)."""
        check_request(request)
        nodes = sorted({s.node for s in request.signals} | trigger_nodes(request))
        has_statusword = {}
        for node in nodes:
            self.access.info(node)  # NodeNotFoundError for a node not on the bus
            has_statusword[node] = self.access.od(node).get(STATUSWORD, 0) is not None
        need = wanted(request, has_statusword)
        infos: dict[Key, SignalInfo] = {}
        for node in sorted({key[0] for key in need.keys}):
            units = await self._units(node)
            od = self.access.od(node)
            for key in need.keys:
                if key[0] == node:
                    infos[key] = lookup(key, od, units)
        plans: dict[int, NodePlan] = {}
        notes: list[str] = []
        for node in sorted({key[0] for key in need.keys}):
            facts = self.pdos.facts(node)
            current = await self.pdos.cached(node)  # kept true by every PDO change
            plan = plan_node(
                node,
                [infos[key] for key in need.keys if key[0] == node],
                current,
                byte_granular=facts.byte_granular,
                fixed_cob_ids=facts.fixed_cob_ids,
                taken_ids=await self.pdos.taken_ids(node),
                id_change_needs_reset=facts.procedure is Procedure.OUTSIDE_OPERATIONAL,
            )
            plans[node] = plan
            notes.extend(f"node {node}: {note}" for note in plan.notes)
        signals = capture_signals(need.keys, plans, need.added)
        setup = Setup(request, signals, infos, plans, 0.0, notes)
        setup.bus_load_percent = (await self.bus_load(setup)).percent
        return setup

    async def bus_load(self, setup: Setup) -> BusLoadResult:
        """The bus during the capture: every node's TPDOs (the scope's included) and SYNC at
        the capture's period. RPDOs are left out: ServoDesk sends none while capturing, and
        another master's traffic is not known here."""
        replace: dict[int, list[PdoConfig]] = {}
        for node in sorted(set(self.known_nodes()) | set(setup.plans)):
            try:
                current = await self.pdos.cached(node)
            except ServodeskError:
                continue  # a node that cannot be read now is not counted (said below)
            plan = setup.plans.get(node)
            taken = {pdo.number for pdo in plan.scope_pdos} if plan else set()
            kept = [p for p in current if p.kind == "tpdo" and p.number not in taken]
            replace[node] = kept + list(plan.scope_pdos if plan else ())
        load = await self.pdos.bus_load(
            MAX_LOAD_PERCENT, replace=replace, sync_period_us=setup.request.sync_period_us
        )
        load.notes.insert(
            0,
            "RPDOs are not counted: ServoDesk sends none during a capture (another master's"
            " would add to this)",
        )
        return load

    async def _units(self, node: int) -> DriveUnits:
        return await drive_units(self.access, node)
