"""Parse uploaded dictionaries off the event loop, a bounded number at a time, in a process of
their own.

Reading a large EDS is CPU work for seconds and takes several times the file's size in memory
(one record per INI key and line while parsing). On the server's event loop it would stop the
API, the WebSocket and the heartbeat monitor meanwhile; in a worker thread it would still hold
the interpreter lock most of the time, and leave the parse's peak in the server's heap. So each
parse runs in a short-lived worker process (one task, then it exits and its memory goes back to
the system) under a memory limit, and only the finished model comes back.
"""

from __future__ import annotations

import asyncio
import ctypes
import io
import mimetypes
import multiprocessing
import os
import pickle
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import replace
from typing import Any, TypeVar, cast

try:
    import resource  # POSIX: the worker's memory limit
except ImportError:  # Windows: parses run without one
    resource = None  # type: ignore[assignment]

from servodesk.errors import InvalidValueError
from servodesk.od.loader import load_od_bytes
from servodesk.od.model import ObjectDictionaryModel, OdImportError, OdObject

T = TypeVar("T")

OBJECTS_PER_CHUNK = 64  # ~5 ms of unpickling each
PARALLEL_PARSES = 2  # the machines this runs on have 2 cores; more uploads wait their turn
WORKER_MEMORY = 2 * 1024**3  # address space of one parse: a pathological file fails alone


WORKER_NICENESS = 10  # bulk work yields the CPU to the server that stops the drives


def lower_priority(niceness: int = WORKER_NICENESS) -> None:
    """Worker start-up: run below the server (on a busy host a stop must not wait for a core).
    POSIX only (os.nice); on Windows the worker keeps the server's priority."""
    if hasattr(os, "nice"):
        os.nice(niceness)


def worker_context(preload: list[str]) -> multiprocessing.context.BaseContext:
    """forkserver: workers fork from a small clean process, not from this threaded one; it
    imports `preload` first (ignored if it already runs), which keeps the workers small.
    Windows has no fork: there they are spawned (a fresh interpreter per worker)."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(preload)
    return context


def _limit_memory(limit: int) -> None:
    """Worker start-up: a file that would need more than `limit` fails with MemoryError
    instead of taking the machine's memory from the drives' server (POSIX: RLIMIT_AS; on
    Windows there is no such limit); and it runs at a lower priority than the server."""
    lower_priority()
    if resource is None:
        return
    _, hard = resource.getrlimit(resource.RLIMIT_AS)
    soft = limit if hard == resource.RLIM_INFINITY else min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def _shared(model: ObjectDictionaryModel) -> ObjectDictionaryModel:
    """The model with equal values as one object each (pickle then sends each once): a vendor
    file repeats types, limits, units and defaults thousands of times, and every object less
    in the server's heap is memory it gets back when the dictionary goes."""
    seen: dict[object, Any] = {}

    def one(value: T) -> T:
        if value is None or isinstance(value, bool):
            return value
        key = (type(value), value)
        return cast(T, seen.setdefault(key, value))

    fields = ("name", "default", "default_raw", "low", "high", "unit", "value", "description")
    objects = {}
    for index, obj in model.objects.items():
        subs = {
            subindex: replace(sub, **{name: one(getattr(sub, name)) for name in fields})
            for subindex, sub in obj.subs.items()
        }
        objects[index] = replace(obj, name=one(obj.name), subs=subs)
    return replace(model, objects=objects)


