"""Background "upload all" jobs: read every readable entry of a node, with progress and cancel.

Jobs live in memory, keyed by a uuid, and run as one asyncio task each. The reading is done
chunk-wise on the node's worker thread (sdo.bulk) and keeps only the raw answers; decoding and
formatting wait until a client asks for the job. So a job runs at the rate of a bare loop of SDO
uploads, and the node stays usable by other requests between chunks.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import time
import uuid
from dataclasses import dataclass, field
from typing import Literal

from servodesk.errors import RequestInterruptedError, ServodeskError
from servodesk.models.sdo import Job, JobResult
from servodesk.nodes.access import NodeAccess
from servodesk.nodes.session import NodeSession
from servodesk.od import ObjectDictionaryModel, OdSub
from servodesk.sdo import codec
from servodesk.sdo.bulk import CHUNK_SECONDS, BulkOutcome, EntryRead, as_entry_read, read_entries
from servodesk.sdo_aborts import abort_meaning

log = logging.getLogger(__name__)

JobState = Literal["running", "done", "cancelled", "failed"]

KEEP_FINISHED = 20  # finished jobs kept for their results; older ones are forgotten
NO_ANSWER = "no answer in time"
STALLED = "node stopped answering"
CLOSED = "the connection to the node was closed (node moved, removed or bus disconnected)"
OD_CHANGED = "cancelled: the node's dictionary changed"


class JobNotFoundError(ServodeskError):
    """No job with this id (never started, or finished long ago and forgotten)."""

    def __init__(self, job_id: str) -> None:
        self.job_id = job_id
        super().__init__(f"no job {job_id}")


@dataclass
class _JobRecord:
    id: str
    node: int
    total: int
    model: ObjectDictionaryModel
    state: JobState = "running"
    error: str | None = None
    # What the drive answered, appended by the job's task a chunk at a time. Turned into API
    # results only when someone looks (`snapshot`), so the read loop does no per-entry work.
    reads: list[EntryRead] = field(default_factory=list)
    results: list[JobResult] = field(default_factory=list)
    stop: threading.Event = field(default_factory=threading.Event)
    stop_reason: str | None = None  # why it was stopped when not by the user
    task: asyncio.Task[None] | None = None
    started: float = field(default_factory=time.monotonic)
    finished: float | None = None

    def snapshot(self, since: int = 0) -> Job:
        """The job as the API shows it, with the results from position `since` on (a poller
        asks only for what it has not seen). Converts the reads that arrived since the last
        look."""
        for read in self.reads[len(self.results) :]:
            self.results.append(job_result(self.model, read))
        since = max(0, min(since, len(self.results)))
        end = self.finished if self.finished is not None else time.monotonic()
        return Job.model_construct(
            id=self.id,
            kind="upload-all",
            node=self.node,
            state=self.state,
            done=len(self.results),
            total=self.total,
            error=self.error,
            elapsed_s=round(end - self.started, 6),
            results_from=since,
            results=self.results[since:],
        )


def job_result(model: ObjectDictionaryModel, read: EntryRead) -> JobResult:
    sub = read.sub
    name = codec.entry_name(model, sub)
    if read.data is not None:
        value = codec.decode(sub, read.data)
        return JobResult(
            index=sub.index,
            subindex=sub.subindex,
            name=name,
            value=codec.api_value(value),
            text=codec.display_text(sub, value, size=len(read.data)),
        )
    code = read.abort_code
    return JobResult(
        index=sub.index,
        subindex=sub.subindex,
        name=name,
        abort_code=None if code is None else f"0x{code:08X}",
        message=NO_ANSWER if code is None else abort_meaning(code),
    )


def readable_entries(model: ObjectDictionaryModel) -> list[OdSub]:
    """Every entry that can be read, in index and sub-index order."""
    return [
        sub
        for index in sorted(model.objects)
        for _, sub in sorted(model.objects[index].subs.items())
        if sub.access != "wo"
    ]


class JobManager:
    def __init__(
        self,
        access: NodeAccess,
        *,
        keep_finished: int = KEEP_FINISHED,
        chunk_budget: float = CHUNK_SECONDS,
    ) -> None:
        self._access = access
        self._keep = keep_finished
        self._budget = chunk_budget
        self._jobs: dict[str, _JobRecord] = {}

    def start_upload_all(self, node: int) -> Job:
        """Start reading every readable entry of `node` (call from the event loop).

        NodeNotFoundError at once if the node is not known.
        """
        session = self._access.session(node)
        model = self._access.od(node)
        subs = readable_entries(model)
        record = _JobRecord(id=str(uuid.uuid4()), node=node, total=len(subs), model=model)
        record.task = asyncio.get_running_loop().create_task(
            self._run(record, session, subs), name=f"upload-all node {node}"
        )
        self._jobs[record.id] = record
        self._forget_old()
        return record.snapshot()

    def dictionary_changed(self, node: int) -> None:
        """The node's dictionary was replaced: its running jobs read entries of the old one."""
        for record in self._jobs.values():
            if record.node == node and record.state == "running" and not record.stop.is_set():
                record.stop_reason = OD_CHANGED
                record.stop.set()

    def get(self, job_id: str, since: int = 0) -> Job:
        return self._record(job_id).snapshot(since)

    async def cancel(self, job_id: str) -> Job:
        """Stop the job after the entry in progress and return it in its final state."""
        record = self._record(job_id)
        record.stop.set()
        if record.task is not None and not record.task.done():
            # wait() rather than awaiting the task: a caller giving up must not cancel the job
            await asyncio.wait({record.task})
        return record.snapshot()

    async def close(self) -> None:
        """Stop every running job (application shutdown)."""
        tasks = [r.task for r in self._jobs.values() if r.task is not None and not r.task.done()]
        for record in self._jobs.values():
            record.stop.set()
        if tasks:
            await asyncio.wait(tasks)

    def _record(self, job_id: str) -> _JobRecord:
        record = self._jobs.get(job_id)
        if record is None:
            raise JobNotFoundError(job_id)
        return record

    def _forget_old(self) -> None:
        finished = [r.id for r in self._jobs.values() if r.state != "running"]
        for job_id in finished[: max(0, len(finished) - self._keep)]:
            del self._jobs[job_id]

    async def _run(self, record: _JobRecord, session: NodeSession, subs: list[OdSub]) -> None:
        try:
            await self._read(record, session, subs)
        finally:
            record.finished = time.monotonic()

    async def _read(self, record: _JobRecord, session: NodeSession, subs: list[OdSub]) -> None:
        try:
            outcome = await read_entries(
                session, subs, as_entry_read, record.reads, stop=record.stop, budget=self._budget
            )
        except asyncio.CancelledError:
            task = asyncio.current_task()
            if task is not None and task.cancelling():
                record.state = "cancelled"
                raise
            # not this task's cancel: the node's session was closed under the job
            record.state = "failed"
            record.error = CLOSED
            return
        except RequestInterruptedError:
            record.state = "failed"
            record.error = CLOSED
            return
        except Exception as error:
            # a background job has no caller to raise to: the job carries the failure
            log.exception("upload-all of node %d failed", record.node)
            record.state = "failed"
            record.error = str(error) or type(error).__name__
            return
        if outcome is BulkOutcome.STALLED:
            record.state = "failed"
            record.error = STALLED
        elif outcome is BulkOutcome.CANCELLED:
            record.state = "cancelled"
            record.error = record.stop_reason
        else:
            record.state = "done"
