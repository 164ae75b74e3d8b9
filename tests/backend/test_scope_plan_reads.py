"""The Scope page checks its plan on every form change: with the simulated drives, a second
check reads no PDO configuration on the bus, and a write to a PDO parameter in between (from
any path) makes the next check read the node's PDOs again. Counted on the bus: the drives'
answers to SDO uploads of 1400h–1BFFh."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import can
import httpx
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.pdo.write_watch import written_object
from servodesk.services import Services
from servodesk.settings import Settings

POSITION, VELOCITY = 0x6064, 0x606C
PDO_AREA = range(0x1400, 0x1C00)


class PdoReads(can.Listener):
    """Per node, the drives' answers to uploads of a PDO parameter (notifier thread)."""

    def __init__(self) -> None:
        self.by_node: Counter[int] = Counter()

    def on_message_received(self, msg: can.Message) -> None:
        data = bytes(msg.data)
        upload = 0x580 < msg.arbitration_id <= 0x5FF and len(data) >= 4 and data[0] >> 5 == 2
        if upload and int.from_bytes(data[1:3], "little") in PDO_AREA:
            self.by_node[msg.arbitration_id - 0x580] += 1


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, scope_live_view=False)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: httpx.Response) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def plan(client: TestClient, reads: PdoReads, signals: list[int], period_us: int) -> Counter[int]:
    """The PDO reads one plan check made, per node."""
    before = reads.by_node.copy()
    request = {
        "signals": [{"node": 1, "index": index} for index in signals],
        "sync_period_us": period_us,
        "duration_s": 1.0,
    }
    assert ok(client.post("/api/scope/plan", json=request))["ok"]
    return reads.by_node - before


def test_a_changed_plan_reads_no_pdos_until_a_pdo_parameter_is_written(
    client: TestClient,
) -> None:
    services: Services = client.app.state.services  # type: ignore[attr-defined]
    reads = PdoReads()
    remove = services.bus.add_frame_listener(reads)
    try:
        plan(client, reads, [POSITION], 1000)  # the first check may read what is not known
        assert plan(client, reads, [POSITION, VELOCITY], 2000) == Counter()
        assert plan(client, reads, [VELOCITY], 1000) == Counter()

        # a raw SDO write to a free TPDO's transmission type (its own value back: the MDi
        # takes changes only while a PDO is invalid) makes node 1's PDOs stale: the next check
        # reads them again, and only node 1's
        free = next(
            p for p in ok(client.get("/api/nodes/1/pdos")) if p["kind"] == "tpdo" and not p["valid"]
        )
        path = f"/api/nodes/1/sdo/{0x1800 + free['number'] - 1:04X}/2"
        value = ok(client.get(path))["value"]
        ok(client.put(path, json={"value": value}))
        again = plan(client, reads, [POSITION, VELOCITY], 1000)
        assert again[1] > 0
        assert set(again) == {1}
        assert plan(client, reads, [POSITION], 1500) == Counter()
    finally:
        remove()


@pytest.mark.parametrize(
    ("can_id", "data", "found"),
    [
        (0x601, "2F00180501000000", (1, 0x1800, 5)),  # expedited download, 1 byte
        (0x605, "2100160000000000", (5, 0x1600, 0)),  # segmented download's initiate
        (0x67F, "C2001A0104000000", (127, 0x1A00, 1)),  # block download's initiate
        (0x601, "4000180100000000", None),  # an upload: a read changes nothing
        (0x601, "0012345678000000", None),  # a download segment: no index in it
        (0x581, "6000180500000000", None),  # the drive's answer
        (0x701, "05", None),  # a heartbeat
    ],
)
def test_writes_are_recognised_from_the_request_frame(
    can_id: int, data: str, found: tuple[int, int, int] | None
) -> None:
    assert written_object(can_id, bytes.fromhex(data)) == found
