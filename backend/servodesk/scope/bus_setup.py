"""Setting the bus up for a capture series and putting it back: SYNC at the capture's period,
the scope's TPDOs written beside the node's own, the nodes put into Operational; each undo step
is tried even when another fails (a capture must never leave the bus changed)."""

from __future__ import annotations

import logging
from collections.abc import Awaitable

from servodesk.errors import ServodeskError
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NmtStateName
from servodesk.network.sync import SyncService
from servodesk.nodes.access import NodeAccess
from servodesk.pdo.service import PdoService
from servodesk.scope.planner import Setup

log = logging.getLogger(__name__)


class BusSetup:
    def __init__(self, access: NodeAccess, pdos: PdoService, sync: SyncService) -> None:
        self.access = access
        self.pdos = pdos
        self.sync = sync

    async def configure(self, setup: Setup) -> None:
        """SYNC at the capture's period, the scope's TPDOs written, the nodes Operational."""
        request = setup.request
        current = self.sync.get()
        if not current.producing or current.period_us != request.sync_period_us:
            setup.sync_before = current
            await self.sync.set(request.sync_period_us)
            if current.producing:
                setup.notes.append(
                    f"SYNC period changed from {current.period_us} µs to"
                    f" {request.sync_period_us} µs for the capture (restored afterwards)"
                )
        for node, plan in setup.plans.items():
            if plan.scope_pdos:
                await self.pdos.apply(node, list(plan.scope_pdos), actor="scope")
                setup.applied.append(node)
        if request.start_nodes:
            for node in setup.applied:  # TPDOs flow only in Operational
                state = self.access.info(node).nmt_state
                if state is NmtStateName.OPERATIONAL:
                    continue
                await self.access.nmt(node, NmtCommandName.START)
                if state is NmtStateName.UNKNOWN:
                    # it sends no heartbeat: put back nothing, its state before is not known
                    setup.notes.append(
                        f"node {node} (NMT state unknown: no heartbeat) started for the capture"
                        " and left Operational"
                    )
                    continue
                setup.started[node] = state
                setup.notes.append(f"node {node} put into Operational for the capture")

    async def undo(self, setup: Setup) -> None:
        """Put back what `configure` changed; each step is tried even when another fails."""
        for node, state in setup.started.items():
            back = (
                NmtCommandName.STOP
                if state is NmtStateName.STOPPED
                else NmtCommandName.PRE_OPERATIONAL
            )
            await self._attempt(f"node {node}: NMT back", self.access.nmt(node, back))
        for node in setup.applied:
            restore = list(setup.plans[node].restore_pdos)
            await self._attempt(
                f"node {node}: TPDOs back", self.pdos.apply(node, restore, actor="scope")
            )
        setup.applied.clear()
        setup.started.clear()
        before = setup.sync_before
        if before is not None:
            period = before.period_us if before.producing else None
            await self._attempt("SYNC back", self.sync.set(period))

    async def _attempt(self, what: str, step: Awaitable[object]) -> None:
        try:
            await step
        except ServodeskError as error:
            log.warning("scope: %s failed: %s", what, error)
