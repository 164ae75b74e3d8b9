"""What the commissioning routes call: make a record, list and read records, sign a step off,
run a step's automated part. A step runs outside the record's lock (store_verify takes
seconds), then the result is written into the record as it is by then."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from functools import partial
from typing import Any

from servodesk.access.actor import current_actor
from servodesk.audit import AuditLog
from servodesk.commissioning import evidence as ev
from servodesk.commissioning import moving, pdo_step, store_verify
from servodesk.commissioning.axis_run import AxisRun
from servodesk.commissioning.plan import (
    AUTOMATED,
    DONE_ON_PAGE,
    check_modes,
    plan_steps,
    record_status,
)
from servodesk.commissioning.store import RecordStore
from servodesk.errors import InvalidValueError, NotFoundError, StateConflictError
from servodesk.models.commissioning import (
    STEP_KEYS,
    CommissioningCreate,
    CommissioningIdentity,
    CommissioningRecord,
    CommissioningStep,
    StepRun,
    StepSignOff,
    StepStatus,
)
from servodesk.motion.safety import MotionSafety
from servodesk.nodes.registry import NodeRegistry
from servodesk.params.service import ParamService
from servodesk.pdo.service import PdoService
from servodesk.scope.service import ScopeService
from servodesk.sdo.service import SdoService
from servodesk.settings import Settings


class RecordNotFoundError(NotFoundError):
    def __init__(self, record_id: int) -> None:
        super().__init__(
            "commissioning_not_found",
            f"no commissioning record {record_id}: list them with GET /api/commissioning",
        )


class StepNotFoundError(NotFoundError):
    def __init__(self, key: str) -> None:
        super().__init__(
            "step_not_found", f"no commissioning step {key!r}: the steps are {', '.join(STEP_KEYS)}"
        )


class StepNotAutomatedError(StateConflictError):
    def __init__(self, key: str) -> None:
        page = DONE_ON_PAGE.get(key, "its")
        super().__init__(
            "step_not_automated",
            f"step {key} has no automated part here: do it on the {page} page, then sign it off "
            f"with PUT /api/commissioning/{{id}}/steps/{key}",
        )


class CommissioningService:
    def __init__(
        self,
        registry: NodeRegistry,
        sdo: SdoService,
        params: ParamService,
        audit: AuditLog,
        settings: Settings,
        *,
        bitrate: Callable[[], int | None],
        simulated: Callable[[], bool],
        safety: MotionSafety | None = None,
        scope: ScopeService | None = None,
        pdos: PdoService | None = None,
    ) -> None:
        self._registry = registry
        self._sdo = sdo
        self._params = params
        self._audit = audit
        self._settings = settings
        self._bitrate = bitrate
        self._simulated = simulated
        self._pdos = pdos
        self.store = RecordStore(settings.data_dir)
        self._locks: dict[int, asyncio.Lock] = {}
        # the steps that move the axis use the motion safety layer and the scope
        self._moving = (
            None
            if safety is None or scope is None
            else partial(AxisRun, safety, scope, registry, sdo, audit, settings)
        )

    def close(self) -> None:
        self.store.close()

    async def create(self, node: int, body: CommissioningCreate) -> CommissioningRecord:
        picked = check_modes(body.modes)
        info = self._registry.info(node)  # NodeNotFoundError for a node never scanned
        supported = await ev.drive_modes(self._registry, self._sdo, node)
        now = time.time()
        steps = plan_steps(supported, picked)
        for step in steps:
            if step.status == "skipped":
                step.at = now
        identity = CommissioningIdentity.model_validate(
            info.model_dump()
            | {"supported_modes": None if supported is None else sorted(supported)}
        )
        title = body.title or f"Node {node} · {info.profile_label}"
        record = CommissioningRecord(
            id=0,
            node=node,
            title=title,
            created=now,
            identity=identity,
            modes=picked,
            steps=steps,
            status=record_status(steps),
        )
        return await self.store.add(record)

    async def list(self, node: int | None = None) -> list[CommissioningRecord]:
        return await self.store.list(node)

    async def get(self, record_id: int) -> CommissioningRecord:
        record = await self.store.get(record_id)
        if record is None:
            raise RecordNotFoundError(record_id)
        return record

    async def sign_off(self, record_id: int, key: str, body: StepSignOff) -> CommissioningStep:
        reason = (body.reason or "").strip() or None
        if body.status == "skipped" and reason is None:
            raise InvalidValueError(f"skipping step {key} needs a reason: say why in `reason`")
        self._check_key(key)
        return await self._update(
            record_id, key, lambda step: self._signed(step, body.status, reason)
        )

    async def run(self, record_id: int, key: str, body: StepRun | None = None) -> CommissioningStep:
        self._check_key(key)
        if (
            key not in AUTOMATED
            or (key in moving.MOVING and self._moving is None)
            or (key == "pdo" and self._pdos is None)
        ):
            raise StepNotAutomatedError(key)
        moving.check_body(key, body)
        record = await self.get(record_id)
        figures: dict[str, float] = {}
        try:
            if key in moving.MOVING and self._moving is not None:
                (status, evidence, reason), figures = await moving.run(
                    self._moving, key, record, body
                )
            elif key == "pdo" and self._pdos is not None:
                apply = body is not None and bool(body.apply)
                status, evidence, reason = await pdo_step.run(
                    self._pdos, self._audit, record, apply=apply, started=time.time()
                )
            else:
                status, evidence, reason = await self._run(key, record)
        except store_verify.BootTimeoutError as error:
            # the record keeps what happened; the caller gets the timeout (504)
            message = str(error)
            failed: dict[str, Any] = {"error": "timeout", "message": message}
            await self._update(
                record_id, key, lambda step: self._ran(step, "failed", failed, message)
            )
            raise
        return await self._update(
            record_id, key, lambda step: self._ran(step, status, evidence, reason, figures)
        )

    async def _run(self, key: str, record: CommissioningRecord) -> ev.Outcome:
        registry, sdo = self._registry, self._sdo
        if key == "identity":
            return await ev.identity(registry, sdo, record)
        if key == "communication":
            return await ev.communication(
                registry, sdo, record, bitrate=self._bitrate(),
                tool_node_id=self._settings.tool_node_id,
            )  # fmt: skip
        if key == "parameters":
            return await ev.parameters(registry, self._audit, record, simulated=self._simulated())
        if key == "limits":
            return await ev.limits(registry, sdo, record)
        return await store_verify.run(
            registry, sdo, self._params, self._audit, record,
            boot_wait=self._settings.boot_wait, tool_node_id=self._settings.tool_node_id,
            simulated=self._simulated(),
        )  # fmt: skip

    @staticmethod
    def _check_key(key: str) -> None:
        if key not in STEP_KEYS:
            raise StepNotFoundError(key)

    @staticmethod
    def _signed(step: CommissioningStep, status: str, reason: str | None) -> None:
        step.status = "done" if status == "done" else "skipped"
        step.reason = reason
        step.by = current_actor().user
        step.at = time.time()

    @staticmethod
    def _ran(
        step: CommissioningStep,
        status: StepStatus,
        evidence: dict[str, Any],
        reason: str | None,
        figures: dict[str, float] | None = None,
    ) -> None:
        step.status, step.evidence, step.reason = status, evidence, reason
        step.figures = figures or {}
        step.by = current_actor().user
        step.at = time.time()

    async def _update(
        self, record_id: int, key: str, change: Callable[[CommissioningStep], None]
    ) -> CommissioningStep:
        """Change one step of the record as stored now, under the record's lock."""
        lock = self._locks.setdefault(record_id, asyncio.Lock())
        async with lock:
            record = await self.get(record_id)
            step = next(s for s in record.steps if s.key == key)
            change(step)
            record.status = record_status(record.steps)
            await self.store.save(record)
            return step
