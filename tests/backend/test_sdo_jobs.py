""" "Upload all" jobs against the simulated drives: completion, cancel, a node that goes silent;
and the chunk reader's per-entry outcomes."""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Iterator

import pytest
from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

from servodesk.errors import NodeNotFoundError
from servodesk.models.sdo import Job
from servodesk.od import DataType, OdSub
from servodesk.sdo.bulk import ChunkCursor, EntryRead, as_entry_read, read_chunk
from servodesk.sdo.jobs import JobManager, JobNotFoundError, readable_entries
from servodesk_sim.frames import Frame
from tests.backend.sim_nodes import SimNodes

pytestmark = pytest.mark.anyio

SDO_RX = 0x600  # SDO request COB-ID base
INITIATE_UPLOAD = 0x40  # SDO command: one per entry read (segments follow for long ones)


@pytest.fixture
def nodes() -> Iterator[SimNodes]:
    with SimNodes(sdo_timeout=0.05) as access:
        yield access


class RequestCounter:
    """Counts the entries the drive was asked for (initiate-upload requests)."""

    def __init__(self, nodes: SimNodes, node: int) -> None:
        self.node = node
        self.count = 0
        self.remove = nodes.sim.add_tap(self._on_frame)

    def _on_frame(self, frame: Frame, origin: object | None) -> None:
        if frame.can_id == SDO_RX + self.node and frame.data[:1] == bytes([INITIATE_UPLOAD]):
            self.count += 1

    async def reach(self, count: int, timeout: float = 5.0) -> None:
        deadline = time.monotonic() + timeout
        while self.count < count:
            if time.monotonic() > deadline:
                raise TimeoutError(f"only {self.count} SDO requests seen")
            await asyncio.sleep(0.001)


async def finished(jobs: JobManager, job_id: str, timeout: float = 10.0) -> Job:
    deadline = time.monotonic() + timeout
    while (job := jobs.get(job_id)).state == "running":
        if time.monotonic() > deadline:
            raise TimeoutError(f"job still running: {job.done}/{job.total}")
        await asyncio.sleep(0.01)
    return job


async def test_upload_all_reads_every_readable_entry(nodes: SimNodes) -> None:
    jobs = JobManager(nodes)
    started = jobs.start_upload_all(3)
    assert started.state == "running"
    assert started.kind == "upload-all"
    job = await finished(jobs, started.id)
    expected = [(s.index, s.subindex) for s in readable_entries(nodes.od(3))]
    assert job.state == "done"
    assert job.total == len(expected) == job.done
    assert [(r.index, r.subindex) for r in job.results] == expected
    assert all(r.abort_code is None and r.text is not None for r in job.results)
    by_key = {(r.index, r.subindex): r for r in job.results}
    assert by_key[(0x1000, 0)].value == 0x00020192  # Device type: CiA 402 drive
    assert by_key[(0x1000, 0)].text == "0x00020192 (131474)"
    assert by_key[(0x1018, 1)].name == "Identity object: Vendor-ID"


async def test_cancel_stops_the_job_between_entries(nodes: SimNodes) -> None:
    requests = RequestCounter(nodes, 3)
    jobs = JobManager(nodes)
    job_id = jobs.start_upload_all(3).id
    await requests.reach(20)
    cancelled = await jobs.cancel(job_id)
    seen_at_cancel = requests.count
    assert cancelled.state == "cancelled"
    assert 20 <= cancelled.done < cancelled.total
    # every request the drive answered is in the results, and no request follows the cancel
    assert cancelled.done == seen_at_cancel
    await asyncio.sleep(0.05)
    requests.remove()
    assert requests.count == seen_at_cancel
    assert jobs.get(job_id).done == cancelled.done


async def test_node_that_stops_answering_fails_the_job(nodes: SimNodes) -> None:
    requests = RequestCounter(nodes, 3)
    jobs = JobManager(nodes)
    job_id = jobs.start_upload_all(3).id
    await requests.reach(20)
    requests.remove()
    nodes.sim.stop()  # the drives go quiet mid-job
    job = await finished(jobs, job_id)
    assert job.state == "failed"
    assert job.error == "node stopped answering"
    assert job.done < job.total
    assert [r.message for r in job.results[-3:]] == ["no answer in time"] * 3
    assert all(r.value is None and r.abort_code is None for r in job.results[-3:])


