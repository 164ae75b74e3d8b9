"""Uploading a dictionary: parsed in a worker process, so the server keeps answering; a bounded
number at a time and within a memory limit; the old dictionary is released when replaced."""

from __future__ import annotations

import gc
import threading
import weakref

import pytest
from fastapi.testclient import TestClient

from servodesk.errors import InvalidValueError
from servodesk.od.parser import OdParser
from servodesk_data import eds_path
from tests.large_eds import make_eds

LARGE = make_eds(3 * 1024 * 1024)


def test_the_server_answers_while_a_large_file_is_parsed(client: TestClient) -> None:
    done = threading.Event()
    answers_during: list[int] = []

    def upload() -> None:
        response = client.post("/api/nodes/1/od", files={"file": ("large.eds", LARGE)})
        assert response.status_code == 200, response.text
        done.set()

    uploader = threading.Thread(target=upload)
    uploader.start()
    while not done.is_set():
        status = client.get("/api/health").status_code
        if not done.is_set():
            answers_during.append(status)
    uploader.join()
    assert len(answers_during) >= 5  # the health route kept answering during the parse
    assert set(answers_during) == {200}
    info = client.get("/api/nodes/1").json()
    assert (info["od_source"], info["od_filename"]) == ("upload", "large.eds")
    tree = client.get("/api/nodes/1/od").json()
    assert any(obj["index_hex"] == "3000" for obj in tree["objects"])


def test_the_replaced_dictionary_is_released(client: TestClient) -> None:
    services = client.app.state.services  # type: ignore[attr-defined]
    with eds_path("mdi-s1c").open("rb") as file:
        client.post("/api/nodes/1/od", files={"file": ("mdi.eds", file)}).raise_for_status()
    uploaded = weakref.ref(services.registry.od(1))
    assert client.delete("/api/nodes/1/od").status_code == 200
    assert client.get("/api/nodes/1/sdo/1008/0").json()["text"] == "DVS_CANOPEN"
    gc.collect()
    assert uploaded() is None


@pytest.mark.anyio
async def test_a_file_beyond_the_memory_limit_fails_alone() -> None:
    parser = OdParser(memory_limit=64 * 1024 * 1024)  # address space of the worker, not RSS
    try:
        with pytest.raises(InvalidValueError, match=r"needs more memory"):
            await parser.parse(make_eds(8 * 1024 * 1024), "huge.eds")
    finally:
        parser.close()
    # the server's own parser still reads normal files
    fresh = OdParser()
    try:
        model = await fresh.parse(eds_path("kinco").read_bytes(), "kinco.eds")
        assert 0x6060 in model.objects
    finally:
        fresh.close()


@pytest.mark.anyio
async def test_parses_beyond_the_bound_wait_their_turn() -> None:
    import asyncio

    parser = OdParser(parallel=1)
    try:
        files = [eds_path(name).read_bytes() for name in ("mdi-s1c", "kinco", "cia402")]
        models = await asyncio.gather(
            *(parser.parse(data, f"{i}.eds") for i, data in enumerate(files))
        )
        assert [model.source for model in models] == ["0.eds", "1.eds", "2.eds"]
    finally:
        parser.close()


def test_bad_files_are_refused_in_words(client: TestClient) -> None:
    for name, data, says in [
        ("x.eds", b"hello", "not an EDS or DCF"),
        ("x.eds", b"\x00\x01\x02" * 100, "binary file"),
    ]:
        response = client.post("/api/nodes/1/od", files={"file": (name, data)})
        assert response.status_code == 422
        assert says in response.json()["message"]
    assert client.get("/api/nodes/1").json()["od_source"] == "profile"  # nothing changed