def _parse(data: bytes, filename: str, node_id: int | None) -> tuple[bytes, int]:
    """Worker side: the model pickled as a head (no objects) and `n` chunks of objects into
    one stream (one pickler: a value shared by many entries is sent once)."""
    try:
        model: ObjectDictionaryModel | None = _shared(
            load_od_bytes(data, filename, node_id=node_id)
        )
    except MemoryError:
        model = None
    if model is None:  # raised out here: the MemoryError's frames (the half-read file) are gone
        raise OdImportError(f"{filename} needs more memory to read than one dictionary may take")
    stream = io.BytesIO()
    pickler = pickle.Pickler(stream, protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dump(replace(model, objects={}))
    items = list(model.objects.items())
    chunks = range(0, len(items), OBJECTS_PER_CHUNK)
    for start in chunks:
        pickler.dump(items[start : start + OBJECTS_PER_CHUNK])
    return stream.getvalue(), len(chunks)


def _assemble(blob: bytes, chunks: int) -> ObjectDictionaryModel:
    """Server side, in a worker thread: unpickling runs in C and holds the interpreter lock
    for its whole length (a large model: ~0.4 s in one piece, a stalled event loop). Chunk
    by chunk, the lock is given back in between."""
    unpickler = pickle.Unpickler(io.BytesIO(blob))
    head: ObjectDictionaryModel = unpickler.load()
    objects: dict[int, OdObject] = {}
    for _ in range(chunks):
        objects.update(unpickler.load())
        time.sleep(0)  # let the event loop run
    return replace(head, objects=objects)


class OdParser:
    """One per app (Services): `await parse(...)` reads a file without blocking the loop."""

    def __init__(
        self, *, parallel: int = PARALLEL_PARSES, memory_limit: int = WORKER_MEMORY
    ) -> None:
        self._parallel = parallel
        self._memory_limit = memory_limit
        self._slots = asyncio.Semaphore(parallel)
        self._pool: ProcessPoolExecutor | None = None
        self._running = 0
        _keep_large_blocks_apart()
        # Filled lazily on the first multipart upload otherwise: long-lived tables allocated in
        # the middle of a large parse's objects would pin that memory after the parse.
        mimetypes.init()

    def _executor(self) -> ProcessPoolExecutor:
        if self._pool is None:
            context = worker_context(["servodesk.od.parse_worker", "servodesk.od.parser"])
            self._pool = ProcessPoolExecutor(
                max_workers=self._parallel,
                mp_context=context,
                initializer=_limit_memory,
                initargs=(self._memory_limit,),
                max_tasks_per_child=1,
            )
        return self._pool

    async def parse(
        self, data: bytes, filename: str, *, node_id: int | None = None
    ) -> ObjectDictionaryModel:
        """The model of an EDS/DCF/XDD; InvalidValueError names what is wrong with the file."""
        async with self._slots:
            self._running += 1
            try:
                # submitted from a thread: the pool starts its worker process in submit() (a
                # round trip to the fork server, which itself starts on first use: up to a
                # second), and that must not happen on the event loop
                pool = self._executor()
                future = await asyncio.to_thread(pool.submit, _parse, data, filename, node_id)
                blob, chunks = await asyncio.wrap_future(future)
                return await asyncio.to_thread(_assemble, blob, chunks)
            except OdImportError as error:
                raise InvalidValueError(str(error)) from None
            except BrokenProcessPool:
                self._pool = None  # a new pool for the next file
                raise InvalidValueError(
                    f"{filename}: the reader stopped (out of memory?); nothing was changed"
                ) from None
            finally:
                self._running -= 1
                if self._running == 0:
                    # idle: let the pool go with its feeder thread, which keeps the last file
                    # it sent (megabytes) until the next one; a new pool starts in milliseconds
                    self.close()

    def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            shut_down_aside(pool, "od-parser-shutdown")


def _libc() -> ctypes.CDLL | None:
    try:
        return ctypes.CDLL("libc.so.6")
    except OSError:
        return None  # not glibc: nothing to tune


M_MMAP_THRESHOLD = -3  # mallopt parameter (malloc.h)


def _keep_large_blocks_apart() -> None:
    """glibc raises its mmap threshold each time a large block is freed (up to 32 MB), after
    which uploaded files and pickled models land in the main heap, where one small block
    allocated after them keeps the whole region. A fixed threshold keeps blocks of 1 MB and
    more in their own mappings, returned to the system when freed."""
    libc = _libc()
    if libc is not None:
        libc.mallopt(M_MMAP_THRESHOLD, 1024 * 1024)


def release_memory() -> None:
    """After a dictionary was dropped: hand the freed heap back to the system. CPython frees
    the objects at once (they hold no reference cycles), but glibc keeps emptied heap pages
    mapped; trimming makes the server's resident memory follow what it really holds."""
    libc = _libc()
    if libc is not None:
        libc.malloc_trim(0)


def shut_down_aside(pool: ProcessPoolExecutor, name: str) -> None:
    """End a worker pool without blocking the caller. shutdown(wait=False) races the pool's
    own thread replacing a finished worker (CPython drops the process table under it); waiting
    is safe, so it waits on a thread of its own."""
    threading.Thread(
        target=pool.shutdown,
        kwargs={"wait": True, "cancel_futures": True},
        name=name,
        daemon=True,
    ).start()