async def test_unknown_job_and_unknown_node(nodes: SimNodes) -> None:
    jobs = JobManager(nodes)
    with pytest.raises(JobNotFoundError):
        jobs.get("no-such-job")
    with pytest.raises(JobNotFoundError):
        await jobs.cancel("no-such-job")
    with pytest.raises(NodeNotFoundError):
        jobs.start_upload_all(99)


# ------------------------------------------------------------------- the chunk reader itself


class _Sdo:
    """Stands in for canopen's SDO client: answers from a table, or raises what canopen does."""

    def __init__(self, answers: dict[int, bytes | Exception]) -> None:
        self.answers = answers
        self.asked: list[int] = []

    def upload(self, index: int, subindex: int) -> bytes:
        self.asked.append(index)
        answer = self.answers[index]
        if isinstance(answer, Exception):
            raise answer
        return answer


class _Remote:
    def __init__(self, answers: dict[int, bytes | Exception]) -> None:
        self.sdo = _Sdo(answers)


def _subs(*indices: int) -> list[OdSub]:
    return [OdSub(i, 0, f"obj {i:04X}", DataType.UNSIGNED8, "ro", False) for i in indices]


def _timeout() -> SdoCommunicationError:
    return SdoCommunicationError("No SDO response received")


def test_one_timeout_is_recorded_and_reading_goes_on() -> None:
    remote = _Remote(
        {0x2000: b"\x01", 0x2001: _timeout(), 0x2002: SdoAbortedError(0x06010001), 0x2003: b"\x04"}
    )
    cursor = ChunkCursor()
    subs = _subs(0x2000, 0x2001, 0x2002, 0x2003)
    reads: list[EntryRead] = read_chunk(remote, subs, cursor, as_entry_read, threading.Event())
    assert [(r.data, r.abort_code, r.timed_out) for r in reads] == [
        (b"\x01", None, False),
        (None, None, True),
        (None, 0x06010001, False),
        (b"\x04", None, False),
    ]
    assert cursor.position == 4
    assert cursor.timeouts_in_a_row == 0


def test_three_timeouts_in_a_row_stop_the_chunk() -> None:
    remote = _Remote({i: _timeout() for i in range(0x2000, 0x2005)})
    cursor = ChunkCursor()
    reads = read_chunk(
        remote, _subs(*range(0x2000, 0x2005)), cursor, as_entry_read, threading.Event()
    )
    assert len(reads) == 3
    assert remote.sdo.asked == [0x2000, 0x2001, 0x2002]
    assert cursor.timeouts_in_a_row == 3


def test_stop_event_and_time_budget_end_a_chunk() -> None:
    remote = _Remote({i: b"\x00" for i in range(0x2000, 0x2004)})
    subs = _subs(*range(0x2000, 0x2004))
    stopped = threading.Event()
    stopped.set()
    assert read_chunk(remote, subs, ChunkCursor(), as_entry_read, stopped) == []
    ticks = iter([0.0, 0.01, 0.06, 0.07])  # the budget of 0.05 s is spent after two entries
    cursor = ChunkCursor()
    reads = read_chunk(
        remote,
        subs,
        cursor,
        as_entry_read,
        threading.Event(),
        budget=0.05,
        clock=lambda: next(ticks),
    )
    assert len(reads) == 2
    assert cursor.position == 2


async def test_job_fails_when_the_node_session_closes(nodes: SimNodes) -> None:
    requests = RequestCounter(nodes, 3)
    jobs = JobManager(nodes, chunk_budget=0.005)  # several chunks: the close lands between two
    job_id = jobs.start_upload_all(3).id
    await requests.reach(20)
    requests.remove()
    nodes.session(3).close()  # as when the registry drops or moves the node
    job = await finished(jobs, job_id)
    assert job.state == "failed"
    assert job.error is not None
    assert "closed" in job.error
